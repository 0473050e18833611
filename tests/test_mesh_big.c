/* test_mesh_big.c: a mesh of more faces than one core takes (mesh_load.c's child gathers them,
 * scene_mesh.c transforms and checks them, on every core) loads as one pass over its faces
 * would: every face in the file's order at its translated corners, the degenerate ones dropped
 * with the first of them named and all counted, and the first non-finite corner or the first
 * face out of the coordinate range reported, wherever in the file they are. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "scene/scene.h"
#include "tmp_dir.h"

/* A grid of COLUMNS x ROWS squares, two triangles each: more faces than mesh_load.c's and
 * scene_mesh.c's thresholds for sharing them among threads (65536). */
#define COLUMNS 300
#define ROWS 150
#define GRID_VERTICES ((COLUMNS + 1) * (ROWS + 1))
#define GRID_FACES (2 * COLUMNS * ROWS)
/* Three corners on a line (a degenerate face), corners at plus and minus infinity and at 1e17
 * and 2e17. */
#define LINE_VERTEX GRID_VERTICES
#define INFINITE_VERTEX (GRID_VERTICES + 3)
#define FAR_VERTEX (GRID_VERTICES + 5)
#define VERTICES (GRID_VERTICES + 7)

/* The camera sees the grid's corner at 1 2 3 (a mesh out of view would warn). */
#define HEADER                                                                     \
    "camera position 1 2 0 direction 0 0 1\nplane width 2 height 2 pixel 0.0625\n" \
    "light position -1 2 0 power 20\n"

/* Corner c of face f of the grid (squares row by row, each as (a, b, d) and (a, d, e)). */
static uint32_t grid_corner(int f, int c) {
    int square = f / 2, i = square % COLUMNS, j = square / COLUMNS;
    uint32_t a = (uint32_t)(j * (COLUMNS + 1) + i), b = a + 1, d = b + COLUMNS + 1,
             e = a + COLUMNS + 1;
    uint32_t first[3] = {a, b, d}, second[3] = {a, d, e};
    return f % 2 ? second[c] : first[c];
}

/* Vertex v's position. */
static void vertex(uint32_t v, float out[3]) {
    if (v < GRID_VERTICES) {
        out[0] = (float)(v % (COLUMNS + 1)) * 0.25f;
        out[1] = (float)(v / (COLUMNS + 1)) * 0.5f;
        out[2] = 0.0f;
    } else if (v < INFINITE_VERTEX) { /* on the line y = x */
        float t = (float)(v - LINE_VERTEX);
        out[0] = out[1] = t, out[2] = 1.0f;
    } else {
        const float far[4] = {INFINITY, -INFINITY, 1e17f, 2e17f};
        out[0] = far[v - INFINITE_VERTEX];
        out[1] = out[2] = 0.0f;
    }
}

/* A binary PLY of the grid whose faces replaced[k] are replaced by faces[k] (corner indices). */
static void write_grid(const char *name, const int *replaced, const uint32_t (*faces)[3], int n) {
    FILE *fp = fopen(tmp_path(name), "wb");
    if (!fp) return;
    fprintf(fp,
            "ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\n"
            "property float y\nproperty float z\nelement face %d\n"
            "property list uchar uint vertex_indices\nend_header\n",
            VERTICES, GRID_FACES);
    for (uint32_t v = 0; v < VERTICES; v++) {
        float p[3];
        vertex(v, p);
        fwrite(p, sizeof p, 1, fp);
    }
    for (int f = 0; f < GRID_FACES; f++) {
        uint32_t corners[3] = {grid_corner(f, 0), grid_corner(f, 1), grid_corner(f, 2)};
        for (int k = 0; k < n; k++)
            if (replaced[k] == f) memcpy(corners, faces[k], sizeof corners);
        unsigned char three = 3;
        fwrite(&three, 1, 1, fp);
        fwrite(corners, sizeof corners, 1, fp);
    }
    fclose(fp);
}

