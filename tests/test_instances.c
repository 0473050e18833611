/* test_instances.c: instances (DESIGN section 3.4): mesh lines that repeat a model share one copy
 * of its faces. Identity instances render the very bits of flattened copies (the same model under
 * another file name, which loads as faces); 1,000 instances of a 100,000-face model hold about
 * one model's memory; 1,000 moved, turned and scaled instances render the image of their copies
 * flattened in double within the bound of rays moved into each instance's space; the reference
 * and packet builds agree bit for bit; a singular transform is an error at its line. With the
 * argument `vulkan`: every Vulkan walk the device has renders the CPU back end's bits (exit 77
 * only without a Vulkan device). Cut-outs work inside instances, and the parts' digest covers
 * the placements. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh_test.h"
#include "png_test.h"
#include "render/part.h"
#include "render/scene_pack.h"
#include "render/vk/vk_context.h"
#include "tmp_dir.h"

/* A bumpy UV sphere of 2 segments (rings - 1) faces as the OBJ tmpdir/name. */
static void write_model(const char *name, int rings, int segments) {
    const double pi = 3.14159265358979323846;
    size_t size = (size_t)rings * segments * 120 + 4096, n = 0;
    char *obj = malloc(size);
    n += (size_t)snprintf(obj + n, size - n, "v 0 1 0\nv 0 -1 0\n");
    for (int r = 1; r < rings; r++) {
        for (int s = 0; s < segments; s++) {
            double t = pi * r / rings, p = 2 * pi * s / segments, bump = 1.0 + 0.2 * sin(5 * p);
            n += (size_t)snprintf(obj + n, size - n, "v %.7f %.7f %.7f\n", sin(t) * cos(p) * bump,
                                  cos(t), sin(t) * sin(p) * bump);
        }
    }
#define RING(r, s) (3 + ((r)-1) * segments + ((s) % segments))
    for (int s = 0; s < segments; s++) {
        n += (size_t)snprintf(obj + n, size - n, "f 1 %d %d\nf 2 %d %d\n", RING(1, s + 1),
                              RING(1, s), RING(rings - 1, s), RING(rings - 1, s + 1));
        for (int r = 1; r < rings - 1; r++)
            n += (size_t)snprintf(obj + n, size - n, "f %d %d %d %d\n", RING(r, s), RING(r, s + 1),
                                  RING(r + 1, s + 1), RING(r + 1, s));
    }
#undef RING
    tmp_file_write(tmp_path(name), obj, n);
    free(obj);
}

static const char *header =
    "camera position 0 6 -14 direction 0 -0.45 1\nplane width 2 height 1.5 pixel 0.05\n"
    "light position -4 9 -6 power 300\nsphere lambertian center 0 -1001 0 radius 1000 color 0.7 "
    "0.7 0.7\nrender samples 2\n";

/* Two identity instances of a 100,000-face model (coincident: the tie rule picks the first)
 * against two flattened copies (the model under a second name): the same film, bit for bit, in
 * report and path mode; the packet builds and the reference agree on the instances. */
