/* ray.h: where rays start and what they hit, one text for C and GLSL (dialect.h): the camera
 * ray, the ray offset, the sphere and triangle tests, the tie rule and the BVH's slab test. The
 * walks that call them differ by back end (src/render/bvh.h says why they agree). */
#ifndef TRAZADOR_COMMON_RAY_H
#define TRAZADOR_COMMON_RAY_H

#include "dialect.h"

/* Primary ray direction through the plane point of pixel (i, j) offset by (u, v) pixels
 * (gpu_frame's right, up and forward, pixel its origin.w). */
TZ_FN vec3 camera_direction(TZ_VEC4 right, TZ_VEC4 up, TZ_VEC4 forward, float pixel, TZ_UINT i,
                            TZ_UINT j, float u, float v) {
    TZ_PRECISE float x = right.w + (TZ_FLOAT(i) + u) * pixel;
    TZ_PRECISE float y = up.w - (TZ_FLOAT(j) + v) * pixel;
    TZ_PRECISE vec3 d = v3_add(v3_add(v3_scale(xyz(right), x), v3_scale(xyz(up), y)),
                               v3_scale(xyz(forward), forward.w));
    return v3_normalize(d);
}

/* Ray offset distance at a point: TZ_EPS scaled with the point's magnitude, so that it grows
 * with the float spacing away from the origin. */
TZ_FN float ray_eps(vec3 p) {
    float m = v3_max_abs(p);
    TZ_PRECISE float r = TZ_EPS * TZ_MAX(m, 1.0f);
    return r;
}

/* The origin of a ray leaving surface point p on the side its normal n points to. */
TZ_FN vec3 offset_origin(vec3 p, vec3 n) {
    TZ_PRECISE vec3 o = v3_add(p, v3_scale(n, ray_eps(p)));
    return o;
}

/* Distance to the sphere (centre c, radius r) along o + t d: the nearest root greater than tmin,
 * infinity for a miss; after Haines et al., Ray Tracing Gems ch. 7: disc = r^2 - |oc - b d|^2 and
 * q = -b - sign(b) sqrt(disc), roots c/q and q. c = |oc|^2 - r^2 is taken on the largest
 * component of oc, (|m| - r)(|m| + r) + the other two squared: exact when a huge wall sphere's
 * centre lies along an axis from the ray origin. When the ray leaves this very sphere (is_self),
 * moving inward (b < 0) only its far root counts; moving outward it cannot hit it again.
 * Branch-free, so that loops over spheres or rays compile to SIMD. */
TZ_LANE_FN float sphere_distance(float cx, float cy, float cz, float r, vec3 o, vec3 d, float tmin,
                                 TZ_BOOL is_self) {
    TZ_PRECISE float ocx = o.x - cx, ocy = o.y - cy, ocz = o.z - cz;
    TZ_PRECISE float b = ocx * d.x + ocy * d.y + ocz * d.z;
    float ax = TZ_ABS(ocx), ay = TZ_ABS(ocy), az = TZ_ABS(ocz);
    TZ_PRECISE float xx = ocx * ocx, yy = ocy * ocy, zz = ocz * ocz;
    TZ_BOOL x_big = (ax >= ay) TZ_AND(ax >= az), y_big = !x_big TZ_AND(ay >= az);
    float big = x_big ? ax : y_big ? ay : az;
    float other1 = x_big ? yy : xx, other2 = (x_big TZ_OR y_big) ? zz : yy;
    TZ_PRECISE float c = (big - r) * (big + r) + other1 + other2;
    TZ_PRECISE float fx = ocx - b * d.x, fy = ocy - b * d.y, fz = ocz - b * d.z;
    TZ_PRECISE float disc = r * r - (fx * fx + fy * fy + fz * fz);
    TZ_PRECISE float root = TZ_SQRT(disc < 0.0f ? 0.0f : disc);
    TZ_PRECISE float q = b > 0.0f ? -b - root : -b + root;
    TZ_PRECISE float cq = c / q;
    float t0 = cq < q ? cq : q, t1 = cq < q ? q : cq;
    TZ_BOOL near_ok = (t0 > tmin) TZ_AND !is_self;
    TZ_BOOL far_ok = (t1 > tmin) TZ_AND(!is_self TZ_OR(b < 0.0f));
    float near = near_ok ? t0 : far_ok ? t1 : TZ_INFINITY;
    TZ_BOOL miss = ((c > 0.0f) TZ_AND(b > 0.0f)) TZ_OR(disc < 0.0f) TZ_OR(q == 0.0f);
    return miss ? TZ_INFINITY : near;
}

/* v's components in the order the watertight triangle test takes them for a ray whose largest
 * direction component is kz: (kx, ky, kz) with kx = kz + 1 and ky = kx + 1 (mod 3), kx and ky
 * swapped when that component is negative (swap), so that the triangle's winding is kept. */
TZ_FN vec3 shear_axes(vec3 v, int kz, TZ_BOOL swap) {
    vec3 p = select3(kz == 0, v3(v.y, v.z, v.x), select3(kz == 1, v3(v.z, v.x, v.y), v));
    return select3(swap, v3(p.y, p.x, p.z), p);
}

