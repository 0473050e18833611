/* test_digest.c: the scene digest of a part's metadata (render_part_meta), which merge and resume
 * compare: a sphere-only scene keeps the value it had before triangles existed, and every field
 * of a triangle changes it. */
#include <string.h>

#include "check.h"
#include "render/part.h"
#include "render/render.h"
#include "scene/scene.h"

/* The digest of scene s rendered with its own settings. */
static void scene_digest(const scene *s, char out[sizeof(((part_meta *)0)->digest)]) {
    render_opts opts;
    render_opts_from_scene(s, &opts);
    part_meta m;
    render_part_meta(s, &opts, &m);
    memcpy(out, m.digest, sizeof m.digest);
}

/* A sphere-only scene keeps the digest it had before triangles existed (its parts still merge);
 * a triangle changes it, and so does a change to any field of a triangle. */
static void test_digest(void) {
    static const char text[] =
        "camera position 0 1 -8\nplane width 4 height 3 pixel 0.01\n"
        "light position -2 3 -1 power 60\n"
        "sphere phong center -1 0 2 radius 1 color 0.6 0.1 0.1 ks 0.3 alpha 40\n";
    scene s;
    scene_error err;
    if (!scene_parse_string(text, sizeof text - 1, "digest.scene", &s, &err)) {
        CHECK(false, "%s", err.message);
        return;
    }
    char spheres[sizeof(((part_meta *)0)->digest)], faces[sizeof spheres], other[sizeof spheres];
    scene_digest(&s, spheres);
    /* the value the digest had before the scene gained triangles (commit adbf42e) */
    CHECK(!strcmp(spheres, "f73fd51f075a1740"), "sphere-only digest %s", spheres);
    /* the sphere's material, then the face's */
    material *parsed = s.materials, both[2] = {s.materials[0], {0}};
    material *m = &both[1];
    *m = (material){.kind = TZ_MATERIAL_LAMBERTIAN, .color = {0.8f, 0.8f, 0.8f}, .ior = 1.0f};
    face_normals n = {.n = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}}};
    triangle t = {.v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, .material = 1, .normals = TRIANGLE_FLAT};
    s.triangles = &t;
    s.triangle_count = 1;
    s.materials = both;
    s.material_count = 2;
    s.normals = &n;
    s.normals_count = 1;
    scene_digest(&s, faces);
    CHECK(strcmp(faces, spheres), "a triangle leaves the digest %s", faces);
    /* every float of the face and its material */
    float *fields[] = {&t.v[0].x,      &t.v[0].y,      &t.v[0].z,     &t.v[1].x, &t.v[1].y,
                       &t.v[1].z,      &t.v[2].x,      &t.v[2].y,     &t.v[2].z, &m->color.x,
                       &m->color.y,    &m->color.z,    &m->ks,        &m->alpha, &m->ior,
                       &m->emission.x, &m->emission.y, &m->emission.z};
    for (size_t k = 0; k < sizeof fields / sizeof fields[0]; k++) {
        float kept = *fields[k];
        *fields[k] = kept + 0.5f;
        scene_digest(&s, other);
        CHECK(strcmp(other, faces), "triangle float %zu leaves the digest", k);
        *fields[k] = kept;
    }
    m->kind = TZ_MATERIAL_PHONG;
    scene_digest(&s, other);
    CHECK(strcmp(other, faces), "material leaves the digest");
    m->kind = TZ_MATERIAL_LAMBERTIAN;
    /* shading normals, then each of their floats */
    char smooth[sizeof spheres];
    t.normals = 0;
    scene_digest(&s, smooth);
    CHECK(strcmp(smooth, faces), "smooth leaves the digest");
    for (int c = 0; c < 3; c++) {
        float *axis[] = {&n.n[c].x, &n.n[c].y, &n.n[c].z};
        for (int a = 0; a < 3; a++) {
            float kept = *axis[a];
            *axis[a] = kept + 0.5f;
            scene_digest(&s, other);
            CHECK(strcmp(other, smooth), "normal %d axis %d leaves the digest", c, a);
            *axis[a] = kept;
        }
    }
    t.normals = TRIANGLE_FLAT;
    scene_digest(&s, other);
    CHECK(!strcmp(other, faces), "the digest is not a function of the fields: %s, %s", other,
          faces);
    s.triangles = NULL, s.materials = parsed, s.normals = NULL;
    s.triangle_count = s.normals_count = 0;
    s.material_count = 1;
    scene_free(&s);
}

/* Scenes whose parts an older trazador estimated differently have digests of their own, so that
 * those parts do not merge with newer ones: one with a smooth mirror face since such faces turn
 * rays about their shading normals, and every scene with faces since their hits are placed on
 * the faces' planes (the sphere-only value of test_digest stays). The values are those trazador
 * gave before and after. */
static void test_smooth_specular(void) {
    static const char flat[] =
        "camera position 0 1 -8\nplane width 4 height 3 pixel 0.5\n"
        "light position -2 3 -1 power 60\n"
        "triangle mirror v0 0 0 0 v1 1 0 0 v2 0 1 0\n";
    static const char smooth[] =
        "camera position 0 1 -8\nplane width 4 height 3 pixel 0.5\n"
        "light position -2 3 -1 power 60\n"
        "triangle mirror v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 0 0 1 n1 0 0 1 "
        "n2 0 0 1\n";
    const char *texts[] = {flat, smooth}, *want[] = {"354454a9e16f4d8e", "4d64500355413c88"};
    for (int k = 0; k < 2; k++) {
        scene s;
        scene_error err;
        if (!scene_parse_string(texts[k], strlen(texts[k]), "digest.scene", &s, &err)) {
            CHECK(false, "%s", err.message);
            continue;
        }
        char digest[sizeof(((part_meta *)0)->digest)];
        scene_digest(&s, digest);
        CHECK(!strcmp(digest, want[k]), "%s mirror face: digest %s, want %s (before: %s)",
              k ? "smooth" : "flat", digest, want[k],
              k ? "26a37dacc5047b8b, c65b672458420829" : "ab83d500be02c7cd");
        scene_free(&s);
    }
}

int main(void) {
    CHECK_CASE(test_digest);
    CHECK_CASE(test_smooth_specular);
    return check_summary("test_digest");
}