static void test_identity(void) {
    char text[2048];
    for (int path = 0; path < 2; path++) {
        /* path mode: the header's render line (its last, 17 bytes) with the mode */
        const char *mode = path ? "render samples 2 mode path\n" : "";
        snprintf(text, sizeof text,
                 "%.*s%smesh lambertian file big.obj color 0.8 0.3 0.2 smooth on\nmesh lambertian "
                 "file big.obj color 0.8 0.3 0.2 smooth on\n",
                 (int)strlen(header) - (path ? 17 : 0), header, mode);
        scene inst, flat;
        scene_error err;
        bool ok = parse(text, 1, &inst, &err);
        CHECK(ok, "identity: %s", err.message);
        if (!ok) return;
        CHECK(
            inst.instance_count == 2 && inst.model_face_count == 100000 && inst.triangle_count == 0,
            "identity: %d instances, %d model faces, %d faces", inst.instance_count,
            inst.model_face_count, inst.triangle_count);
        snprintf(text, sizeof text,
                 "%.*s%smesh lambertian file big.obj color 0.8 0.3 0.2 smooth on\nmesh lambertian "
                 "file big_copy.obj color 0.8 0.3 0.2 smooth on\n",
                 (int)strlen(header) - (path ? 17 : 0), header, mode);
        ok = parse(text, 1, &flat, &err);
        CHECK(ok && flat.instance_count == 0 && flat.triangle_count == 200000,
              "flattened: %s, %d faces", ok ? "parsed" : err.message, ok ? flat.triangle_count : 0);
        film a = {0}, b = {0}, r = {0};
        CHECK(render_with(&inst, NULL, &a) && render_with(&flat, NULL, &b) &&
                  render_with(&inst, "reference", &r),
              "identity: a render failed");
        CHECK(same_film(&a, &b), "%s mode: identity instances differ from flattened copies",
              path ? "path" : "report");
        CHECK(same_film(&a, &r), "%s mode: the packet build differs from the reference",
              path ? "path" : "report");
        film_free(&a), film_free(&b), film_free(&r);
        scene_free(&inst);
        if (ok) scene_free(&flat);
    }
}

/* The scene text of n instances of name on a grid, each moved, turned and scaled its own way. */
static char *grid_text(const char *name, int n) {
    size_t size = 4096 + (size_t)n * 200, used = 0;
    char *text = malloc(size);
    used += (size_t)snprintf(text, size, "%s", header);
    for (int k = 0; k < n; k++) {
        double x = (k % 40) * 0.5 - 10.0, z = (k / 40) * 0.5 - 2.0;
        used += (size_t)snprintf(text + used, size - used,
                                 "mesh lambertian file %s color 0.8 0.3 0.2 smooth on scale %.3f "
                                 "rotate 0.3 1 0.2 %d translate %.2f 0.3 %.2f\n",
                                 name, 0.15 + 0.01 * (k % 7), (k * 37) % 360, x, z);
    }
    return text;
}

/* s with its instances replaced by their faces moved in double and rounded once, as mesh lines
 * of their own would have placed them (normals by the inverse transpose, renormalized). */
static bool flatten(scene *s) {
    int total = s->triangle_count;
    for (int k = 0; k < s->instance_count; k++) total += s->models[s->instances[k].model].count;
    triangle *t = realloc(s->triangles, (size_t)total * sizeof *t);
    face_normals *nn = realloc(s->normals, ((size_t)s->normals_count + (size_t)total) * sizeof *nn);
    if (!t || !nn) return false;
    s->triangles = t, s->normals = nn;
    for (int k = 0; k < s->instance_count; k++) {
        const scene_instance *in = &s->instances[k];
        const double(*a)[4] = in->to_world;
        double inv[3][3], det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                                a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                                a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
                inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
            }
        const scene_model *m = &s->models[in->model];
        for (int f = 0; f < m->count; f++) {
            triangle face = s->model_faces[m->first + f];
            for (int c = 0; c < 3; c++) {
                double p[3] = {face.v[c].x, face.v[c].y, face.v[c].z}, w[3];
                for (int i = 0; i < 3; i++)
                    w[i] = a[i][0] * p[0] + a[i][1] * p[1] + a[i][2] * p[2] + a[i][3];
                face.v[c] = v3((float)w[0], (float)w[1], (float)w[2]);
            }
            if (face.normals != TRIANGLE_FLAT) {
                face_normals fn = s->normals[face.normals];
                for (int c = 0; c < 3; c++) {
                    double n[3] = {fn.n[c].x, fn.n[c].y, fn.n[c].z}, w[3], len = 0.0;
                    for (int i = 0; i < 3; i++) {
                        w[i] = inv[0][i] * n[0] + inv[1][i] * n[1] + inv[2][i] * n[2];
                        len += w[i] * w[i];
                    }
                    len = sqrt(len);
                    fn.n[c] = v3((float)(w[0] / len), (float)(w[1] / len), (float)(w[2] / len));
                }
                s->normals[s->normals_count] = fn;
                face.normals = (uint32_t)s->normals_count++;
            }
            s->triangles[s->triangle_count++] = face;
        }
    }
    s->instance_count = 0;
    return true;
}

