/* test_mesh_import.c: what the import makes of model files as their makers meant them (issue
 * 49): a right-handed model (an L of two boxes, OBJ and glTF) renders as the same faces written
 * by hand in trazador's left-handed space, not mirrored; files without materials get lambertian
 * 0.8 grey; mapped materials reflect at most what they receive, or warn; glass is checked part
 * by part; a glTF emission strength that assimp drops is said. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "mesh_test.h"
#include "tmp_dir.h"

/* The L in the scene's space, as quads (corners in order around each face): a foot along +x,
 * x -1 to 1, y -1 to -0.5, z -1 to 0, and an upright at its -x end, x -1 to -0.5, y -0.5 to 1,
 * z -1 to -0.5 (the front half: nearer a camera at -z). All coordinates are exact in binary, so
 * every reader parses them to the same floats. */
#define L_QUADS 12
static double l_quads[L_QUADS][4][3];

/* The six faces of box lo..hi as quads. */
static void box_quads(const double lo[3], const double hi[3], double (*out)[4][3]) {
    static const int faces[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (int f = 0; f < 6; f++)
        for (int k = 0; k < 4; k++) {
            int c = faces[f][k];
            out[f][k][0] = c & 1 ? hi[0] : lo[0];
            out[f][k][1] = c & 2 ? hi[1] : lo[1];
            out[f][k][2] = c & 4 ? hi[2] : lo[2];
        }
}

/* The L's faces in the model file's right-handed space, converted by hand: z negated and each
 * face wound the other way, so the scene's quad (q0 q1 q2 q3), triangles (q0 q1 q2) and
 * (q0 q2 q3), is the file's triangles (m0 m2 m1) and (m0 m3 m2), m = q mirrored. */
static void file_triangles(double out[2 * L_QUADS][3][3]) {
    static const int order[2][3] = {{0, 2, 1}, {0, 3, 2}};
    for (int q = 0; q < L_QUADS; q++)
        for (int t = 0; t < 2; t++)
            for (int k = 0; k < 3; k++) {
                const double *c = l_quads[q][order[t][k]];
                out[2 * q + t][k][0] = c[0];
                out[2 * q + t][k][1] = c[1];
                out[2 * q + t][k][2] = -c[2];
            }
}

/* The L's glTF text, its primitive of material 0 of `materials` (a JSON array) when given. */
static void gltf_text(char *out, size_t size, const char *materials) {
    size_t bytes = 2 * L_QUADS * 9 * sizeof(float);
    snprintf(out, size,
             "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0}%s}]}],%s%s%s\"buffers\":[{\"uri\":\"l.bin\",\"byteLength\":%zu}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu}],\"accessors\":[{"
             "\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\","
             "\"min\":[-1,-1,0],\"max\":[1,1,1]}]}\n",
             materials ? ",\"material\":0" : "", materials ? "\"materials\":" : "",
             materials ? materials : "", materials ? "," : "", bytes, bytes, 2 * L_QUADS * 3);
}

/* The L as l.obj and as l.gltf with l.bin (one buffer of float corners, no indices, no
 * material). */
static void write_l_files(void) {
    const double foot_lo[3] = {-1, -1, -1}, foot_hi[3] = {1, -0.5, 0};
    const double up_lo[3] = {-1, -0.5, -1}, up_hi[3] = {-0.5, 1, -0.5};
    box_quads(foot_lo, foot_hi, l_quads);
    box_quads(up_lo, up_hi, l_quads + 6);
    double tri[2 * L_QUADS][3][3];
    file_triangles(tri);
    char obj[8192] = "# an L, right-handed: its upright stands at the front (+z)\n";
    float bin[2 * L_QUADS * 9];
    for (int t = 0; t < 2 * L_QUADS; t++)
        for (int k = 0; k < 3; k++) {
            size_t n = strlen(obj);
            snprintf(obj + n, sizeof obj - n, "v %g %g %g\n", tri[t][k][0], tri[t][k][1],
                     tri[t][k][2]);
            for (int a = 0; a < 3; a++) bin[t * 9 + k * 3 + a] = (float)tri[t][k][a];
        }
    for (int t = 0; t < 2 * L_QUADS; t++) {
        size_t n = strlen(obj);
        snprintf(obj + n, sizeof obj - n, "f %d %d %d\n", 3 * t + 1, 3 * t + 2, 3 * t + 3);
    }
    write_text("l.obj", obj);
    tmp_file_write(tmp_path("l.bin"), bin, sizeof bin);
    char gltf[2048];
    gltf_text(gltf, sizeof gltf, NULL);
    write_text("l.gltf", gltf);
}

#define L_HEADER                                                                        \
    "camera position 0.5 0.5 -6 direction 0 0 1\nplane width 2 height 2 pixel 0.0625\n" \
    "light position -1 3 -5 power 40\nrender samples 1\n"

/* Renders text; false (checked) when it does not parse or render. */
static bool render_text(const char *name, const char *text, film *f) {
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "%s: %s", name, ok ? "" : err.message);
    if (!ok) return false;
    ok = render(&s, f);
    CHECK(ok, "%s: render failed", name);
    scene_free(&s);
    return ok;
}