static bool parse(const char *text, scene *s, scene_error *err) {
    return scene_parse_string(text, strlen(text), tmp_path("scene.scene"), s, err);
}

/* Two degenerate faces, one in each half of the file: every other face comes in order at its
 * corners moved by (1, 2, 3), the two dropped, the first of them named (corners mirrored into
 * trazador's space: z negated, corners 0 2 1). */
static void test_order_and_drops(void) {
    const int bad[2] = {1000, GRID_FACES - 7};
    const uint32_t line[2][3] = {{LINE_VERTEX, LINE_VERTEX + 1, LINE_VERTEX + 2},
                                 {LINE_VERTEX + 2, LINE_VERTEX, LINE_VERTEX + 1}};
    write_grid("drops.ply", bad, line, 2);
    scene s;
    scene_error err;
    bool ok = parse(HEADER "mesh lambertian file drops.ply translate 1 2 3\n", &s, &err);
    CHECK(ok, "drops: %s", err.message);
    if (!ok) return;
    CHECK(s.triangle_count == GRID_FACES - 2, "drops: %d triangles, want %d", s.triangle_count,
          GRID_FACES - 2);
    CHECK(s.warning_count == 1 && strstr(s.warnings[0].message, "2 degenerate faces dropped") &&
              strstr(s.warnings[0].message, "the first, face 1001:"),
          "drops: %d warnings, %s", s.warning_count, s.warning_count ? s.warnings[0].message : "");
    int wrong = 0, t = 0;
    for (int f = 0; f < GRID_FACES && t < s.triangle_count; f++) {
        if (f == bad[0] || f == bad[1]) continue;
        for (int c = 0; c < 3; c++) {
            float p[3];
            vertex(grid_corner(f, (3 - c) % 3), p);
            vec3 v = s.triangles[t].v[c];
            wrong += v.x != p[0] + 1.0f || v.y != p[1] + 2.0f || v.z != -p[2] + 3.0f;
        }
        t++;
    }
    CHECK(wrong == 0, "drops: %d corners out of order or moved wrongly", wrong);
    scene_free(&s);
}

/* Faces at[0] and at[1] (at[0] first in the file) take corners at plus and minus infinity, or
 * at 1e17 and 2e17 under `keys`: the error names the first, wherever the two are. */
static void expect_first(const char *name, const char *keys, const int at[2], const char *want) {
    bool far = strstr(want, "coordinate range") != NULL;
    const uint32_t faces[2][3] = {{far ? FAR_VERTEX : INFINITE_VERTEX, 0, 1},
                                  {far ? FAR_VERTEX + 1 : INFINITE_VERTEX + 1, 2, 3}};
    write_grid(name, at, faces, 2);
    char text[512];
    snprintf(text, sizeof text, HEADER "mesh lambertian file %s%s\n", name, keys);
    scene s;
    scene_error err;
    bool ok = parse(text, &s, &err);
    CHECK(!ok && strstr(err.message, want), "%s: %s, want '%s'", name, ok ? "parsed" : err.message,
          want);
    if (ok) scene_free(&s);
}

static void test_first_error(void) {
    /* both late (one share when the faces are shared by two), or one early and one late */
    const int late[2] = {GRID_FACES - 100, GRID_FACES - 3}, apart[2] = {12, GRID_FACES - 5};
    expect_first("infinite_late.ply", "", late, "non-finite position (inf 0 0)");
    expect_first("infinite_apart.ply", "", apart, "non-finite position (inf 0 0)");
    char want[64];
    snprintf(want, sizeof want, "face %d leaves the coordinate range", GRID_FACES - 99);
    expect_first("far_late.ply", " scale 100", late, want);
    expect_first("far_apart.ply", " scale 100", apart, "face 13 leaves the coordinate range");
}

int main(void) {
    if (!tmp_dir_make("test_mesh_big")) {
        printf("cannot make a temporary folder\n");
        return 1;
    }
    CHECK_CASE(test_order_and_drops);
    CHECK_CASE(test_first_error);
    return check_summary("test_mesh_big");
}
