/* test_mesh.c: meshes from files (src/scene/mesh_load.c, the `mesh` directive): a unit cube in
 * OBJ and in ASCII PLY, transformed, gives the triangles and the image of six `quad` lines at
 * the transformed corners; an OBJ with MTL materials renders like the same faces written with
 * the mapped materials; every error gives its message at line:col (a file-size limit too); 1 and 4
 * parser threads agree; hostile files fail cleanly; lines naming one file import it once.
 * What meshes look like where only rendering shows it is tests/test_mesh_render.c.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include "check.h"
#include "mesh_test.h"
#include "render/part.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmp_dir.h"

#define PI 3.14159265358979323846

static const double cube[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
/* The six faces, each counter-clockwise seen from outside. */
static const int cube_faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                     {3, 7, 6, 2}, {0, 4, 7, 3}, {1, 2, 6, 5}};
/* scale 0.8 0.6 0.5 rotate 1 2 0.5 30 translate -0.3 -0.2 3 */
static const double xf_scale[3] = {0.8, 0.6, 0.5}, xf_axis[3] = {1, 2, 0.5}, xf_deg = 30,
                    xf_move[3] = {-0.3, -0.2, 3};
#define XF "scale 0.8 0.6 0.5 rotate 1 2 0.5 30 translate -0.3 -0.2 3"

static void transform(const double in[3], double out[3]) {
    double l = sqrt(xf_axis[0] * xf_axis[0] + xf_axis[1] * xf_axis[1] + xf_axis[2] * xf_axis[2]);
    double u[3] = {xf_axis[0] / l, xf_axis[1] / l, xf_axis[2] / l}, s[3];
    for (int k = 0; k < 3; k++) s[k] = in[k] * xf_scale[k];
    double a = xf_deg * PI / 180, c = cos(a), sn = sin(a),
           d = u[0] * s[0] + u[1] * s[1] + u[2] * s[2];
    double cr[3] = {u[1] * s[2] - u[2] * s[1], u[2] * s[0] - u[0] * s[2],
                    u[0] * s[1] - u[1] * s[0]};
    for (int k = 0; k < 3; k++) out[k] = s[k] * c + cr[k] * sn + u[k] * d * (1 - c) + xf_move[k];
}

static void write_cube_files(void) {
    char obj[2048] = "# unit cube\n", ply[2048];
    for (int v = 0; v < 8; v++) {
        size_t n = strlen(obj);
        snprintf(obj + n, sizeof obj - n, "v %g %g %g\n", cube[v][0], cube[v][1], cube[v][2]);
    }
    for (int f = 0; f < 6; f++) {
        size_t n = strlen(obj);
        snprintf(obj + n, sizeof obj - n, "f %d %d %d %d\n", cube_faces[f][0] + 1,
                 cube_faces[f][1] + 1, cube_faces[f][2] + 1, cube_faces[f][3] + 1);
    }
    write_text("cube.obj", obj);
    snprintf(ply, sizeof ply,
             "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
             "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
             "end_header\n");
    for (int v = 0; v < 8; v++) {
        size_t n = strlen(ply);
        snprintf(ply + n, sizeof ply - n, "%g %g %g\n", cube[v][0], cube[v][1], cube[v][2]);
    }
    for (int f = 0; f < 6; f++) {
        size_t n = strlen(ply);
        snprintf(ply + n, sizeof ply - n, "4 %d %d %d %d\n", cube_faces[f][0], cube_faces[f][1],
                 cube_faces[f][2], cube_faces[f][3]);
    }
    write_text("cube.ply", ply);
    /* the same cube wound inward */
    const char *in = strstr(obj, "\nf ") + 1;
    char inward[2048];
    snprintf(inward, sizeof inward, "%.*s", (int)(in - obj), obj);
    for (int f = 0; f < 6; f++) {
        size_t n = strlen(inward);
        snprintf(inward + n, sizeof inward - n, "f %d %d %d %d\n", cube_faces[f][0] + 1,
                 cube_faces[f][3] + 1, cube_faces[f][2] + 1, cube_faces[f][1] + 1);
    }
    write_text("cube_in.obj", inward);
}

