/* test_mesh_smooth.c: the normals `mesh ... smooth on` generates where a file has none
 * (src/scene/mesh_smooth.c): a cube stays flat, a tessellated sphere turns round, faces meeting at
 * under 60 degrees share their corner's normal and faces meeting at more do not, a file's own
 * normals and degenerate faces are left alone, the centres of big fans get theirs, and models
 * loaded through assimp get them, a torus of shared vertices its exact normals within 1.5
 * degrees. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "scene/mesh_load.h"
#include "tmp_dir.h"

#define ANGLE 60.0f
#define PI 3.14159265358979323846

static mesh_face face_of(vec3 a, vec3 b, vec3 c) {
    mesh_face f;
    memset(&f, 0, sizeof f);
    f.v[0] = a, f.v[1] = b, f.v[2] = c;
    return f;
}

static vec3 unit_normal(const mesh_face *f) {
    return v3_normalize(v3_cross(v3_sub(f->v[1], f->v[0]), v3_sub(f->v[2], f->v[0])));
}

static bool near3(vec3 a, vec3 b, float tol) {
    return fabsf(a.x - b.x) <= tol && fabsf(a.y - b.y) <= tol && fabsf(a.z - b.z) <= tol;
}

static bool smooth(mesh_face *faces, size_t count) {
    mesh m = {.faces = faces, .face_count = count};
    return mesh_smooth_normals(&m, ANGLE);
}

/* A unit cube wound outward, 12 faces: every corner keeps its own face's normal. */
static void test_cube(void) {
    static const float p[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                                  {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    static const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                    {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
    mesh_face faces[12];
    for (int q = 0; q < 6; q++) {
        vec3 c[4];
        for (int k = 0; k < 4; k++)
            c[k] = v3(p[quads[q][k]][0], p[quads[q][k]][1], p[quads[q][k]][2]);
        faces[2 * q] = face_of(c[0], c[1], c[2]);
        faces[2 * q + 1] = face_of(c[0], c[2], c[3]);
    }
    EXPECT(smooth(faces, 12));
    for (int f = 0; f < 12; f++)
        for (int k = 0; k < 3; k++) EXPECT(near3(faces[f].n[k], unit_normal(&faces[f]), 0.0f));
}

/* A UV sphere of RINGS x SEGMENTS: every corner's normal within a degree of the radius. */
#define RINGS 24
#define SEGMENTS 48
static vec3 sphere_point(int ring, int segment) {
    if (ring == 0 || ring == RINGS) return v3(0.0f, ring ? -1.0f : 1.0f, 0.0f); /* one pole */
    double theta = PI * ring / RINGS, phi = 2.0 * PI * (segment % SEGMENTS) / SEGMENTS;
    return v3((float)(sin(theta) * cos(phi)), (float)cos(theta), (float)(sin(theta) * sin(phi)));
}

static void test_sphere(void) {
    static mesh_face faces[2 * RINGS * SEGMENTS];
    size_t n = 0;
    for (int r = 0; r < RINGS; r++)
        for (int s = 0; s < SEGMENTS; s++) {
            vec3 a = sphere_point(r, s), b = sphere_point(r, s + 1);
            vec3 c = sphere_point(r + 1, s + 1), d = sphere_point(r + 1, s);
            if (r > 0) faces[n++] = face_of(a, b, c); /* outward */
            if (r < RINGS - 1) faces[n++] = face_of(a, c, d);
        }
    EXPECT(smooth(faces, n));
    float worst = 1.0f;
    for (size_t f = 0; f < n; f++)
        for (int k = 0; k < 3; k++) {
            float d = v3_dot(faces[f].n[k], v3_normalize(faces[f].v[k]));
            worst = d < worst ? d : worst;
        }
    CHECK(worst > cosf(1.0f * (float)PI / 180.0f), "sphere: worst cosine %.6f", (double)worst);
}

/* Two faces on the x axis hinged by `degrees` between their normals. */
static void hinge(float degrees, mesh_face faces[2]) {
    float a = degrees * (float)PI / 180.0f;
    vec3 o = v3(0, 0, 0), x = v3(1, 0, 0);
    faces[0] = face_of(o, x, v3(0, 1, 0)); /* normal +z */
    faces[1] = face_of(x, o, v3(0, -cosf(a), sinf(a)));
}

static void test_angle(void) {
    mesh_face faces[2];
    hinge(50.0f, faces); /* under 60: the hinge's corners take the mean of both normals */
    EXPECT(smooth(faces, 2));
    vec3 mean = v3_normalize(v3_add(unit_normal(&faces[0]), unit_normal(&faces[1])));
    EXPECT(near3(faces[0].n[0], mean, 1e-6f) && near3(faces[0].n[1], mean, 1e-6f));
    EXPECT(near3(faces[1].n[0], mean, 1e-6f) && near3(faces[1].n[1], mean, 1e-6f));
    EXPECT(near3(faces[0].n[2], unit_normal(&faces[0]), 0.0f)); /* alone at its position */
    hinge(70.0f, faces);                                        /* over 60: each keeps its own */
    EXPECT(smooth(faces, 2));
    for (int f = 0; f < 2; f++)
        for (int k = 0; k < 3; k++) EXPECT(near3(faces[f].n[k], unit_normal(&faces[f]), 0.0f));
}

/* A file's normals stay; a degenerate face keeps none and changes no neighbour; -0 is 0. */
static void test_kept(void) {
    mesh_face faces[3];
    hinge(30.0f, faces);
    faces[0].v[0] = v3(-0.0f, 0.0f, -0.0f);
    faces[1].n[0] = faces[1].n[1] = faces[1].n[2] = v3(0, 0.6f, 0.8f);
    faces[2] = face_of(v3(0, 0, 0), v3(1, 0, 0), v3(2, 0, 0));
    EXPECT(smooth(faces, 3));
    vec3 mean = v3_normalize(v3_add(unit_normal(&faces[0]), unit_normal(&faces[1])));
    EXPECT(near3(faces[0].n[0], mean, 1e-6f) && near3(faces[0].n[1], mean, 1e-6f));
    for (int k = 0; k < 3; k++) {
        EXPECT(near3(faces[1].n[k], v3(0, 0.6f, 0.8f), 0.0f));
        EXPECT(near3(faces[2].n[k], v3(0, 0, 0), 0.0f));
    }
}

/* The centre of a fan of FAN_FACES faces: a flat disc's corners there take its normal (all
 * faces within half the angle of their mean), a cone's of 45-degree slope each take the faces
 * within the angle of its own (tilted toward the axis, not the cone's mean). */
#define FAN_FACES 1000
static void test_fan(void) {
    static mesh_face faces[FAN_FACES];
    for (float height = 0.0f; height <= 1.0f; height += 1.0f) {
        for (int f = 0; f < FAN_FACES; f++) {
            double a = 2 * PI * f / FAN_FACES, b = 2 * PI * (f + 1) / FAN_FACES;
            faces[f] = face_of(v3(0, height, 0), v3((float)cos(b), 0, (float)sin(b)),
                               v3((float)cos(a), 0, (float)sin(a)));
        }
        EXPECT(smooth(faces, FAN_FACES));
        int wrong = 0;
        for (int f = 0; f < FAN_FACES; f++) {
            vec3 own = unit_normal(&faces[f]), n = faces[f].n[0];
            if (height == 0.0f)
                wrong += !near3(n, own, 1e-6f);
            else
                wrong += !(v3_dot(n, own) > cosf((float)PI / 4.0f) && n.y > own.y + 0.1f);
        }
        CHECK(wrong == 0, "fan of height %g: %d centre normals wrong", (double)height, wrong);
    }
}

/* The 50-degree hinge of test_angle as a file without normals, through assimp: smooth on
 * generates them, smooth off leaves none. PLY shares each corner between faces as one vertex, of
 * which assimp's own GenSmoothNormals kept one face's normal (16 degrees off on average on a
 * 24 x 12 torus); OBJ gives each face corners of its own. */
static void expect_hinge_file(const char *name, const char *text) {
    FILE *fp = fopen(tmp_path(name), "w");
    if (!fp) {
        CHECK(0, "cannot write %s", tmp_path(name));
        return;
    }
    fputs(text, fp);
    fclose(fp);
    mesh m;
    char error[512];
    CHECK(mesh_load(tmp_path(name), true, &m, error, sizeof error), "%s: %s", name, error);
    CHECK(m.face_count == 2, "%s: %zu faces", name, m.face_count);
    if (m.face_count == 2) {
        vec3 mean = v3_normalize(v3_add(unit_normal(&m.faces[0]), unit_normal(&m.faces[1])));
        /* (the hinge is each face's first two corners in the file, 0 and 2 once the faces are
         * mirrored into trazador's space and their winding flipped) */
        CHECK(near3(m.faces[0].n[0], mean, 1e-6f) && near3(m.faces[0].n[2], mean, 1e-6f) &&
                  near3(m.faces[1].n[0], mean, 1e-6f) && near3(m.faces[1].n[2], mean, 1e-6f),
              "%s: the hinge's corners are not the mean of its faces' normals", name);
    }
    mesh_free(&m);
    CHECK(mesh_load(tmp_path(name), false, &m, error, sizeof error), "%s: %s", name, error);
    for (size_t f = 0; f < m.face_count; f++)
        for (int k = 0; k < 3; k++) EXPECT(near3(m.faces[f].n[k], v3(0, 0, 0), 0.0f));
    mesh_free(&m);
    remove(tmp_path(name));
}

/* A torus of TORUS_U x TORUS_V quads (radii 1 and TORUS_R about the y axis) as a PLY of shared
 * vertices: every generated normal within a degree and a half of the exact one (0.67 at worst
 * here; assimp's own step, 16.6). */
#define TORUS_U 24
#define TORUS_V 12
#define TORUS_R 0.4
static void test_torus(void) {
    FILE *fp = fopen(tmp_path("torus.ply"), "w");
    if (!fp) {
        CHECK(0, "cannot write %s", tmp_path("torus.ply"));
        return;
    }
    fprintf(fp,
            "ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
            "property float z\nelement face %d\nproperty list uchar int vertex_indices\n"
            "end_header\n",
            TORUS_U * TORUS_V, 2 * TORUS_U * TORUS_V);
    for (int i = 0; i < TORUS_U; i++)
        for (int j = 0; j < TORUS_V; j++) {
            double a = 2 * PI * i / TORUS_U, b = 2 * PI * j / TORUS_V, ring = 1 + TORUS_R * cos(b);
            fprintf(fp, "%.7f %.7f %.7f\n", ring * cos(a), TORUS_R * sin(b), ring * sin(a));
        }
    for (int i = 0; i < TORUS_U; i++)
        for (int j = 0; j < TORUS_V; j++) {
            int p = i * TORUS_V + j, q = (i + 1) % TORUS_U * TORUS_V + j;
            int s = (i + 1) % TORUS_U * TORUS_V + (j + 1) % TORUS_V,
                t = i * TORUS_V + (j + 1) % TORUS_V;
            fprintf(fp, "3 %d %d %d\n3 %d %d %d\n", p, t, s, p, s, q);
        }
    fclose(fp);
    mesh m;
    char error[512];
    CHECK(mesh_load(tmp_path("torus.ply"), true, &m, error, sizeof error), "torus: %s", error);
    float worst = 1.0f;
    for (size_t f = 0; f < m.face_count; f++)
        for (int k = 0; k < 3; k++) {
            vec3 p = m.faces[f].v[k];
            float a = atan2f(p.z, p.x);
            vec3 exact = v3_normalize(v3(p.x - cosf(a), p.y, p.z - sinf(a)));
            float d = v3_dot(m.faces[f].n[k], exact);
            worst = d < worst ? d : worst;
        }
    CHECK(m.face_count == 2 * TORUS_U * TORUS_V, "torus: %zu faces", m.face_count);
    CHECK(worst > cosf(1.5f * (float)PI / 180.0f), "torus: worst cosine %.6f", (double)worst);
    mesh_free(&m);
    remove(tmp_path("torus.ply"));
}

static void test_load(void) {
    const char *vertices = "0 0 0\n1 0 0\n0 1 0\n0 -0.6427876 0.7660444\n";
    char text[512];
    snprintf(text, sizeof text,
             "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
             "property float z\nelement face 2\nproperty list uchar int vertex_indices\n"
             "end_header\n%s3 0 1 2\n3 1 0 3\n",
             vertices);
    expect_hinge_file("hinge.ply", text);
    expect_hinge_file("hinge.obj",
                      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -0.6427876 0.7660444\n"
                      "f 1 2 3\nf 2 1 4\n");
}

int main(void) {
    if (!tmp_dir_make("test_mesh_smooth")) return 1;
    CHECK_CASE(test_cube);
    CHECK_CASE(test_sphere);
    CHECK_CASE(test_angle);
    CHECK_CASE(test_kept);
    CHECK_CASE(test_fan);
    CHECK_CASE(test_load);
    CHECK_CASE(test_torus);
    remove(tmpdir);
    return check_summary("test_mesh_smooth");
}