/* 1,000 instances of a 200-face model, moved, turned and scaled, against the same placements
 * flattened: rays moved into an instance's space round differently from faces moved out of it,
 * so a few pixels differ, by little. */
static void test_moved(void) {
    char *text = grid_text("small.obj", 1000);
    scene inst, flat;
    scene_error err;
    bool ok = parse(text, 1, &inst, &err) && parse(text, 1, &flat, &err);
    free(text);
    CHECK(ok, "moved: %s", err.message);
    if (!ok) return;
    CHECK(inst.instance_count == 1000 && inst.model_face_count == 200,
          "moved: %d instances of %d faces", inst.instance_count, inst.model_face_count);
    CHECK(flatten(&flat), "moved: out of memory flattening");
    film a = {0}, b = {0}, r = {0};
    CHECK(render_with(&inst, NULL, &a) && render_with(&flat, NULL, &b) &&
              render_with(&inst, "reference", &r),
          "moved: a render failed");
    CHECK(same_film(&a, &r), "moved: the packet build differs from the reference");
    if (a.accum && b.accum) {
        int n = a.width * a.height, differ = 0;
        double diff = 0.0, sum = 0.0;
        for (int k = 0; k < n; k++) {
            for (int c = 0; c < 3; c++) {
                double x = a.accum[4 * k + c] / a.accum[4 * k + 3];
                double y = b.accum[4 * k + c] / b.accum[4 * k + 3];
                diff += fabs(x - y), sum += y;
                differ += fabs(x - y) > 1e-3 * (1.0 + y) && c == 0;
            }
        }
        printf("moved: %d of %d pixels differ, mean difference %.3g of the mean\n", differ, n,
               diff / sum);
        CHECK(differ <= n / 50 && diff <= 2e-3 * sum,
              "moved: %d of %d pixels differ, mean difference %.3g of the mean", differ, n,
              diff / sum);
    }
    film_free(&a), film_free(&b), film_free(&r);
    scene_free(&inst);
    scene_free(&flat);
}

/* 1,000 instances of a 100,000-face model: one copy of its faces, its packed scene within 1.2
 * times that of the model alone, and a render that the reference build agrees with. */
static void test_thousand(void) {
    char *text = grid_text("big.obj", 1000);
    scene s, one;
    scene_error err;
    bool ok = parse(text, 0, &s, &err);
    free(text);
    CHECK(ok, "thousand: %s", err.message);
    if (!ok) return;
    char single[1024];
    snprintf(single, sizeof single, "%smesh lambertian file big.obj color 0.8 0.3 0.2 smooth on\n",
             header);
    ok = parse(single, 1, &one, &err);
    CHECK(ok, "one model: %s", err.message);
    CHECK(s.instance_count == 1000 && s.model_face_count == 100000 && s.triangle_count == 0,
          "thousand: %d instances, %d model faces, %d faces", s.instance_count, s.model_face_count,
          s.triangle_count);
    render_opts o;
    render_stats st_many = {0}, st_one = {0};
    packed_scene p;
    render_opts_from_scene(&s, &o);
    o.stats = &st_many;
    bool packed = scene_pack(&s, &o, &p);
    if (packed) scene_pack_report(&p, &o, 0.0), scene_pack_free(&p);
    render_opts_from_scene(&one, &o);
    o.stats = &st_one;
    packed = packed && ok && scene_pack(&one, &o, &p);
    if (packed) scene_pack_report(&p, &o, 0.0), scene_pack_free(&p);
    CHECK(packed && st_many.scene_bytes < 1.2 * (double)st_one.scene_bytes,
          "thousand: %.1f MB packed, one model %.1f MB", st_many.scene_bytes * 1e-6,
          st_one.scene_bytes * 1e-6);
    printf("1,000 instances: %.2f MB packed, one model %.2f MB\n", st_many.scene_bytes * 1e-6,
           st_one.scene_bytes * 1e-6);
    film a = {0}, r = {0};
    CHECK(render_with(&s, NULL, &a) && render_with(&s, "reference", &r),
          "thousand: a render failed");
    CHECK(same_film(&a, &r), "thousand: the packet build differs from the reference");
    film_free(&a), film_free(&r);
    scene_free(&s);
    if (ok) scene_free(&one);
}