/* The L from OBJ and from glTF renders bit for bit as its quads written in the scene's space,
 * the upright (x < -0.5) on the image's left, the foot reaching to its right. */
static void test_handedness(void) {
    write_l_files();
    char quads[8192] = L_HEADER;
    for (int q = 0; q < L_QUADS; q++) {
        size_t n = strlen(quads);
        n += (size_t)snprintf(quads + n, sizeof quads - n, "quad lambertian");
        for (int k = 0; k < 4; k++)
            n += (size_t)snprintf(quads + n, sizeof quads - n, " v%d %g %g %g", k, l_quads[q][k][0],
                                  l_quads[q][k][1], l_quads[q][k][2]);
        snprintf(quads + n, sizeof quads - n, "\n");
    }
    film want = {0};
    if (!render_text("quads", quads, &want)) return;
    /* the quads themselves: the upright's rows (y above -0.5) are lit on the left only */
    int left = 0, right = 0;
    for (int j = 0; j < want.height / 2; j++)
        for (int i = 0; i < want.width; i++) {
            const float *px = &want.accum[((size_t)j * want.width + i) * 4];
            if (px[0] + px[1] + px[2] > 0.0f) *(i < want.width / 2 ? &left : &right) += 1;
        }
    CHECK(left > 0 && right == 0, "quads: the upright's rows: %d pixels lit left, %d right", left,
          right);
    const char *files[] = {"l.obj", "l.gltf"};
    for (int k = 0; k < 2; k++) {
        char text[512];
        snprintf(text, sizeof text, L_HEADER "mesh lambertian file %s\n", files[k]);
        film got = {0};
        if (render_text(files[k], text, &got)) {
            size_t bytes = (size_t)want.width * want.height * 4 * sizeof *want.accum;
            CHECK(got.width == want.width && got.height == want.height &&
                      !memcmp(got.accum, want.accum, bytes),
                  "%s: not the image of its faces mirrored into the scene's space by hand",
                  files[k]);
        }
        film_free(&got);
    }
    film_free(&want);
}

/* The material of the first face of `mesh file NAME`; false (checked) when it does not parse. */
static bool first_material(const char *name, material *out) {
    char text[256];
    snprintf(text, sizeof text, L_HEADER "mesh file %s\n", name);
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "%s: %s", name, ok ? "" : err.message);
    if (!ok) return false;
    *out = *triangle_material(&s, &s.triangles[0]);
    scene_free(&s);
    return true;
}

/* Files without materials (PLY, STL, OFF, OBJ without MTL, glTF without one) get the README's
 * lambertian 0.8 grey, not assimp's made-up material (PLY, STL: white with specular 1, which
 * became Phong ks 1 over white); a material of the file's own is mapped, even white. */
