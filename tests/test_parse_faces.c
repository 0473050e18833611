/* test_parse_faces.c: the parser's triangles and quads: every field, defaults, the quad's split,
 * Spanish names, file order among spheres, and the same faces on every thread count. */
#include "parse_check.h"

static bool triangle_at(const triangle *t, vec3 a, vec3 b, vec3 c) {
    return vec_is(t->v[0], a.x, a.y, a.z) && vec_is(t->v[1], b.x, b.y, b.z) &&
           vec_is(t->v[2], c.x, c.y, c.z);
}

/* Triangles and quads: every field, defaults, the quad's split, Spanish names, and spheres and
 * faces kept apart in file order. */
static void test_faces(void) {
    static const char faces[] = BASE
        "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0 1 0\n"
        "sphere mirror center 0 0 9 radius 1\n"
        "triangle phong v2 0 1 2 v0 -1 0 2 n1 3 4 0 v1 1 0 2 n0 0 0 -2 n2 0 0 -1e-30 "
        "color 0.5 0.25 1 ks 0.1 alpha 8\n"
        "quad espejo v0 0 0 0 v1 2 0 0 v2 2 0 2 v3 0 0 2 color 0.9 0.5 0.1\n"
        "triangle lambertiana v0 0 0 0 v1 1 0 0 v2 0 0 1 emission 1 2 3\n"
        "quad mirror v0 -1 -1 5 v1 1 -1 5 v2 1 1 5 v3 -1 1 5\n"
        "triangle espejo v0 0 0 0 v1 1 0 0 v2 0 1 0\n"
        "quad phong v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 ks 1 alpha 0 emission 0 0 0.5\n"
        "sphere lambertian center 0 0 -9 radius 1\n"
        "render mode path\n";
    scene s;
    const char *n = "faces";
    if (!parse_ok(n, BYTES(faces), &s)) return;
    if (!check(s.triangle_count == 10 && s.sphere_count == 2, n, "%d triangles, %d spheres",
               s.triangle_count, s.sphere_count)) {
        scene_free(&s);
        return;
    }
    const triangle *t = s.triangles;
    check(triangle_at(&t[0], v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)) &&
              t[0].normals == TRIANGLE_FLAT &&
              triangle_material(&s, &t[0])->kind == TZ_MATERIAL_LAMBERTIAN &&
              vec_is(triangle_material(&s, &t[0])->color, 0.8f, 0.8f, 0.8f) &&
              triangle_material(&s, &t[0])->ks == 0 && triangle_material(&s, &t[0])->alpha == 0 &&
              triangle_material(&s, &t[0])->ior == 1.0f &&
              vec_is(triangle_material(&s, &t[0])->emission, 0, 0, 0) && !triangle_emits(&s, &t[0]),
          n, "lambertian triangle and its defaults");
    /* Keys in any order; normals of any length normalized, their direction kept. */
    check(triangle_at(&t[1], v3(-1, 0, 2), v3(1, 0, 2), v3(0, 1, 2)) &&
              (t[1].normals != TRIANGLE_FLAT) && vec_is(s.normals[t[1].normals].n[0], 0, 0, -1) &&
              vec_is(s.normals[t[1].normals].n[1], 0.6f, 0.8f, 0) &&
              vec_is(s.normals[t[1].normals].n[2], 0, 0, -1) &&
              triangle_material(&s, &t[1])->kind == TZ_MATERIAL_PHONG &&
              vec_is(triangle_material(&s, &t[1])->color, 0.5f, 0.25f, 1) &&
              triangle_material(&s, &t[1])->ks == 0.1f &&
              triangle_material(&s, &t[1])->alpha == 8.0f &&
              triangle_material(&s, &t[1])->ior == 1.0f,
          n, "phong triangle with normals");
    /* A quad is (v0 v1 v2) then (v0 v2 v3), both with its material. */
    check(triangle_at(&t[2], v3(0, 0, 0), v3(2, 0, 0), v3(2, 0, 2)) &&
              triangle_at(&t[3], v3(0, 0, 0), v3(2, 0, 2), v3(0, 0, 2)),
          n, "quad split");
    for (int k = 2; k <= 3; k++)
        check(triangle_material(&s, &t[k])->kind == TZ_MATERIAL_MIRROR &&
                  vec_is(triangle_material(&s, &t[k])->color, 0.9f, 0.5f, 0.1f) &&
                  t[k].normals == TRIANGLE_FLAT && triangle_material(&s, &t[k])->ks == 0 &&
                  triangle_material(&s, &t[k])->ior == 1.0f,
              n, "espejo quad half %d", k - 2);
    check(triangle_material(&s, &t[4])->kind == TZ_MATERIAL_LAMBERTIAN &&
              vec_is(triangle_material(&s, &t[4])->color, 0.8f, 0.8f, 0.8f) &&
              vec_is(triangle_material(&s, &t[4])->emission, 1, 2, 3) && triangle_emits(&s, &t[4]),
          n, "lambertiana triangle with emission");
    check(triangle_at(&t[5], v3(-1, -1, 5), v3(1, -1, 5), v3(1, 1, 5)) &&
              triangle_at(&t[6], v3(-1, -1, 5), v3(1, 1, 5), v3(-1, 1, 5)) &&
              triangle_material(&s, &t[5])->kind == TZ_MATERIAL_MIRROR &&
              vec_is(triangle_material(&s, &t[5])->color, 1, 1, 1),
          n, "mirror quad");
    check(triangle_material(&s, &t[7])->kind == TZ_MATERIAL_MIRROR &&
              vec_is(triangle_material(&s, &t[7])->color, 1, 1, 1),
          n, "espejo triangle");
    for (int k = 8; k <= 9; k++)
        check(triangle_material(&s, &t[k])->kind == TZ_MATERIAL_PHONG &&
                  triangle_material(&s, &t[k])->ks == 1.0f &&
                  triangle_material(&s, &t[k])->alpha == 0.0f &&
                  vec_is(triangle_material(&s, &t[k])->color, 0.8f, 0.8f, 0.8f) &&
                  vec_is(triangle_material(&s, &t[k])->emission, 0, 0, 0.5f) &&
                  triangle_emits(&s, &t[k]),
              n, "phong quad half %d", k - 8);
    check(vec_is(s.spheres[0].center, 0, 0, 9) && vec_is(s.spheres[1].center, 0, 0, -9), n,
          "spheres among the faces");
    scene_free(&s);
    check(!s.triangles && s.triangle_count == 0, n, "scene_free leaves triangles zeroed");

    /* The tolerances' edges: a quad 0.9e-5 of its diagonal off flat, a face of height 1.1e-5 of
     * its longest edge, faces just inside the sizes single precision can normalize. */
    static const char edges[] = BASE
        "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 1.27e-5\n"
        "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0.5 1.1e-5 0\n"
        "triangle lambertian v0 0 0 0 v1 4e-10 0 0 v2 0 4e-10 0\n"
        "triangle lambertian v0 0 0 0 v1 3.6e9 0 0 v2 0 3.6e9 0\n"
        "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 -0.5 0.5 0\n"
        "triangle mirror v0 1e9 1e9 -1e9 v1 -1e9 1e9 -1e9 v2 1e9 -1e9 -1e9\n";
    n = "face tolerances";
    if (parse_ok(n, BYTES(edges), &s)) {
        check(s.triangle_count == 8, n, "%d triangles", s.triangle_count);
        scene_free(&s);
    }
}