#define HEADER                                                                     \
    "camera position 0 0 0 direction 0 0 1\nplane width 2 height 2 pixel 0.0625\n" \
    "light position -1 2 0 power 20\nbackground 0.1 0.2 0.3\nrender samples 2\n"

/* Whether triangle a has the corners of b (any order) within tol. */
static bool same_corners(const triangle *a, const triangle *b, double tol) {
    for (int r = 0; r < 3; r++) {
        bool all = true;
        for (int k = 0; k < 3 && all; k++) {
            vec3 p = a->v[k], q = b->v[(k + r) % 3];
            all = fabs(p.x - q.x) <= tol && fabs(p.y - q.y) <= tol && fabs(p.z - q.z) <= tol;
        }
        if (all) return true;
    }
    return false;
}

/* Every triangle of a matches one of b with the same material, and the counts agree. */
static bool same_triangles(const scene *a, const scene *b) {
    if (a->triangle_count != b->triangle_count) return false;
    for (int i = 0; i < a->triangle_count; i++) {
        bool found = false;
        for (int j = 0; j < b->triangle_count && !found; j++) {
            const triangle *t = &a->triangles[i], *u = &b->triangles[j];
            const material *tm = triangle_material(a, t), *um = triangle_material(b, u);
            found = same_corners(t, u, 1e-5) && tm->kind == um->kind &&
                    fabsf(tm->color.x - um->color.x) < 1e-6f && fabsf(tm->ks - um->ks) < 1e-6f &&
                    fabsf(tm->alpha - um->alpha) < 1e-6f && fabsf(tm->ior - um->ior) < 1e-6f;
        }
        if (!found) return false;
    }
    return true;
}

/* The largest difference between two films' pixel means (infinite when their sizes differ). */
static double film_difference(const film *a, const film *b) {
    if (a->width != b->width || a->height != b->height) return INFINITY;
    double worst = 0;
    for (size_t k = 0; k < (size_t)a->width * a->height; k++) {
        for (int c = 0; c < 3; c++) {
            double x = a->accum[k * 4 + c] / a->accum[k * 4 + 3];
            double y = b->accum[k * 4 + c] / b->accum[k * 4 + 3];
            worst = fmax(worst, fabs(x - y));
        }
    }
    return worst;
}

/* Parses and renders both texts; checks the same triangles and pixels within 1e-4. */
static void expect_same(const char *name, const char *mesh_text, const char *quad_text) {
    scene a, b;
    scene_error err;
    bool ok_a = parse(mesh_text, 1, &a, &err);
    if (!ok_a) scene_error_print(&err);
    bool ok_b = parse(quad_text, 1, &b, &err);
    if (!ok_b) scene_error_print(&err);
    CHECK(ok_a && ok_b, "%s: parse failed", name);
    if (!ok_a || !ok_b) return;
    CHECK(same_triangles(&a, &b), "%s: %d and %d triangles differ", name, a.triangle_count,
          b.triangle_count);
    film fa = {0}, fb = {0};
    CHECK(render(&a, &fa) && render(&b, &fb), "%s: render failed", name);
    if (fa.accum && fb.accum) {
        double d = film_difference(&fa, &fb);
        CHECK(d <= 1e-4, "%s: pixels differ by %g", name, d);
    }
    film_free(&fa);
    film_free(&fb);
    scene_free(&a);
    scene_free(&b);
}

static char quads[8192];

/* Six quad lines at the transformed cube's corners, each with `material`: the file's
 * right-handed corners first mirrored into trazador's space (z negated, each face's corners in
 * the reverse order), then transformed. */
static void cube_quads(const char *material) {
    snprintf(quads, sizeof quads, "%s", HEADER);
    for (int f = 0; f < 6; f++) {
        size_t n = strlen(quads);
        n += (size_t)snprintf(quads + n, sizeof quads - n, "quad %s", material);
        for (int k = 0; k < 4; k++) {
            const double *c = cube[cube_faces[f][(4 - k) % 4]];
            double mirrored[3] = {c[0], c[1], -c[2]}, p[3];
            transform(mirrored, p);
            n += (size_t)snprintf(quads + n, sizeof quads - n, " v%d %.9g %.9g %.9g", k,
                                  (double)(float)p[0], (double)(float)p[1], (double)(float)p[2]);
        }
        snprintf(quads + n, sizeof quads - n, "\n");
    }
}

