/* emitter_pack.c: path mode's emitter table (struct gpu_emitter, shaders/shared_layout.h): the
 * emitting spheres and faces, the environment map and the sun's disc, each picked in proportion
 * to its power (DESIGN section 3.6). */
#include <math.h>
#include <string.h>

#include "render/scene_pack.h"
#include "util/big_memory.h"
#include "util/log.h"

/* The mean of an emission's channels, as double. */
static double emission_mean(vec3 e) { return ((double)e.x + e.y + e.z) / 3.0; }

/* A triangle's area, in double. */
static double triangle_area(const triangle *t) {
    double e1[3] = {t->v[1].x - (double)t->v[0].x, t->v[1].y - (double)t->v[0].y,
                    t->v[1].z - (double)t->v[0].z};
    double e2[3] = {t->v[2].x - (double)t->v[0].x, t->v[2].y - (double)t->v[0].y,
                    t->v[2].z - (double)t->v[0].z};
    double c[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                   e1[0] * e2[1] - e1[1] * e2[0]};
    return 0.5 * sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
}

/* The power an emitter is picked by, in units of a sphere's r^2 mean(Le) (its flux over 4 pi^2):
 * a two-sided triangle of area A emits 2 pi A Le, so A mean(Le) / (2 pi). */
static double sphere_power(const scene *s, const sphere *sp) {
    return (double)sp->radius * sp->radius * emission_mean(sphere_material(s, sp)->emission);
}
static double triangle_power(const scene *s, const triangle *t) {
    return triangle_area(t) * emission_mean(triangle_material(s, t)->emission) /
           (2.0 * 3.14159265358979323846);
}

/* Appends emitter slot `slot` for primitive id (uint bits in primitive_cdf.x). */
static void put_emitter(packed_scene *out, uint32_t slot, uint32_t id, vec3 emission, double power,
                        double running, double total, uint32_t n, float area) {
    float index_bits;
    memcpy(&index_bits, &id, sizeof index_bits);
    out->emitters[slot] = (struct gpu_emitter){
        .emission_pick = vec4_from(emission, (float)(power / total)),
        .primitive_cdf = {index_bits, slot + 1 == n ? 1.0f : (float)(running / total), area, 0},
    };
}

double emitter_scene_radius(const scene *s) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int k = 0; k < s->sphere_count; k++) {
        const sphere *sp = &s->spheres[k];
        const float c[3] = {sp->center.x, sp->center.y, sp->center.z};
        for (int a = 0; a < 3; a++)
            lo[a] = fmin(lo[a], (double)c[a] - sp->radius),
            hi[a] = fmax(hi[a], (double)c[a] + sp->radius);
    }
    for (int k = 0; k < s->triangle_count; k++)
        for (int v = 0; v < 3; v++) {
            const vec3 p = s->triangles[k].v[v];
            const float c[3] = {p.x, p.y, p.z};
            for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], c[a]), hi[a] = fmax(hi[a], c[a]);
        }
    double d2 = 0.0;
    for (int a = 0; a < 3; a++) d2 += hi[a] > lo[a] ? (hi[a] - lo[a]) * (hi[a] - lo[a]) : 0.0;
    return d2 > 0.0 ? 0.5 * sqrt(d2) : 1.0;
}

/* The emitters of path mode from the spheres, then the triangles, in their final (BVH) order
 * (a sphere's emitter holds its index in the scene until here, triangle_source[t] the scene
 * index of triangle t), then the environment map (env_power: the scene's radius squared times
 * its mean radiance, a sphere's unit, as pbrt-v4's infinite lights), then the sun's disc
 * (light_pack.c): each emitter is picked in
 * proportion to its power (sphere_power, triangle_power), the shares summed in double; a sphere's
 * emitter becomes its emitter's slot + 1 or 0, an emitting triangle's v2.w (0 from pack_triangles)
 * its slot + 1. False (logged) on out-of-memory. */
bool emitters_pack(packed_scene *out, const scene *sc, bool path_mode,
                   const uint32_t *triangle_source, double env_power, const sun_disc *sun) {
    uint32_t count = (uint32_t)sc->sphere_count, triangles = (uint32_t)sc->triangle_count, n = 0;
    double total = 0.0;
    if (path_mode && env_power > 0.0) total += env_power, n++;
    if (sun->power > 0.0) total += sun->power, n++;
    for (uint32_t k = 0; path_mode && k < count; k++) {
        double power = sphere_power(sc, &sc->spheres[k]);
        if (power > 0.0) total += power, n++;
    }
    for (uint32_t k = 0; path_mode && k < triangles; k++) {
        double power = triangle_power(sc, &sc->triangles[k]);
        if (power > 0.0) total += power, n++;
    }
    out->emitters = big_calloc(n ? n : 1, sizeof *out->emitters);
    if (!out->emitters) {
        log_error("out of memory packing %u emitters", n);
        return false;
    }
    double running = 0.0;
    uint32_t slot = 0;
    for (uint32_t k = 0; k < count; k++) {
        struct gpu_sphere *g = &out->spheres[k];
        const sphere *sp = &sc->spheres[(uint32_t)g->emitter];
        double power = sphere_power(sc, sp);
        g->emitter = 0.0f;
        if (!path_mode || !(power > 0.0)) continue;
        running += power;
        put_emitter(out, slot, k, sphere_material(sc, sp)->emission, power, running, total, n,
                    0.0f);
        g->emitter = (float)++slot;
    }
    /* A triangle's v2.w is 0 from pack_triangles; report mode has no emitters to look up (the
     * scene's triangles in BVH order are scattered reads). */
    for (uint32_t k = 0; path_mode && k < triangles; k++) {
        const triangle *t = &sc->triangles[triangle_source[k]];
        double power = triangle_power(sc, t);
        if (!(power > 0.0)) continue;
        running += power;
        put_emitter(out, slot, count + k, triangle_material(sc, t)->emission, power, running, total,
                    n, (float)triangle_area(t));
        out->triangles[k].v2.w = (float)++slot;
    }
    if (path_mode && env_power > 0.0) {
        running += env_power;
        put_emitter(out, slot, TZ_ENV_PRIMITIVE, v3(0, 0, 0), env_power, running, total, n, 0.0f);
        out->frame.env_slot = ++slot;
    }
    if (sun->power > 0.0) {
        running += sun->power;
        put_emitter(out, slot, TZ_SUN_PRIMITIVE, sun->radiance, sun->power, running, total, n,
                    0.0f);
        out->frame.sun_slot = ++slot;
    }
    out->frame.emitter_count = n;
    return true;
}