static void test_no_material(void) {
    write_l_files();
    write_text("bare.ply",
               "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\n"
               "property float y\nproperty float z\nelement face 1\n"
               "property list uchar int vertex_indices\nend_header\n"
               "0 0 1\n1 0 1\n0 1 1\n3 0 1 2\n");
    write_text("bare.stl",
               "solid t\nfacet normal 0 0 -1\nouter loop\nvertex 0 0 1\n"
               "vertex 0 1 1\nvertex 1 0 1\nendloop\nendfacet\nendsolid t\n");
    write_text("bare.off", "OFF\n3 1 0\n0 0 1\n1 0 1\n0 1 1\n3 0 1 2\n");
    write_text("bare.obj", "v 0 0 1\nv 1 0 1\nv 0 1 1\nf 1 2 3\n");
    write_text("white.mtl", "newmtl white\nKd 1 1 1\nKs 1 1 1\nNs 10\n");
    write_text("white.obj",
               "mtllib white.mtl\nv 0 0 1\nv 1 0 1\nv 0 1 1\nusemtl white\n"
               "f 1 2 3\n");
    const char *bare[] = {"bare.ply", "bare.stl", "bare.off", "bare.obj", "l.gltf"};
    for (size_t k = 0; k < sizeof bare / sizeof bare[0]; k++) {
        material m;
        if (!first_material(bare[k], &m)) continue;
        CHECK(m.kind == TZ_MATERIAL_LAMBERTIAN && m.color.x == 0.8f && m.color.y == 0.8f &&
                  m.color.z == 0.8f && m.ks == 0.0f,
              "%s: material %d colour %g %g %g ks %g, want lambertian 0.8", bare[k], (int)m.kind,
              (double)m.color.x, (double)m.color.y, (double)m.color.z, (double)m.ks);
    }
    material m;
    if (first_material("white.obj", &m))
        CHECK(m.kind == TZ_MATERIAL_PHONG && m.color.x == 1.0f && m.ks == 1.0f,
              "white.obj: its own material became %d colour %g ks %g", (int)m.kind,
              (double)m.color.x, (double)m.ks);
}

#define PATH_HEADER                                                                   \
    "camera position 0.5 0.5 -6 direction 0 0 1\nplane width 2 height 2 pixel 0.25\n" \
    "render mode path samples 1\n"

/* The scene of `mesh file NAME` in path mode; false (checked) when it does not parse. */
static bool parse_path_mode(const char *name, scene *s) {
    char text[256];
    snprintf(text, sizeof text, PATH_HEADER "mesh file %s\n", name);
    scene_error err;
    bool ok = parse(text, 1, s, &err);
    CHECK(ok, "%s: %s", name, ok ? "" : err.message);
    return ok;
}

/* The L's quads written in the scene's space with the material words and keys given. */
static void l_quads_text(char *out, size_t size, const char *material) {
    snprintf(out, size, L_HEADER);
    for (int q = 0; q < L_QUADS; q++) {
        size_t n = strlen(out);
        n += (size_t)snprintf(out + n, size - n, "quad %s", material);
        for (int k = 0; k < 4; k++)
            n += (size_t)snprintf(out + n, size - n, " v%d %g %g %g", k, l_quads[q][k][0],
                                  l_quads[q][k][1], l_quads[q][k][2]);
        snprintf(out + n, size - n, "\n");
    }
}

/* glTF's metallic-roughness factors map to pbr exactly (base colour, metallic, roughness; none
 * warns), and the L of such a file renders bit for bit as its quads written with pbr keys; a
 * factor outside [0, 1] is an error naming the material. A file's Phong material above 1 (MTL
 * Kd 0.8, Ks 0.5) warns in path mode, naming it. */
