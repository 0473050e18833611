/* mesh_smooth.c: normals for the corners a model file gives none (`mesh ... smooth on`): the
 * faces that meet at a corner's position (mesh_corner_bits) are found through a hash table, and
 * the corner takes the mean of the unit normals of those that meet its own face at under the
 * smoothing angle, its own included: assimp's GenSmoothNormals rule, without that step's slow
 * search by distance or its one normal per shared vertex (docs/DESIGN.md, section 3.4). */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"

#define NO_CORNER UINT32_MAX
/* link_positions asks for the table slot of the corner this many ahead. */
#define AHEAD 16
/* Rings of more corners than this take smooth_coherent_ring's way where they can. */
#define BIG_RING 64

static uint32_t position_hash(const uint32_t b[3]) {
    uint32_t h = b[0] * 0x9e3779b1u ^ b[1] * 0x85ebca77u ^ b[2] * 0xc2b2ae3du;
    h ^= h >> 15;
    h *= 0x2c1b3c6du;
    return h ^ (h >> 13);
}

static vec3 corner(const mesh *m, uint32_t c) { return m->faces[c / 3].v[c % 3]; }

/* The unit normal of face f by its winding, zero for a degenerate face. */
static vec3 face_normal(const mesh_face *f) {
    vec3 n = v3_cross(v3_sub(f->v[1], f->v[0]), v3_sub(f->v[2], f->v[0]));
    float length = v3_length(n);
    return length > 0.0f && isfinite(length) ? v3_scale(n, 1.0f / length) : v3(0, 0, 0);
}

/* Links the corners of each position into a ring (next), through a hash table of each
 * position's first corner (capacity a power of two, NO_CORNER where empty). */
static void link_positions(const mesh *m, uint32_t corners, uint32_t *table, uint32_t mask,
                           uint32_t *next) {
    for (uint32_t c = 0; c < corners; c++) {
        uint32_t bits[3], other[3];
        if (c + AHEAD < corners) { /* the table is far bigger than the caches */
            mesh_corner_bits(corner(m, c + AHEAD), bits);
            __builtin_prefetch(&table[position_hash(bits) & mask]);
        }
        mesh_corner_bits(corner(m, c), bits);
        next[c] = c;
        for (uint32_t slot = position_hash(bits) & mask;; slot = (slot + 1) & mask) {
            uint32_t first = table[slot];
            if (first == NO_CORNER) {
                table[slot] = c;
                break;
            }
            mesh_corner_bits(corner(m, first), other);
            if (!memcmp(bits, other, sizeof bits)) {
                next[c] = next[first];
                next[first] = c;
                break;
            }
        }
    }
}

/* The normal of corner c, which has none, from the ring of corners at its position. */
static vec3 smooth_corner(const vec3 *normals, const uint32_t *next, uint32_t c, float min_cos) {
    vec3 own = normals[c / 3], sum = own;
    for (uint32_t d = next[c]; d != c; d = next[d])
        if (v3_dot(own, normals[d / 3]) >= min_cos) sum = v3_add(sum, normals[d / 3]);
    float length = v3_length(sum);
    return length > 0.0f ? v3_scale(sum, 1.0f / length) : own;
}

/* Whether corner c's ring holds more than BIG_RING corners. */
static bool big_ring(const uint32_t *next, uint32_t c) {
    uint32_t d = next[c];
    for (int k = 0; k < BIG_RING && d != c; k++) d = next[d];
    return d != c;
}

/* A big ring (a fan's centre, where smooth_corner's loops would be quadratic in the fan's faces)
 * whose faces' normals all lie within half the angle of their mean: every two then meet at under
 * the angle, so each corner without a normal takes that mean. False, nothing written, when they
 * do not. */
static bool smooth_coherent_ring(mesh *m, const vec3 *normals, const uint32_t *next, uint32_t c,
                                 float half_cos) {
    vec3 sum = normals[c / 3];
    for (uint32_t d = next[c]; d != c; d = next[d]) sum = v3_add(sum, normals[d / 3]);
    float length = v3_length(sum);
    if (!(length > 0.0f)) return false;
    vec3 mean = v3_scale(sum, 1.0f / length);
    uint32_t d = c;
    do {
        if (!v3_is_zero(normals[d / 3]) && !(v3_dot(normals[d / 3], mean) >= half_cos))
            return false;
        d = next[d];
    } while (d != c);
    do {
        vec3 *n = &m->faces[d / 3].n[d % 3];
        if (v3_is_zero(*n) && !v3_is_zero(normals[d / 3])) *n = mean;
        d = next[d];
    } while (d != c);
    return true;
}

bool mesh_smooth_normals(mesh *m, float max_angle_degrees) {
    if (m->face_count > (NO_CORNER - 1) / 3) return false;
    uint32_t corners = (uint32_t)m->face_count * 3, capacity = 16;
    while (capacity < 2 * (size_t)corners && capacity < (1u << 31)) capacity *= 2;
    vec3 *normals = malloc(m->face_count * sizeof *normals + 1);
    uint32_t *table = malloc((size_t)capacity * sizeof *table);
    uint32_t *next = malloc((size_t)corners * sizeof *next + 1);
    bool ok = normals && table && next && capacity > corners; /* an empty slot ends a probe */
    if (ok) {
        for (size_t f = 0; f < m->face_count; f++) normals[f] = face_normal(&m->faces[f]);
        memset(table, 0xff, (size_t)capacity * sizeof *table);
        link_positions(m, corners, table, capacity - 1, next);
        double radians = max_angle_degrees * 3.14159265358979323846 / 180.0;
        float min_cos = (float)cos(radians), half_cos = (float)cos(radians / 2.0);
        for (uint32_t c = 0; c < corners; c++) {
            vec3 *n = &m->faces[c / 3].n[c % 3];
            if (!v3_is_zero(*n) || v3_is_zero(normals[c / 3])) continue;
            if (big_ring(next, c) && smooth_coherent_ring(m, normals, next, c, half_cos)) continue;
            *n = smooth_corner(normals, next, c, min_cos);
        }
    }
    free(normals);
    free(table);
    free(next);
    return ok;
}