/* A text of several MB mixing spheres, triangles (some smooth, some emitting) and quads: any
 * thread count gives the faces in file order, bit for bit, and the same first error. */
static void test_chunks_faces(void) {
    int lines = 40000;
    size_t size = (size_t)lines * 128, used = 0;
    char *text = malloc(size);
    size_t *line_at = malloc(((size_t)lines + 1) * sizeof *line_at);
    for (int k = 1; k <= lines; k++) {
        line_at[k - 1] = used;
        const char *line = "";
        char buffer[128];
        if (k == 1) {
            line = "camera position 0 0 0";
        } else if (k == 2) {
            line = "plane width 4 height 3 pixel 0.01";
        } else if (k == 3) {
            line = "render mode path";
        } else if (k % 101 == 0) {
            line = "# comment";
        } else if (k % 3 == 0) {
            snprintf(buffer, sizeof buffer, "sphere phong center %d.5 %d 9 radius 0.25", k % 1000,
                     k % 17);
            line = buffer;
        } else if (k % 3 == 1) {
            snprintf(buffer, sizeof buffer, "triangle mirror v0 %d 0 0 v1 %d.5 0 1 v2 0 %d 2%s%s",
                     k, k, k % 97 + 1, k % 7 ? "" : " n0 0 0 1 n1 0 1 1 n2 1 0.5 0",
                     k % 11 ? "" : " emission 1 1 1");
            line = buffer;
        } else {
            snprintf(buffer, sizeof buffer,
                     "quad lambertiana v0 0 0 %d v1 %d 0 %d v2 %d 1 %d v3 0 1 %d color 0.5 0.5 0.5",
                     k, k % 50 + 1, k, k % 50 + 1, k, k);
            line = buffer;
        }
        used += (size_t)snprintf(text + used, size - used, "%s\n", line);
    }
    line_at[lines] = used;
    scene s;
    scene_error err;
    const char *name = "chunks of mixed primitives";
    if (check(parse_all_threads(name, text, used, &err, &s), name, "%d:%d %s", err.line, err.col,
              err.message)) {
        /* Lines 3k+1 are triangles, 3k+2 quads (both halves): file order, halves in order. */
        int expected = 0;
        for (int k = 4; k <= lines; k++)
            if (k % 101 && k % 3 != 0) expected += k % 3 == 1 ? 1 : 2;
        check(s.triangle_count == expected && s.triangles[0].v[0].x == 4.0f &&
                  s.triangles[1].v[0].z == 5.0f && s.triangles[2].v[0].z == 5.0f &&
                  s.triangles[2].v[1].x == 6.0f &&
                  s.triangles[s.triangle_count - 1].v[0].x == (float)lines,
              name, "%d triangles, expected %d", s.triangle_count, expected);
        scene_free(&s);
    }
    /* A bad face late, found by a chunk parsed ahead, and a face emitting in report mode. */
    char *bad = malloc(used + 1);
    const struct {
        int line;
        const char *text, *message;
        int col;
    } cases[] = {
        {29999, "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0.5 0.5 1", "quad is not flat", 40},
        {20002, "triangle mirror v0 0 0 0 v1 1 1 1 v2 2 2 2", "triangle is degenerate", 1},
        {3, "render seed 2", "emission needs path mode", 0},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        memcpy(bad, text, used);
        replace_line(bad, line_at, cases[c].line, cases[c].text);
        char case_name[96];
        snprintf(case_name, sizeof case_name, "%s, '%s' at line %d", name, cases[c].text,
                 cases[c].line);
        bool ok = parse_all_threads(case_name, bad, used, &err, &s);
        /* in report mode the first emitting triangle (line 22: 3k+1 and a multiple of 11) fails */
        int line = cases[c].col ? cases[c].line : 22;
        check(!ok && err.line == line && (!cases[c].col || err.col == cases[c].col) &&
                  strstr(err.message, cases[c].message),
              case_name, "%d:%d %s", err.line, err.col, err.message);
        if (ok) scene_free(&s);
    }
    free(bad);
    free(line_at);
    free(text);
}

int main(void) {
    test_faces();
    test_chunks_faces();
    return parse_check_summary("test_parse_faces");
}
