/* scene_near_clip.c: the warning of what camera rays may cut away near the camera (the nearest
 * sphere surface or triangle within the near clip that the ray offset makes far from the
 * origin), or of a sphere or face too big for single precision to place near the camera. */
#include <math.h>

#include "scene/directives.h"
#include "scene/parser.h"
#include "scene/scene.h"
#include "shared_layout.h"

/* The spacing of floats around magnitude m (m > 0). */
static double float_step(double m) { return ldexp(1.0, ilogb(m) - 23); }

/* |v - s e|: the distance from a point, at v from a segment's start, to the point s of the way
 * along the segment e. */
static double segment_gap(dvec3 v, dvec3 e, double s) {
    return d3_length((dvec3){v.x - s * e.x, v.y - s * e.y, v.z - s * e.z});
}

/* The distance from p to triangle t's nearest point, in double: Ericson, Real-Time Collision
 * Detection, 5.1.5 (the corner, edge or inside region that p projects to). */
static double triangle_gap(vec3 p, const triangle *t) {
    vec3 a = t->v[0], b = t->v[1], c = t->v[2];
    dvec3 ab = d3_sub(b, a), ac = d3_sub(c, a), ap = d3_sub(p, a);
    double d1 = d3_dot(ab, ap), d2 = d3_dot(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) return d3_length(ap);
    dvec3 bp = d3_sub(p, b);
    double d3 = d3_dot(ab, bp), d4 = d3_dot(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) return d3_length(bp);
    if (d1 * d4 - d3 * d2 <= 0.0 && d1 >= 0.0 && d3 <= 0.0)
        return segment_gap(ap, ab, d1 / (d1 - d3));
    dvec3 cp = d3_sub(p, c);
    double d5 = d3_dot(ab, cp), d6 = d3_dot(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) return d3_length(cp);
    if (d5 * d2 - d1 * d6 <= 0.0 && d2 >= 0.0 && d6 <= 0.0)
        return segment_gap(ap, ac, d2 / (d2 - d6));
    if (d3 * d6 - d5 * d4 <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
        return segment_gap(bp, d3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6)));
    dvec3 n = d3_cross(ab, ac); /* not zero: faces are checked (face_problem) */
    return fabs(d3_dot(ap, n)) / d3_length(n);
}

/* The float nearest to x on the side of `toward` (an upper bound when toward is +INFINITY). */
static float float_bound(double x, float toward) {
    float f = (float)x;
    return (f > x && toward < 0.0f) || (f < x && toward > 0.0f) ? nextafterf(f, toward) : f;
}

static float min3(float a, float b, float c) { return a < b ? (a < c ? a : c) : (b < c ? b : c); }
static float max3(float a, float b, float c) { return a > b ? (a > c ? a : c) : (b > c ? b : c); }

/* Whether the corners v all lie beyond one side of the box lo..hi: then the face is farther than
 * the box's half-size from its centre. Float compares counted without branches (a face's sides
 * are unpredictable), the whole cost of a face that is far. */
static bool beyond_box(const vec3 v[3], vec3 lo, vec3 hi) {
    int sides = (min3(v[0].x, v[1].x, v[2].x) > hi.x) + (max3(v[0].x, v[1].x, v[2].x) < lo.x) +
                (min3(v[0].y, v[1].y, v[2].y) > hi.y) + (max3(v[0].y, v[1].y, v[2].y) < lo.y) +
                (min3(v[0].z, v[1].z, v[2].z) > hi.z) + (max3(v[0].z, v[1].z, v[2].z) < lo.z);
    return sides > 0;
}

/* The box of half-size r around c, rounded outward to floats. */
static void box_around(vec3 c, double r, vec3 *lo, vec3 *hi) {
    *lo = v3(float_bound(c.x - r, -INFINITY), float_bound(c.y - r, -INFINITY),
             float_bound(c.z - r, -INFINITY));
    *hi = v3(float_bound(c.x + r, INFINITY), float_bound(c.y + r, INFINITY),
             float_bound(c.z + r, INFINITY));
}

/* The triangle of s nearest to the camera at cam, looking along f, of those not wholly behind it
 * and nearer than *nearest: its index, with *nearest set to its distance; -1 when none. One pass
 * without allocation, so that a million faces cost a few ms: the exact distance only for faces
 * that reach into the box of half-size *nearest around the camera. */
static int nearest_face(const scene *s, vec3 cam, vec3 f, double *nearest) {
    dvec3 forward = {f.x, f.y, f.z};
    int which = -1;
    vec3 lo, hi;
    box_around(cam, *nearest, &lo, &hi);
    for (int k = 0; k < s->triangle_count; k++) {
        const vec3 *v = s->triangles[k].v;
        if (beyond_box(v, lo, hi)) continue;
        if (d3_dot(d3_sub(v[0], cam), forward) < 0.0 && d3_dot(d3_sub(v[1], cam), forward) < 0.0 &&
            d3_dot(d3_sub(v[2], cam), forward) < 0.0)
            continue; /* wholly behind the camera */
        double gap = triangle_gap(cam, &s->triangles[k]);
        if (gap < *nearest) {
            *nearest = gap, which = k;
            box_around(cam, gap, &lo, &hi);
        }
    }
    return which;
}

/* Warns about the face reaching farthest from the origin when that is over SCENE_FACE_SPAN times
 * the camera's largest |coordinate| (at least 1). A hit is placed on its face's plane
 * (plane_hit), but the watertight test finds a face's distance only to within a few float
 * spacings of its corners, while rays near the camera leave surfaces TZ_EPS times their distance
 * from the origin off them: a ray leaving a face nearly along it (a low light's shadow ray) may
 * start behind the face sharing its edge and meet it, a dark speck (docs/PERF.md, "Huge faces",
 * measures where). */