static void test_bright_materials(void) {
    write_l_files();
    const float bases[2][3] = {{1, 1, 1}, {0.9f, 0.6f, 0.2f}}, metals[3] = {0, 0.5f, 1};
    for (int b = 0; b < 2; b++)
        for (int k = 0; k < 3; k++) {
            char materials[256], gltf[2048];
            snprintf(materials, sizeof materials,
                     "[{\"name\":\"m\",\"pbrMetallicRoughness\":{\"baseColorFactor\":"
                     "[%g,%g,%g,1],\"metallicFactor\":%g,\"roughnessFactor\":0.3}}]",
                     (double)bases[b][0], (double)bases[b][1], (double)bases[b][2],
                     (double)metals[k]);
            gltf_text(gltf, sizeof gltf, materials);
            write_text("metal.gltf", gltf);
            scene s;
            if (!parse_path_mode("metal.gltf", &s)) continue;
            const material *m = triangle_material(&s, &s.triangles[0]);
            CHECK(m->kind == TZ_MATERIAL_PBR && m->color.x == bases[b][0] &&
                      m->color.y == bases[b][1] && m->color.z == bases[b][2] &&
                      m->metallic == metals[k] && m->roughness == 0.3f && m->ior == 1.5f,
                  "base %g metallic %g: kind %d color %g metallic %g roughness %g",
                  (double)bases[b][1], (double)metals[k], m->kind, (double)m->color.y,
                  (double)m->metallic, (double)m->roughness);
            CHECK(s.warning_count == 0, "base %g metallic %g: warned %s", (double)bases[b][1],
                  (double)metals[k], s.warning_count ? s.warnings[0].message : "");
            scene_free(&s);
            char keys[128], quads[8192], text[512];
            snprintf(keys, sizeof keys, "pbr color %g %g %g metallic %g roughness 0.3",
                     (double)bases[b][0], (double)bases[b][1], (double)bases[b][2],
                     (double)metals[k]);
            l_quads_text(quads, sizeof quads, keys);
            snprintf(text, sizeof text, L_HEADER "mesh file metal.gltf\n");
            film want = {0}, got = {0};
            if (render_text("pbr quads", quads, &want) && render_text("metal.gltf", text, &got)) {
                size_t bytes = (size_t)want.width * want.height * 4 * sizeof *want.accum;
                CHECK(got.width == want.width && got.height == want.height &&
                          !memcmp(got.accum, want.accum, bytes),
                      "base %g metallic %g: the glTF's image is not its faces' with pbr keys",
                      (double)bases[b][1], (double)metals[k]);
            }
            film_free(&want);
            film_free(&got);
        }
    char gltf[2048];
    gltf_text(gltf, sizeof gltf,
              "[{\"name\":\"bent\",\"pbrMetallicRoughness\":{\"roughnessFactor\":1.5}}]");
    write_text("bent.gltf", gltf);
    scene s;
    scene_error err;
    bool parsed = parse(L_HEADER "mesh file bent.gltf\n", 1, &s, &err);
    CHECK(!parsed && strstr(err.message, "bent.gltf") && strstr(err.message, "'bent'") &&
              strstr(err.message, "roughness factor is 1.5, outside [0, 1]"),
          "a roughness factor of 1.5: %s", parsed ? "parsed" : err.message);
    if (parsed) scene_free(&s);
    write_text("shiny.mtl", "newmtl shiny\nKd 0.8 0.8 0.8\nKs 0.5 0.5 0.5\nNs 20\n");
    write_text("shiny.obj",
               "mtllib shiny.mtl\nv 0 0 1\nv 1 0 1\nv 0 1 1\nusemtl shiny\n"
               "f 1 2 3\n");
    if (parse_path_mode("shiny.obj", &s)) {
        CHECK(s.warning_count == 1 && s.warnings[0].line == 4 && s.warnings[0].col == 11 &&
                  strstr(s.warnings[0].message,
                         "shiny.obj': its material 'shiny': max(color) "
                         "0.8 + ks 0.5 = 1.3 is above 1"),
              "shiny.obj: %d warnings: %s", s.warning_count,
              s.warning_count ? s.warnings[0].message : "");
        scene_free(&s);
    }
}

/* An octahedron of radius r about (x, y, z) in OBJ (its vertices from `first`, 1-based), wound
 * outward; then an open square (two faces) of material `floor_material` under it. */