static void test_cube(void) {
    write_cube_files();
    cube_quads("phong color 0.7 0.4 0.2 ks 0.3 alpha 12");
    expect_same("obj cube",
                HEADER "mesh phong file cube.obj " XF " color 0.7 0.4 0.2 ks 0.3 alpha 12\n",
                quads);
    expect_same("ply cube",
                HEADER "mesh phong color 0.7 0.4 0.2 file cube.ply ks 0.3 " XF " alpha 12\n",
                quads);
    /* glass faces are wound outward whatever the file's winding */
    expect_same("glass cube wound inward", HEADER "mesh refractive file cube_in.obj " XF "\n",
                HEADER "mesh refractive file cube.obj " XF "\n");
}

/* Three faces with three MTL materials: a lambertian, a Phong and a mirror (the file's
 * right-handed faces at -z, wound the other way, are the quads' once mirrored). */
static void test_mtl(void) {
    write_text("three.mtl",
               "newmtl matte\nKd 0.2 0.5 0.7\nKs 0 0 0\n"
               "newmtl shiny\nKd 0.5 0.4 0.3\nKs 0.3 0.2 0.1\nNs 20\n"
               "newmtl chrome\nKd 0.9 0.9 0.9\nillum 3\n");
    write_text("three.obj",
               "mtllib three.mtl\n"
               "v -2 -1 -2\nv 2 -1 -2\nv 2 -1 -6\nv -2 -1 -6\n"
               "v -2 2 -6\nv 2 2 -6\nv -2 2 -2\n"
               "usemtl matte\nf 1 2 3 4\n"
               "usemtl shiny\nf 4 3 6 5\n"
               "usemtl chrome\nf 1 4 5 7\n");
    expect_same("obj mtl", HEADER "mesh file three.obj\n",
                HEADER
                "quad lambertian v0 -2 -1 2 v1 -2 -1 6 v2 2 -1 6 v3 2 -1 2 color 0.2 0.5 0.7\n"
                "quad phong v0 -2 -1 6 v1 -2 2 6 v2 2 2 6 v3 2 -1 6 color 0.5 0.4 0.3 ks 0.2 "
                "alpha 20\n"
                "quad mirror v0 -2 -1 2 v1 -2 2 2 v2 -2 2 6 v3 -2 -1 6 color 0.9 0.9 0.9\n");
}

/* text's error is at line:col and its message holds `want`. */
static void expect_error(const char *text, int line, int col, const char *want) {
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(!ok, "parsed, expected '%s'", want);
    if (ok) {
        scene_free(&s);
        return;
    }
    CHECK(err.line == line && err.col == col && strstr(err.message, want),
          "got %d:%d: %s, want %d:%d: %s", err.line, err.col, err.message, line, col, want);
}