static void warn_huge_face(parser *p) {
    double reach = SCENE_FACE_SPAN * parser_largest_coordinate(p->s.camera_position);
    int which = -1;
    for (int k = 0; k < p->s.triangle_count; k++) {
        const vec3 *v = p->s.triangles[k].v;
        double m = fmax(v3_max_abs(v[0]), fmax(v3_max_abs(v[1]), v3_max_abs(v[2])));
        if (m > reach) reach = m, which = k;
    }
    if (which < 0) return;
    const vec3 *v = p->s.triangles[which].v;
    parser_warn(p, p->camera_line, p->camera_col,
                "triangle %d (corners %g %g %g, %g %g %g, %g %g %g) reaches over %g times as far "
                "from the origin as the camera: single precision finds its distances near the "
                "camera less exactly than rays leaving it are offset there, so it and the faces "
                "sharing its edges may shade each other in dark specks; use a smaller face (a "
                "floor of half-size 1e5 looks as flat)",
                which + 1, (double)v[0].x, (double)v[0].y, (double)v[0].z, (double)v[1].x,
                (double)v[1].y, (double)v[1].z, (double)v[2].x, (double)v[2].y, (double)v[2].z,
                SCENE_FACE_SPAN);
}

/* Camera rays start TZ_EPS times the camera's largest |coordinate| (at least 1) along their path,
 * as every ray does from its origin (DESIGN section 3): far from the origin that is a near clip
 * (10 units at 1e5). Warns when a sphere or triangle not wholly behind the camera has its surface
 * within SCENE_NEAR_CLIP_FACTOR times that distance of the camera, naming the nearest: it may be
 * cut away. Warns instead when a sphere is so big that its surface near the camera is within
 * SCENE_PRECISION_STEPS of the float spacing at its size, and that is coarser than the near clip:
 * single precision cannot place that surface (a floor of radius 3e7 one unit under the camera
 * renders black). */
void parser_warn_near_clip(parser *p) {
    warn_huge_face(p);
    vec3 cam = p->s.camera_position, f = p->s.camera_direction;
    double f_length = sqrt((double)f.x * f.x + (double)f.y * f.y + (double)f.z * f.z);
    float big = parser_largest_coordinate(cam);
    double offset = (double)TZ_EPS * big, nearest = INFINITY, worst = 1.0, step = 0.0;
    int which = -1, coarse = -1;
    for (int k = 0; k < p->s.sphere_count; k++) {
        const sphere *s = &p->s.spheres[k];
        double dx = (double)s->center.x - cam.x, dy = (double)s->center.y - cam.y,
               dz = (double)s->center.z - cam.z;
        double ahead = (dx * f.x + dy * f.y + dz * f.z) / f_length;
        if (ahead < -(double)s->radius) continue; /* wholly behind the camera */
        double distance = sqrt(dx * dx + dy * dy + dz * dz), gap = fabs(distance - s->radius);
        if (gap < nearest) nearest = gap, which = k;
        /* only where precision, not the near clip, is the coarser limit */
        double sk = float_step(fmax(distance, s->radius)), blur = SCENE_PRECISION_STEPS * sk;
        if (blur > SCENE_NEAR_CLIP_FACTOR * offset && gap / blur < worst)
            worst = gap / blur, coarse = k, step = sk;
    }
    if (coarse >= 0) {
        const sphere *s = &p->s.spheres[coarse];
        parser_warn(p, p->camera_line, p->camera_col,
                    "sphere %d (centre %g %g %g, radius %g) is too big for its surface to lie this "
                    "near the camera: at its size single-precision positions are %g apart, and its "
                    "surface is less than %g such steps from the camera, so it may be misplaced, "
                    "black or missing; use a smaller sphere (a floor of radius 1e4 looks as flat) "
                    "or move the camera away",
                    coarse + 1, (double)s->center.x, (double)s->center.y, (double)s->center.z,
                    (double)s->radius, step, (double)SCENE_PRECISION_STEPS);
        return;
    }
    /* A lone face needs no such warning: its exact corners place it (a floor triangle of
     * half-size 1e7 one unit under the camera shades within 3% of one of 1e4); its neighbours
     * are warn_huge_face's. */
    double limit = SCENE_NEAR_CLIP_FACTOR * offset, face_gap = fmin(nearest, limit);
    int face = nearest_face(&p->s, cam, f, &face_gap);
    const char *far = big > 1.0f ? " this far from the origin (the ray offset grows with it)" : "";
    const char *move = big > 1.0f ? "; move the scene nearer the origin" : "";
    if (face >= 0) {
        /* 8 digits: far from the origin, where this warns, %g would merge neighbouring faces. */
        const vec3 *v = p->s.triangles[face].v;
        parser_warn(p, p->camera_line, p->camera_col,
                    "camera rays start %g along their path%s, and triangle %d (corners %.8g %.8g "
                    "%.8g, %.8g %.8g %.8g, %.8g %.8g %.8g) is %g from the camera: it may be cut "
                    "away%s",
                    offset, far, face + 1, (double)v[0].x, (double)v[0].y, (double)v[0].z,
                    (double)v[1].x, (double)v[1].y, (double)v[1].z, (double)v[2].x, (double)v[2].y,
                    (double)v[2].z, face_gap, move);
        return;
    }
    if (which < 0 || nearest >= limit) return;
    const sphere *s = &p->s.spheres[which];
    parser_warn(p, p->camera_line, p->camera_col,
                "camera rays start %g along their path%s, and sphere %d (centre %g %g %g, radius "
                "%g) has its surface %g from the camera: it may be cut away%s",
                offset, far, which + 1, (double)s->center.x, (double)s->center.y,
                (double)s->center.z, (double)s->radius, nearest, move);
}