/* A transform that does not invert in single precision is refused at its line. */
static void test_singular(void) {
    char text[1024];
    snprintf(text, sizeof text,
             "%smesh lambertian file small.obj color 0.8 0.3 0.2\nmesh lambertian file small.obj "
             "color 0.8 0.3 0.2 scale 1e-39\n",
             header);
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(!ok && err.line == 7 && err.col == 22 && strstr(err.message, "singular"),
          "singular: %s %d:%d %s", ok ? "parsed" : "refused", err.line, err.col, err.message);
    if (ok) scene_free(&s);
}

/* A unit square of 8 x 8 quads with UVs across it (OBJ) and an RGBA map whose left texel is
 * cut (alpha 0) and right kept: a cut-out model for instances. */
static void write_cutout_model(void) {
    char obj[16384];
    size_t n = 0;
    for (int j = 0; j <= 8; j++)
        for (int i = 0; i <= 8; i++)
            n += (size_t)snprintf(obj + n, sizeof obj - n, "v %g %g 0\nvt %g %g\n", i / 8.0,
                                  j / 8.0, i / 8.0, j / 8.0);
    for (int j = 0; j < 8; j++)
        for (int i = 0; i < 8; i++) {
            int a = j * 9 + i + 1, b = a + 1, c = a + 10, d = a + 9;
            n += (size_t)snprintf(obj + n, sizeof obj - n, "f %d/%d %d/%d %d/%d %d/%d\n", a, a, b,
                                  b, c, c, d, d);
        }
    tmp_file_write(tmp_path("fence.obj"), obj, n);
    const uint8_t texels[8] = {200, 40, 40, 0, 40, 200, 40, 255};
    write_png(tmp_path("cut.png"), 2, 1, PNG_COLOR_TYPE_RGBA, texels);
}

/* Two instances of the fence model, one moved and turned, before a sphere: the scene text,
 * cut out by cut.png or not. */
static void cutout_text(char *text, size_t size, bool cut) {
    char map[600] = "";
    if (cut) snprintf(map, sizeof map, " alpha_map %s", tmp_path("cut.png"));
    snprintf(text, size,
             "%smesh lambertian file fence.obj color 0.8 0.8 0.8%s scale 3 translate -1.5 0 -2\n"
             "mesh lambertian file fence.obj color 0.8 0.8 0.8%s scale 2.5 rotate 0 1 0 35 "
             "translate 0.5 0.2 -1\nsphere lambertian center 0 1 2 radius 1 color 0.2 0.4 0.8\n",
             header, map, map);
}

/* Cut-outs inside instances: a face is cut in its model's space, the packet build and the
 * reference agree, and the cut half lets the light through (the film is not the uncut one). */
static void test_cutout(void) {
    char text[2048];
    scene s, whole;
    scene_error err;
    cutout_text(text, sizeof text, true);
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "cut-out instances: %s", err.message);
    if (!ok) return;
    cutout_text(text, sizeof text, false);
    ok = parse(text, 1, &whole, &err);
    CHECK(ok, "uncut instances: %s", err.message);
    CHECK(s.instance_count == 2, "cut-out instances: %d instances", s.instance_count);
    film a = {0}, r = {0}, w = {0};
    CHECK(render_with(&s, NULL, &a) && render_with(&s, "reference", &r) &&
              (!ok || render_with(&whole, NULL, &w)),
          "cut-out instances: a render failed");
    CHECK(same_film(&a, &r), "cut-out instances: the packet build differs from the reference");
    CHECK(ok && a.accum && w.accum && !same_film(&a, &w), "cut-out instances: nothing was cut");
    film_free(&a), film_free(&r), film_free(&w);
    scene_free(&s);
    if (ok) scene_free(&whole);
}