static void test_errors(void) {
    write_text("points.obj", "v 0 0 0\nv 1 0 0\np 1\np 2\n");
    write_text("huge.obj", "v 0 0 0\nv 1e39 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text("cube.xyzq", "not a model\n");
    write_text("garbage.ply", "ply\nformat ascii 1.0\nelement vertex banana\n");
    write_text("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    write_text("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    expect_error(HEADER "mesh file missing.obj\n", 6, 11, "missing.obj': cannot open");
    expect_error(HEADER "mesh lambertian file points.obj\n", 6, 22, "holds no triangles");
    expect_error(HEADER "mesh file huge.obj\n", 6, 11, "non-finite position");
    expect_error(HEADER "mesh file cube.xyzq\n", 6, 11, "unsupported format");
    expect_error(HEADER "mesh file garbage.ply\n", 6, 11, "cannot load: ");
    expect_error(HEADER "mesh refractive file open.obj\n", 6, 22, "not closed");
    expect_error(HEADER "mesh file flat.obj\n", 6, 11, "every face is degenerate");
    expect_error(HEADER "mesh file cube.obj scale 0\n", 6, 20, "scale must not be zero");
    expect_error(HEADER "mesh file cube.obj rotate 0 0 0 5\n", 6, 20, "axis must not be zero");
    expect_error(HEADER "mesh file cube.obj color 1 1 1\n", 6, 20, "needs a material word");
    expect_error(HEADER "mesh glass file cube.obj\n", 6, 6, "unknown material 'glass'");
    expect_error(HEADER "mesh lambertian scale 2\n", 6, 1, "missing required key 'file'");
    expect_error(HEADER "mesh lambertian file cube.obj emission 1 1 1\n", 6, 31,
                 "emission needs path mode");
    /* Under a file-size limit the faces' shared memory cannot grow: a message, not a signal. */
    struct rlimit limit;
    getrlimit(RLIMIT_FSIZE, &limit);
    struct rlimit tiny = {.rlim_cur = 16, .rlim_max = limit.rlim_max};
    setrlimit(RLIMIT_FSIZE, &tiny);
    expect_error(HEADER "mesh file cube.obj\n", 6, 11, "(the file-size limit, ulimit -f, caps it)");
    setrlimit(RLIMIT_FSIZE, &limit);
    /* a degenerate face among good ones: dropped, one warning */
    write_text("one_bad.obj", "v 0 0 -5\nv 1 0 -5\nv 0 1 -5\nv 2 0 -5\nf 1 2 3\nf 1 2 4\n");
    scene s;
    scene_error err;
    bool ok = parse(HEADER "mesh file one_bad.obj\n", 1, &s, &err);
    CHECK(ok, "one_bad: %s", err.message);
    if (ok) {
        CHECK(s.triangle_count == 1, "one_bad: %d triangles", s.triangle_count);
        CHECK(s.warning_count == 1 && strstr(s.warnings[0].message, "1 degenerate face dropped"),
              "one_bad: warnings %d", s.warning_count);
        scene_free(&s);
    }
}

/* An MTL value that is not finite or a negative colour is an error naming the material, not a
 * zero (an emitter that vanished); the limit of assimp's time can be given. */
static void test_material_values(void) {
    static const struct {
        const char *line, *want;
    } bad[] = {
        {"Ke 1e39 1 1", "material 'm': its emission (Ke) is not finite: inf 1 1"},
        {"Ke -1 0 0", "its emission (Ke) is negative: -1 0 0"},
        {"Kd 0.5 nan 0.5", "its diffuse colour (Kd) is not finite"},
        {"Ns inf", "its shininess (Ns) is not finite"},
    };
    write_text("m.obj", "mtllib m.mtl\nv 0 0 5\nv 1 0 5\nv 0 1 5\nusemtl m\nf 1 2 3\n");
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        char mtl[128];
        snprintf(mtl, sizeof mtl, "newmtl m\n%s\n", bad[k].line);
        write_text("m.mtl", mtl);
        expect_error(HEADER "mesh file m.obj\n", 6, 11, bad[k].want);
    }
    write_text("m.mtl", "newmtl m\nKd 0.2 0.3 0.4\nKe 0 0 0\n");
    scene s;
    scene_error err;
    bool ok = parse(HEADER "mesh file m.obj\n", 1, &s, &err);
    CHECK(ok && s.material_count == 1 && s.materials[0].color.y == 0.3f, "good mtl: %s",
          ok ? "wrong material" : err.message);
    if (ok) scene_free(&s);
    setenv("TRAZADOR_MESH_SECONDS", "soon", 1);
    expect_error(HEADER "mesh file m.obj\n", 6, 11, "TRAZADOR_MESH_SECONDS='soon' is not a time");
    setenv("TRAZADOR_MESH_SECONDS", "1e-9", 1);
    expect_error(HEADER "mesh file m.obj\n", 6, 11, "did not finish within its time limit");
    setenv("TRAZADOR_MESH_SECONDS", "60", 1);
    ok = parse(HEADER "mesh file m.obj\n", 1, &s, &err);
    CHECK(ok, "a limit of 60 s: %s", err.message);
    if (ok) scene_free(&s);
    unsetenv("TRAZADOR_MESH_SECONDS");
}

/* The scene keeps the identity of every file its meshes read, each once (the CLI refuses to
 * write over them): the OBJ and its MTL, whichever mesh line named them. */
static void test_inputs(void) {
    scene s;
    scene_error err;
    bool ok = parse(HEADER
                    "mesh file three.obj\nmesh file three.obj translate 0 0 1\n"
                    "mesh file cube.ply translate 0 0 9\n",
                    1, &s, &err);
    CHECK(ok, "inputs: %s", err.message);
    if (!ok) return;
    static const char *files[] = {"three.obj", "three.mtl", "cube.ply"};
    CHECK(s.input_count == 3, "inputs: %d, want 3", s.input_count);
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        struct stat st;
        bool found = false;
        if (stat(tmp_path(files[f]), &st) == 0)
            for (int k = 0; k < s.input_count; k++)
                found |= s.inputs[k].device == (uint64_t)st.st_dev &&
                         s.inputs[k].inode == (uint64_t)st.st_ino &&
                         strstr(s.inputs[k].path, files[f]) != NULL;
        CHECK(found, "inputs: %s not among them", files[f]);
    }
    scene_free(&s);
}