/* The edge functions and distance of the watertight test: U, V, W the weights of corners a, b,
 * c times det = U + V + W, and T = t * det. */
TZ_STRUCT(triangle_edges) { float u, v, w, det, t_det; }
TZ_STRUCT_END(triangle_edges)

/* What the watertight test takes from a ray's direction alone: the axis kz of its largest
 * component, swap (shear_axes), and the shear sx, sy, sz that turns it into +z. */
TZ_STRUCT(ray_shear) {
    int kz;
    TZ_BOOL swap;
    float sx, sy, sz;
}
TZ_STRUCT_END(ray_shear)

/* shear_of's kz and swap alone (sx, sy, sz zero). */
TZ_LANE_FN ray_shear shear_order_of(vec3 d) {
    float ax = TZ_ABS(d.x), ay = TZ_ABS(d.y), az = TZ_ABS(d.z);
    ray_shear s;
    s.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
    float dz = s.kz == 0 ? d.x : s.kz == 1 ? d.y : d.z;
    s.swap = dz < 0.0f;
    s.sx = 0.0f;
    s.sy = 0.0f;
    s.sz = 0.0f;
    return s;
}

TZ_LANE_FN ray_shear shear_of(vec3 d) {
    ray_shear s = shear_order_of(d);
    vec3 ds = shear_axes(d, s.kz, s.swap);
    TZ_PRECISE float sx = ds.x / ds.z, sy = ds.y / ds.z, sz = 1.0f / ds.z;
    s.sx = sx;
    s.sy = sy;
    s.sz = sz;
    return s;
}

/* The edge functions of the watertight test from the corners moved to the ray origin and put in
 * shear_axes order (pa, pb, pc) and the ray's shear sx, sy, sz (shear_of). */
TZ_LANE_FN triangle_edges sheared_edge_functions(vec3 pa, vec3 pb, vec3 pc, float sx, float sy,
                                                 float sz) {
    TZ_PRECISE float ax2 = pa.x - sx * pa.z, ay2 = pa.y - sy * pa.z;
    TZ_PRECISE float bx2 = pb.x - sx * pb.z, by2 = pb.y - sy * pb.z;
    TZ_PRECISE float cx2 = pc.x - sx * pc.z, cy2 = pc.y - sy * pc.z;
    triangle_edges e;
    TZ_PRECISE float u = cx2 * by2 - cy2 * bx2;
    TZ_PRECISE float v = ax2 * cy2 - ay2 * cx2;
    TZ_PRECISE float w = bx2 * ay2 - by2 * ax2;
    TZ_PRECISE float det = u + v + w;
    TZ_PRECISE float t_det = u * (sz * pa.z) + v * (sz * pb.z) + w * (sz * pc.z);
    e.u = u;
    e.v = v;
    e.w = w;
    e.det = det;
    e.t_det = t_det;
    return e;
}

/* The watertight ray-triangle test of Woop, Benthin and Wald (JCGT 2(1), 2013), without its
 * double-precision fallback, for the ray from o whose direction's shear is s (shear_of): the
 * corners are moved to the ray origin and sheared so that the ray runs along +z, and the edge
 * functions are 2D cross products of corners. An edge shared by two faces gives them exactly
 * opposite edge functions (the same products, subtracted the other way round), so a ray through it
 * hits at least one of them: no ray slips between faces. */
TZ_LANE_FN triangle_edges triangle_edge_functions(vec3 a, vec3 b, vec3 c, vec3 o, ray_shear s) {
    return sheared_edge_functions(shear_axes(v3_sub(a, o), s.kz, s.swap),
                                  shear_axes(v3_sub(b, o), s.kz, s.swap),
                                  shear_axes(v3_sub(c, o), s.kz, s.swap), s.sx, s.sy, s.sz);
}

/* The distance of a triangle test's edge functions e: t > tmin, infinity for a miss (or when
 * the ray leaves this very triangle, is_self: a plane cannot be met again). Both sides count. */
TZ_LANE_FN float edges_distance(triangle_edges e, float tmin, TZ_BOOL is_self) {
    TZ_BOOL negative = (e.u < 0.0f) TZ_OR(e.v < 0.0f) TZ_OR(e.w < 0.0f);
    TZ_BOOL positive = (e.u > 0.0f) TZ_OR(e.v > 0.0f) TZ_OR(e.w > 0.0f);
    TZ_PRECISE float t = e.t_det / e.det;
    TZ_BOOL hit = !(negative TZ_AND positive)TZ_AND(e.det != 0.0f) TZ_AND(t > tmin) TZ_AND !is_self;
    return hit ? t : TZ_INFINITY;
}

/* triangle_distance with the ray's shear s = shear_of(d) given: a walk makes it once for all the
 * triangles it tests. */
TZ_LANE_FN float sheared_triangle_distance(vec3 a, vec3 b, vec3 c, vec3 o, ray_shear s, float tmin,
                                           TZ_BOOL is_self) {
    return edges_distance(triangle_edge_functions(a, b, c, o, s), tmin, is_self);
}