/* The digest of scene s's parts (render_part_meta), as text. */
static void digest_of(const scene *s, char *out, size_t size) {
    render_opts o;
    render_opts_from_scene(s, &o);
    part_meta m;
    render_part_meta(s, &o, &m);
    snprintf(out, size, "%.*s", (int)sizeof m.digest, m.digest);
}

/* Parts of scenes that place a model differently do not merge: the digest covers the models'
 * faces and every instance's transform; the same text twice gives the same digest. */
static void test_digest(void) {
    char *text = grid_text("small.obj", 3);
    char *moved = strdup(text);
    char *at = moved ? strstr(moved, "translate -10.00") : NULL;
    if (at) memcpy(at, "translate -9.000", 16); /* the first instance moves along x */
    scene a, b, c;
    scene_error err;
    bool ok =
        parse(text, 1, &a, &err) && parse(text, 1, &b, &err) && at && parse(moved, 1, &c, &err);
    free(text), free(moved);
    CHECK(ok && a.instance_count == 3, "digest: %s", ok ? "no instances" : err.message);
    if (!ok) return;
    char da[300], db[300], dc[300];
    digest_of(&a, da, sizeof da), digest_of(&b, db, sizeof db), digest_of(&c, dc, sizeof dc);
    CHECK(!strcmp(da, db), "digest: the same scene gives %s and %s", da, db);
    CHECK(strcmp(da, dc), "digest: a moved instance keeps the digest %s", da);
    scene_free(&a), scene_free(&b), scene_free(&c);
}

/* Scene text on the CPU back end and on every Vulkan walk: the same film bit for bit. */
static void expect_text_walks_agree(const char *what, const char *text) {
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "%s: %s", what, err.message);
    if (!ok) return;
    CHECK(s.instance_count > 0, "%s: no instances", what);
    expect_walks_agree(what, &s);
    scene_free(&s);
}

/* Identity instances of a 100,000-face model, 300 moved, turned and scaled instances of a
 * 200-face one among a plain mesh line's faces and spheres, and 1,000 moved instances of the
 * 100,000-face model, on every Vulkan walk. */
static void test_vulkan(void) {
    char text[2048];
    snprintf(text, sizeof text,
             "%smesh lambertian file big.obj color 0.8 0.3 0.2 smooth on\nmesh lambertian "
             "file big.obj color 0.8 0.3 0.2 smooth on\n",
             header);
    expect_text_walks_agree("identity", text);
    char *grid = grid_text("small.obj", 300);
    size_t len = strlen(grid);
    char *mixed = malloc(len + 512);
    snprintf(mixed, len + 512,
             "%smesh mirror file big_copy.obj scale 0.5 translate 0 1 4\n"
             "sphere refractive center 2 1 -2 radius 0.8\n",
             grid);
    free(grid);
    expect_text_walks_agree("moved", mixed);
    free(mixed);
    char cut[2048];
    cutout_text(cut, sizeof cut, true);
    expect_text_walks_agree("cut-out instances", cut);
    char *thousand = grid_text("big.obj", 1000);
    expect_text_walks_agree("1,000 of 100,000 faces", thousand);
    free(thousand);
}

int main(int argc, char **argv) {
    bool vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (vulkan && vk_context_device_count() == 0) {
        printf("test_instances: no Vulkan device, skipped\n");
        return 77;
    }
    tmp_dir_make(vulkan ? "test_instances_vulkan" : "test_instances");
    write_model("big.obj", 201, 250); /* 2 x 250 x 200 = 100,000 faces */
    write_model("big_copy.obj", 201, 250);
    write_model("small.obj", 11, 10); /* 200 faces */
    write_cutout_model();
    if (vulkan) {
        test_vulkan();
        return check_summary("test_instances vulkan");
    }
    test_identity();
    test_moved();
    test_thousand();
    test_singular();
    test_cutout();
    test_digest();
    return check_summary("test_instances");
}