/* What trazador cannot show is named once in a warning (textures it does not shade), and a
 * model's texture that cannot be read is a warning naming it. */
static void test_unsupported(void) {
    write_text("textured.mtl",
               "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd a.png\nmap_bump b.png\n"
               "newmtl b\nKd 0.5 0.5 0.5\nmap_Kd c.png\n");
    write_text("textured.obj",
               "mtllib textured.mtl\nv 0 0 -5\nv 1 0 -5\nv 0 1 -5\nv 1 1 -5\n"
               "usemtl a\nf 1 2 3\nusemtl b\nf 2 4 3\n");
    scene s;
    scene_error err;
    bool ok = parse(HEADER "mesh file textured.obj\n", 1, &s, &err);
    CHECK(ok, "textured: %s", err.message);
    if (!ok) return;
    /* The missing maps are warnings naming them (the faces render without them); what is not
     * shaded (the bump map) is named, the shaded colour map is not. */
    bool missing = false, bump = false, diffuse = false;
    for (int k = 0; k < s.warning_count; k++) {
        const char *w = s.warnings[k].message;
        missing |= strstr(w, "a.png") && strstr(w, "not shown") && s.warnings[k].line == 6;
        bump |= strstr(w, "bump texture") != NULL;
        diffuse |= strstr(w, "diffuse texture") != NULL;
    }
    CHECK(missing && bump && !diffuse, "textured: %d warnings, missing %d bump %d diffuse %d",
          s.warning_count, missing, bump, diffuse);
    scene_free(&s);
    /* with a material of its own, the file's materials are not used: no warning */
    ok = parse(HEADER "mesh lambertian file textured.obj\n", 1, &s, &err);
    CHECK(ok && s.warning_count == 0, "textured with a material: %d warnings",
          ok ? s.warning_count : -1);
    if (ok) scene_free(&s);
}

/* The digest of a part covers the model's content: moving one vertex of the file changes it. */
static void test_digest(void) {
    struct part_meta before, after;
    const char *text = HEADER "mesh lambertian file moved.obj\n";
    write_text("moved.obj", "v 0 0 5\nv 1 0 5\nv 0 1 5\nf 1 2 3\n");
    for (int k = 0; k < 2; k++) {
        if (k) write_text("moved.obj", "v 0 0 5\nv 1 0 5\nv 0 1.001 5\nf 1 2 3\n");
        scene s;
        scene_error err;
        bool ok = parse(text, 1, &s, &err);
        CHECK(ok, "digest: %s", err.message);
        if (!ok) return;
        render_opts o;
        render_opts_from_scene(&s, &o);
        render_part_meta(&s, &o, k ? &after : &before);
        scene_free(&s);
    }
    CHECK(strcmp(before.digest, after.digest) != 0, "digest unchanged: %s", before.digest);
}