/* Distance to the triangle (corners a, b, c) along o + t d, as edges_distance. Branch-free, as
 * sphere_distance. */
TZ_LANE_FN float triangle_distance(vec3 a, vec3 b, vec3 c, vec3 o, vec3 d, float tmin,
                                   TZ_BOOL is_self) {
    return sheared_triangle_distance(a, b, c, o, shear_of(d), tmin, is_self);
}

/* The distance along d from o to the plane through a of normal n, measured along n: n.(a - o) /
 * n.d (not finite where d runs along the plane). */
TZ_FN float plane_distance(vec3 a, vec3 n, vec3 o, vec3 d) {
    TZ_PRECISE float t = v3_dot(n, v3_sub(a, o)) / v3_dot(n, d);
    return t;
}

/* Where the ray o + t d meets the plane through a of unit normal n (plane_distance), exact for a
 * face square to an axis however far its corners lie, where the watertight test's distance (from
 * the corners' sheared depths) is a few float spacings of the corners off. pos when the ray runs
 * along the plane. */
TZ_FN vec3 plane_hit(vec3 a, vec3 n, vec3 o, vec3 d, vec3 pos) {
    TZ_PRECISE float t = plane_distance(a, n, o, d);
    TZ_PRECISE vec3 p = v3_add(o, v3_scale(d, t));
    return v3_dot(n, d) != 0.0f && t < TZ_INFINITY && t > -TZ_INFINITY ? p : pos;
}

/* The distance from o along wi, a direction drawn toward the triangle (a, b, c) by light
 * sampling: the watertight test's, or, where rounding puts the direction a hair outside the
 * triangle (about 1e-4 of the directions drawn within a thin or small one), the distance to its
 * plane. */
TZ_FN float triangle_light_distance(vec3 a, vec3 b, vec3 c, vec3 o, vec3 wi) {
    float t = triangle_distance(a, b, c, o, wi, ray_eps(o), TZ_FALSE);
    if (t < TZ_INFINITY) return t;                                /* the plane is the rare case's */
    vec3 ng = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a))); /* unit: dot stays finite */
    TZ_PRECISE float plane = plane_distance(a, ng, o, wi);
    TZ_BOOL meets = (plane > ray_eps(o)) TZ_AND(plane < TZ_INFINITY);
    return meets ? plane : TZ_INFINITY;
}

/* The tie rule: true when primitive k at distance t replaces the nearest hit so far (primitive id
 * at distance best, id -1 for none): nearer, or as near with a lower index. */
TZ_FN TZ_BOOL nearer_hit(float t, int k, float best, int id) {
    return (t < best) TZ_OR((t == best) TZ_AND(id >= 0) TZ_AND(k < id));
}

/* 1/d with zero components of d replaced by 1e30 first, so that the slab test has no NaN. */
TZ_FN vec3 inverse_direction(vec3 d) {
    return v3(d.x != 0.0f ? 1.0f / d.x : 1e30f, d.y != 0.0f ? 1.0f / d.y : 1e30f,
              d.z != 0.0f ? 1.0f / d.z : 1e30f);
}

/* Distance at which the ray enters the box lo..hi (xyz), infinity when it misses it or enters
 * at or beyond tmax (slab test; inv from inverse_direction). Selects, not min and max: GLSL's
 * leave NaN operands undefined; precise keeps a compiler from turning them into min and max. */
TZ_FN float box_entry(TZ_VEC4 lo, TZ_VEC4 hi, vec3 o, vec3 inv, float tmax) {
    TZ_PRECISE float x1 = (lo.x - o.x) * inv.x, x2 = (hi.x - o.x) * inv.x;
    TZ_PRECISE float y1 = (lo.y - o.y) * inv.y, y2 = (hi.y - o.y) * inv.y;
    TZ_PRECISE float z1 = (lo.z - o.z) * inv.z, z2 = (hi.z - o.z) * inv.z;
    TZ_PRECISE float near = x1 < x2 ? x1 : x2, far = x1 < x2 ? x2 : x1;
    TZ_PRECISE float ny = y1 < y2 ? y1 : y2, fy = y1 < y2 ? y2 : y1;
    TZ_PRECISE float nz = z1 < z2 ? z1 : z2, fz = z1 < z2 ? z2 : z1;
    near = near > ny ? near : ny;
    near = near > nz ? near : nz;
    near = near > 0.0f ? near : 0.0f;
    far = far < fy ? far : fy;
    far = far < fz ? far : fz;
    return near <= far && near < tmax ? near : TZ_INFINITY;
}

/* The sphere count of a BVH child reference (0: an inner node) and its index (of the node, or
 * of the leaf's first sphere). */
TZ_FN TZ_UINT child_count(TZ_UINT ref) { return ref >> TZ_BVH_COUNT_SHIFT; }
TZ_FN TZ_UINT child_index(TZ_UINT ref) { return ref & TZ_BVH_INDEX_MASK; }

#endif