static size_t octahedron(char *out, size_t size, double x, double y, double z, double r, int first,
                         const char *material) {
    static const int faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                    {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    size_t n = (size_t)snprintf(out, size,
                                "usemtl %s\nv %g %g %g\nv %g %g %g\nv %g %g %g\nv %g %g %g\n"
                                "v %g %g %g\nv %g %g %g\n",
                                material, x + r, y, z, x - r, y, z, x, y + r, z, x, y - r, z, x, y,
                                z + r, x, y, z - r);
    for (int f = 0; f < 8; f++)
        n += (size_t)snprintf(out + n, size - n, "f %d %d %d\n", first + faces[f][0],
                              first + faces[f][2], first + faces[f][1]);
    return n;
}

/* Six times the signed volume the scene's triangles bound (positive: wound outward). */
static double scene_volume(const scene *s) {
    double volume = 0;
    for (int t = 0; t < s->triangle_count; t++) {
        const vec3 *v = s->triangles[t].v;
        volume += v[0].x * ((double)v[1].y * v[2].z - (double)v[1].z * v[2].y) +
                  v[0].y * ((double)v[1].z * v[2].x - (double)v[1].x * v[2].z) +
                  v[0].z * ((double)v[1].x * v[2].y - (double)v[1].y * v[2].x);
    }
    return volume;
}

/* Glass is checked part by part (faces joined by edges): a closed glass ball beside an open floor
 * in one file loads (OBJ and glTF), so does a glass jar closed by an opaque lid, an open glass
 * pane is refused naming its material, faces and box, and a closed part is wound outward
 * whatever the line's transform (a mirroring scale too). */
static void test_glass_parts(void) {
    write_l_files();
    write_text("parts.mtl",
               "newmtl glass\nKd 1 1 1\nd 0.1\nNi 1.5\n"
               "newmtl floor\nKd 0.5 0.5 0.5\n");
    char obj[4096] = "mtllib parts.mtl\n";
    size_t n = strlen(obj);
    n += octahedron(obj + n, sizeof obj - n, 0, 0, -4, 1, 1, "glass");
    snprintf(obj + n, sizeof obj - n,
             "usemtl floor\nv -5 -1 -9\nv 5 -1 -9\nv 5 -1 1\nv -5 -1 1\nf 7 8 9 10\n");
    write_text("ball_floor.obj", obj);
    n = strlen("mtllib parts.mtl\n");
    n += octahedron(obj + n, sizeof obj - n, 0, 0, -4, 1, 1, "glass");
    snprintf(obj + n, sizeof obj - n, "v -5 -1 -9\nv 5 -1 -9\nv 5 -1 1\nv -5 -1 1\nf 7 8 9 10\n");
    write_text("ball_pane.obj", obj);
    const char *good[] = {"mesh file ball_floor.obj", "mesh file ball_floor.obj scale -1 2 1",
                          "mesh refractive file ball_floor.obj scale 1 -1 1 ior 1.3"};
    for (int k = 0; k < 3; k++) {
        char text[512];
        snprintf(text, sizeof text, PATH_HEADER "%s\n", good[k]);
        scene s;
        scene_error err;
        bool ok = parse(text, 1, &s, &err);
        if (k == 2) {
            CHECK(!ok && err.line == 4 && err.col == 22 &&
                      strstr(err.message,
                             "ball_floor.obj': a refractive part is not closed: 2 "
                             "faces of material 'floor' from face 9, between -5 -1 "
                             "-9 and 5 -1 1;"),
                  "all glass, the floor open: %s", ok ? "parsed" : err.message);
        } else {
            CHECK(ok && s.triangle_count == 10, "%s: %s", good[k], ok ? "" : err.message);
        }
        if (!ok) continue;
        /* the ball alone: its eight faces wound outward */
        s.triangle_count = 8;
        CHECK(scene_volume(&s) > 0.0, "%s: the glass ball is wound inward", good[k]);
        s.triangle_count = 10;
        scene_free(&s);
    }
    /* a glass jar closed by an opaque lid: one closed part, loaded as before */
    write_text("jar.obj",
               "mtllib parts.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\n"
               "v 1 0 1\nv 1 1 1\nv 0 1 1\nusemtl glass\nf 1 4 3 2\nf 5 6 7 8\n"
               "f 1 2 6 5\nf 2 3 7 6\nf 1 5 8 4\nusemtl floor\nf 4 8 7 3\n");
    scene s;
    scene_error err;
    bool ok = parse(PATH_HEADER "mesh file jar.obj\n", 1, &s, &err);
    CHECK(ok && s.triangle_count == 12, "a glass jar with an opaque lid: %s",
          ok ? "" : err.message);
    if (ok) scene_free(&s);
    ok = parse(PATH_HEADER "mesh file ball_pane.obj\n", 1, &s, &err);
    CHECK(!ok && strstr(err.message,
                        "a refractive part is not closed: 2 faces of material "
                        "'glass' from face 9, between -5 -1 -9 and 5 -1 1; its edge"),
          "an open glass pane: %s", ok ? "parsed" : err.message);
    if (ok) scene_free(&s);
    /* glTF: the L's two boxes of glass (KHR_materials_transmission), each closed, rough glass of
     * glTF's default roughness 1, and an open floor of its own material in a second primitive */
    float floor[6][3] = {{-5, -1, -9}, {5, -1, -9}, {5, -1, 1},
                         {-5, -1, -9}, {5, -1, 1},  {-5, -1, 1}};
    tmp_file_write(tmp_path("floor.bin"), floor, sizeof floor);
    char gltf[4096];
    size_t bytes = 2 * L_QUADS * 9 * sizeof(float);
    snprintf(gltf, sizeof gltf,
             "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":"
             "[\"KHR_materials_transmission\"],\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":["
             "{\"attributes\":{\"POSITION\":0},\"material\":0},"
             "{\"attributes\":{\"POSITION\":1},\"material\":1}]}],"
             "\"materials\":[{\"name\":\"glass\",\"extensions\":{\"KHR_materials_transmission\":"
             "{\"transmissionFactor\":1}}},{\"name\":\"floor\",\"pbrMetallicRoughness\":"
             "{\"metallicFactor\":0}}],"
             "\"buffers\":[{\"uri\":\"l.bin\",\"byteLength\":%zu},"
             "{\"uri\":\"floor.bin\",\"byteLength\":%zu}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":%zu},{\"buffer\":1,"
             "\"byteLength\":%zu}],\"accessors\":[{\"bufferView\":0,\"componentType\":5126,"
             "\"count\":%d,\"type\":\"VEC3\",\"min\":[-1,-1,0],\"max\":[1,1,1]},"
             "{\"bufferView\":1,\"componentType\":5126,\"count\":6,\"type\":\"VEC3\","
             "\"min\":[-5,-1,-9],\"max\":[5,-1,1]}]}\n",
             bytes, sizeof floor, bytes, sizeof floor, 2 * L_QUADS * 3);
    write_text("glass_floor.gltf", gltf);
    ok = parse(PATH_HEADER "mesh file glass_floor.gltf\n", 1, &s, &err);
    CHECK(ok && s.triangle_count == 2 * L_QUADS + 2, "glTF glass beside a floor: %s",
          ok ? "" : err.message);
    if (ok) {
        int glass = 0;
        for (int t = 0; t < s.triangle_count; t++)
            glass += triangle_material(&s, &s.triangles[t])->kind == TZ_MATERIAL_DIELECTRIC &&
                     triangle_material(&s, &s.triangles[t])->roughness == 1.0f;
        CHECK(glass == 2 * L_QUADS, "glTF glass beside a floor: %d glass faces", glass);
        scene_free(&s);
    }
}

/* A glTF of one triangle whose material 'Lamp' emits 1 0.5 0.25, with strength 12 when `strong`
 * (KHR_materials_emissive_strength, as Blender exports a strong emitter); its buffer at `uri`,
 * or none (a GLB's own). */
static void lamp_json(char *out, size_t size, bool strong, const char *uri) {
    snprintf(out, size,
             "{\"asset\":{\"version\":\"2.0\"},%s\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
             "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
             "{\"POSITION\":0},\"material\":0}]}],\"materials\":[{\"name\":\"Lamp\","
             "\"emissiveFactor\":[1,0.5,0.25]%s}],\"buffers\":[{%s%s%s\"byteLength\":36}],"
             "\"bufferViews\":[{\"buffer\":0,\"byteLength\":36}],\"accessors\":[{"
             "\"bufferView\":0,\"componentType\":5126,\"count\":3,\"type\":\"VEC3\","
             "\"min\":[0,0,1],\"max\":[1,1,1]}]}",
             strong ? "\"extensionsUsed\":[\"KHR_materials_emissive_strength\"]," : "",
             strong ? ",\"extensions\":{\"KHR_materials_emissive_strength\":"
                      "{\"emissiveStrength\":12}}"
                    : "",
             uri ? "\"uri\":\"" : "", uri ? uri : "", uri ? "\"," : "");
}

/* assimp 5.2.5 reads no emission strength: a glTF (and a GLB) emitter that has one keeps its
 * emissive factor alone, and a warning names the file, the extension and the material; one
 * without the extension warns of nothing. */
static void test_emission_strength(void) {
    const float tri[9] = {0, 0, 1, 1, 0, 1, 0, 1, 1};
    tmp_file_write(tmp_path("tri.bin"), tri, sizeof tri);
    char json[2048];
    lamp_json(json, sizeof json, true, "tri.bin");
    write_text("lamp.gltf", json);
    lamp_json(json, sizeof json, false, "tri.bin");
    write_text("plain_lamp.gltf", json);
    /* the GLB: a header, the JSON chunk padded with spaces, the BIN chunk */
    lamp_json(json, sizeof json, true, NULL);
    uint32_t json_length = (uint32_t)(strlen(json) + 3) / 4 * 4;
    memset(json + strlen(json), ' ', json_length - strlen(json));
    unsigned char glb[4096];
    uint32_t words[5] = {0x46546C67u, 2, 12 + 8 + json_length + 8 + sizeof tri, json_length,
                         0x4E4F534Au};
    memcpy(glb, words, sizeof words);
    memcpy(glb + 20, json, json_length);
    uint32_t bin[2] = {sizeof tri, 0x004E4942u};
    memcpy(glb + 20 + json_length, bin, sizeof bin);
    memcpy(glb + 28 + json_length, tri, sizeof tri);
    tmp_file_write(tmp_path("lamp.glb"), glb, 28 + json_length + sizeof tri);
    const char *files[] = {"lamp.gltf", "lamp.glb", "plain_lamp.gltf"};
    for (int k = 0; k < 3; k++) {
        scene s;
        if (!parse_path_mode(files[k], &s)) continue;
        const material *m = triangle_material(&s, &s.triangles[0]);
        CHECK(m->emission.x == 1.0f && m->emission.y == 0.5f && m->emission.z == 0.25f,
              "%s: emission %g %g %g", files[k], (double)m->emission.x, (double)m->emission.y,
              (double)m->emission.z);
        if (k < 2)
            CHECK(s.warning_count == 1 && s.warnings[0].line == 4 &&
                      strstr(s.warnings[0].message,
                             "its emission strength "
                             "(KHR_materials_emissive_strength, which "
                             "assimp 5.2.5 does not read: material 'Lamp' "
                             "emits its emissive factor alone)"),
                  "%s: %d warnings: %s", files[k], s.warning_count,
                  s.warning_count ? s.warnings[0].message : "");
        else
            CHECK(s.warning_count == 0, "%s: warned %s", files[k],
                  s.warning_count ? s.warnings[0].message : "");
        scene_free(&s);
    }
}

int main(void) {
    if (!tmp_dir_make("test_mesh_import")) {
        printf("cannot make a temporary folder\n");
        return 1;
    }
    CHECK_CASE(test_handedness);
    CHECK_CASE(test_no_material);
    CHECK_CASE(test_bright_materials);
    CHECK_CASE(test_glass_parts);
    CHECK_CASE(test_emission_strength);
    return check_summary("test_mesh_import");
}