/* Truncations of the cube files and byte garbage load or fail, never crash. */
static void test_hostile(void) {
    static const char *files[] = {"cube.obj", "cube.ply", "three.obj"};
    for (size_t f = 0; f < sizeof files / sizeof files[0]; f++) {
        size_t len;
        unsigned char *data = tmp_file_read(tmp_path(files[f]), &len);
        CHECK(data != NULL, "read %s", files[f]);
        if (!data) continue;
        const char *ext = strrchr(files[f], '.');
        char name[64], text[512];
        snprintf(name, sizeof name, "cut%s", ext);
        snprintf(text, sizeof text, HEADER "mesh lambertian file %s\n", name);
        for (size_t n = 0; n < len; n += 3) {
            for (size_t k = 0; k < n; k += 7) data[k] ^= (unsigned char)(n & 0x55);
            tmp_file_write(tmp_path(name), data, n);
            scene s;
            scene_error err;
            if (parse(text, 1, &s, &err)) scene_free(&s);
            for (size_t k = 0; k < n; k += 7) data[k] ^= (unsigned char)(n & 0x55);
        }
        free(data);
    }
    CHECK(true, "hostile files survived");
}

/* A PLY that loops assimp 5.2.5 for ever ends at the child's limit of processor time with the
 * limit's message (the fuzz corpus's input, less its format byte). */
static void test_hang(void) {
    size_t len;
    unsigned char *data =
        tmp_file_read(TRAZADOR_SOURCE_DIR "/tests/corpus_mesh/ply_assimp_hang", &len);
    CHECK(data != NULL && len > 1, "read the hanging PLY");
    if (!data || len < 2) return;
    tmp_file_write(tmp_path("hang.ply"), data + 1, len - 1);
    free(data);
    setenv("TRAZADOR_MESH_SECONDS", "0.3", 1);
    expect_error(HEADER "mesh lambertian file hang.ply\n", 6, 22,
                 "did not finish within its time limit of 0.3 s of processor time");
    unsetenv("TRAZADOR_MESH_SECONDS");
}

/* Whether two scenes place the same models the same way (field by field: padding differs). */
static bool same_instances(const scene *a, const scene *b) {
    bool same = a->instance_count == b->instance_count;
    for (int k = 0; same && k < a->instance_count; k++)
        same = a->instances[k].model == b->instances[k].model &&
               !memcmp(a->instances[k].to_world, b->instances[k].to_world,
                       sizeof a->instances[k].to_world);
    return same;
}

/* Mesh lines among enough spheres to be cut into chunks parse the same on 1 and 4 threads (the
 * repeated lines as instances of the two models' 18 faces). */
static void test_threads(void) {
    size_t size = 4 << 20, used = 0;
    char *text = malloc(size);
    used += (size_t)snprintf(text, size, "%s", HEADER);
    for (int k = 0; k < 40000; k++) {
        used += (size_t)snprintf(text + used, size - used,
                                 "sphere lambertian center %d 0 40 radius 0.25\n", k % 100);
        if (k % 9000 == 0)
            used += (size_t)snprintf(text + used, size - used,
                                     "mesh file three.obj translate %d 0 0\nmesh lambertian file "
                                     "cube.ply " XF "\n",
                                     k / 9000);
    }
    scene a, b;
    scene_error err;
    bool ok_a = parse(text, 1, &a, &err), ok_b = parse(text, 4, &b, &err);
    CHECK(ok_a && ok_b, "threads: parse failed: %s", err.message);
    if (ok_a && ok_b) {
        CHECK(
            a.triangle_count == 0 && b.triangle_count == 0 && a.model_face_count == 18 &&
                b.model_face_count == 18 && a.instance_count == 10 && b.instance_count == 10 &&
                !memcmp(a.model_faces, b.model_faces, 18 * sizeof *a.model_faces) &&
                same_instances(&a, &b) && a.material_count == b.material_count &&
                !memcmp(a.materials, b.materials, (size_t)a.material_count * sizeof *a.materials) &&
                a.sphere_count == b.sphere_count,
            "threads: %d and %d model faces, %d and %d faces, %d and %d instances",
            a.model_face_count, b.model_face_count, a.triangle_count, b.triangle_count,
            a.instance_count, b.instance_count);
    }
    if (ok_a) scene_free(&a);
    if (ok_b) scene_free(&b);
    free(text);
}

/* Scene text a's faces (triangles, their materials and normals) are b's then c's, byte for byte. */
static void expect_concatenation(const char *name, const char *a, const char *b, const char *c) {
    scene sa, sb, sc;
    scene_error err;
    bool ok = parse(a, 1, &sa, &err);
    CHECK(ok, "%s: %s", name, err.message);
    if (!ok) return;
    if (parse(b, 1, &sb, &err)) {
        if (parse(c, 1, &sc, &err)) {
            bool same = sa.triangle_count == sb.triangle_count + sc.triangle_count &&
                        sa.normals_count == sb.normals_count + sc.normals_count;
            for (int k = 0; same && k < sa.triangle_count; k++) {
                bool first = k < sb.triangle_count;
                const triangle *ta = &sa.triangles[k];
                const triangle *tb =
                    first ? &sb.triangles[k] : &sc.triangles[k - sb.triangle_count];
                const scene *sx = first ? &sb : &sc;
                same = !memcmp(ta->v, tb->v, sizeof ta->v) &&
                       material_same(triangle_material(&sa, ta), triangle_material(sx, tb)) &&
                       (ta->normals == TRIANGLE_FLAT) == (tb->normals == TRIANGLE_FLAT) &&
                       (ta->normals == TRIANGLE_FLAT ||
                        !memcmp(&sa.normals[ta->normals], &sx->normals[tb->normals],
                                sizeof *sa.normals));
            }
            CHECK(same, "%s: the faces differ from the lines parsed apart", name);
            scene_free(&sc);
        }
        scene_free(&sb);
    }
    scene_free(&sa);
}

/* Lines naming one file import it once (mesh_cache.c) and each gets the faces its own import
 * would have: transformed, flipped for glass and smoothed on its own copy (`lights on` keeps a
 * repeated line's own copy: without it the line is an instance, tests/test_instances.c). */
static void test_repeated(void) {
    expect_concatenation("cube twice",
                         HEADER "mesh file cube.obj " XF
                                "\nmesh file cube.obj translate 0 0 9 lights on\n",
                         HEADER "mesh file cube.obj " XF "\n",
                         HEADER "mesh file cube.obj translate 0 0 9 lights on\n");
    expect_concatenation(
        "glass flips its own copy",
        HEADER
        "mesh refractive file cube_in.obj\nmesh lambertian file cube_in.obj translate 0 0 3\n",
        HEADER "mesh refractive file cube_in.obj\n",
        HEADER "mesh lambertian file cube_in.obj translate 0 0 3\n");
    write_sphere(6, 8);
    expect_concatenation(
        "smooth off, then on",
        HEADER
        "mesh file sphere.obj translate 0 0 9\nmesh file sphere.obj smooth on translate 0 0 5\n",
        HEADER "mesh file sphere.obj translate 0 0 9\n",
        HEADER "mesh file sphere.obj smooth on translate 0 0 5\n");
    /* a file changed between parses is read again */
    write_text("moving.obj", "v 0 0 5\nv 1 0 5\nv 0 1 5\nf 1 2 3\n");
    expect_concatenation(
        "moving, first", HEADER "mesh file moving.obj\nmesh file moving.obj lights on\n",
        HEADER "mesh file moving.obj\n", HEADER "mesh file moving.obj lights on\n");
    write_text("moving.obj", "v 0 0 5\nv 2 0 5\nv 0 1 5\nv 0 0 6\nf 1 2 3\nf 1 2 4\n");
    scene s;
    scene_error err;
    bool ok = parse(HEADER "mesh file moving.obj\n", 1, &s, &err);
    CHECK(ok && s.triangle_count == 2 && s.triangles[0].v[2].x == 2.0f, "moving: %s",
          ok ? "the old file's faces" : err.message);
    if (ok) scene_free(&s);
}

int main(void) {
    if (!tmp_dir_make("test_mesh")) {
        printf("cannot make a temporary folder\n");
        return 1;
    }
    CHECK_CASE(test_cube);
    CHECK_CASE(test_mtl);
    CHECK_CASE(test_errors);
    CHECK_CASE(test_material_values);
    CHECK_CASE(test_inputs);
    CHECK_CASE(test_unsupported);
    CHECK_CASE(test_digest);
    CHECK_CASE(test_hostile);
    CHECK_CASE(test_hang);
    CHECK_CASE(test_threads);
    CHECK_CASE(test_repeated);
    return check_summary("test_mesh");
}
