/* view_camera.c: the view's camera moves (view_camera.h), in double on the scene's floats. */
#include "cli/view_camera.h"

#include <math.h>
#include <stdio.h>

/* pi, which C11 does not define. */
#define VIEW_PI 3.14159265358979323846
/* Radians the camera turns a pixel of mouse travel: a drag across a 400-pixel view turns it
 * about 115 degrees. */
#define ORBIT_RADIANS_PER_PIXEL 0.005
/* The steepest the camera looks up or down (radians, 89 degrees): the frame R = up x F needs the
 * direction away from up. */
#define ORBIT_MAX_ELEVATION (89.0 * VIEW_PI / 180.0)
/* The share of the way to the pivot a wheel step moves the camera. */
#define DOLLY_STEP 0.2

typedef struct dvec {
    double x, y, z;
} dvec;

static dvec d_of(vec3 v) { return (dvec){v.x, v.y, v.z}; }
static vec3 f_of(dvec v) { return v3((float)v.x, (float)v.y, (float)v.z); }
static dvec d_add(dvec a, dvec b) { return (dvec){a.x + b.x, a.y + b.y, a.z + b.z}; }
static dvec d_sub(dvec a, dvec b) { return (dvec){a.x - b.x, a.y - b.y, a.z - b.z}; }
static dvec d_scale(dvec a, double s) { return (dvec){a.x * s, a.y * s, a.z * s}; }
static double d_dot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static dvec d_cross(dvec a, dvec b) {
    return (dvec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static dvec d_unit(dvec a) { return d_scale(a, 1.0 / sqrt(d_dot(a, a))); }

/* v turned by angle a about the unit axis k (Rodrigues' formula). */
static dvec d_rotate(dvec v, dvec k, double a) {
    double c = cos(a), s = sin(a);
    return d_add(d_add(d_scale(v, c), d_scale(d_cross(k, v), s)),
                 d_scale(k, d_dot(k, v) * (1.0 - c)));
}

view_camera view_camera_of(const scene *s) {
    return (view_camera){s->camera_position, s->camera_direction, s->camera_up};
}

/* The nearest t > tmin where o + t d (d a unit vector) meets sphere sp; INFINITY for none. */
static double sphere_t(const sphere *sp, dvec o, dvec d, double tmin) {
    dvec oc = d_sub(o, d_of(sp->center));
    double b = d_dot(oc, d), r = sp->radius;
    dvec perp = d_sub(oc, d_scale(d, b));
    double disc = r * r - d_dot(perp, perp);
    if (disc < 0.0) return INFINITY;
    double q = sqrt(disc), t0 = -b - q, t1 = -b + q;
    return t0 > tmin ? t0 : t1 > tmin ? t1 : INFINITY;
}

/* The t > tmin where o + t d meets face f (Moller-Trumbore); INFINITY for none. */
static double triangle_t(const triangle *f, dvec o, dvec d, double tmin) {
    dvec a = d_of(f->v[0]), e1 = d_sub(d_of(f->v[1]), a), e2 = d_sub(d_of(f->v[2]), a);
    dvec p = d_cross(d, e2);
    double det = d_dot(e1, p);
    if (det == 0.0) return INFINITY;
    dvec s = d_sub(o, a);
    double u = d_dot(s, p) / det;
    dvec q = d_cross(s, e1);
    double v = d_dot(d, q) / det, t = d_dot(e2, q) / det;
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > tmin ? t : INFINITY;
}

/* The middle of the scene's primitives and lights, and whether it has any. */
static bool scene_middle(const scene *s, dvec *middle) {
    dvec lo = {INFINITY, INFINITY, INFINITY}, hi = {-INFINITY, -INFINITY, -INFINITY};
    int n = 0;
    for (int k = 0; k < s->triangle_count; k++)
        for (int c = 0; c < 3; c++, n++) {
            dvec v = d_of(s->triangles[k].v[c]);
            lo = (dvec){fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z)};
            hi = (dvec){fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z)};
        }
    /* Spheres by their centres: a room's huge walls would put its middle far outside it. */
    for (int k = 0; k < s->sphere_count; k++, n++) {
        dvec v = d_of(s->spheres[k].center);
        lo = (dvec){fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z)};
        hi = (dvec){fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z)};
    }
    for (int k = 0; k < s->light_count; k++, n++) {
        dvec v = d_of(s->lights[k].position);
        lo = (dvec){fmin(lo.x, v.x), fmin(lo.y, v.y), fmin(lo.z, v.z)};
        hi = (dvec){fmax(hi.x, v.x), fmax(hi.y, v.y), fmax(hi.z, v.z)};
    }
    *middle = d_scale(d_add(lo, hi), 0.5);
    return n > 0;
}

view_drag view_camera_drag(const scene *s, view_camera c) {
    dvec o = d_of(c.position), d = d_unit(d_of(c.direction));
    /* Past the camera's near clip and its own rounding, as the renderer starts its rays. */
    double scale = fmax(1.0, fmax(fabs(o.x), fmax(fabs(o.y), fabs(o.z))));
    double tmin = fmax((double)s->camera_near, scale * 1e-6), t = INFINITY;
    for (int k = 0; k < s->sphere_count; k++) t = fmin(t, sphere_t(&s->spheres[k], o, d, tmin));
    for (int k = 0; k < s->triangle_count; k++)
        t = fmin(t, triangle_t(&s->triangles[k], o, d, tmin));
    if (!isfinite(t)) {
        dvec middle;
        double ahead = scene_middle(s, &middle) ? d_dot(d_sub(middle, o), d) : 0.0;
        t = ahead > tmin ? ahead : 2.0 * s->plane_width;
    }
    dvec pivot = d_add(o, d_scale(d, t));
    return (view_drag){.start = c, .pivot = {pivot.x, pivot.y, pivot.z}};
}

static dvec pivot_of(const view_drag *d) { return (dvec){d->pivot[0], d->pivot[1], d->pivot[2]}; }

view_camera view_camera_orbit(const view_drag *d, int dx, int dy) {
    dvec pivot = pivot_of(d), up = d_unit(d_of(d->start.up));
    dvec offset = d_sub(d_of(d->start.position), pivot), f = d_unit(d_of(d->start.direction));
    /* Dragging right turns the camera left about the pivot, so the scene follows the mouse. */
    double yaw = -dx * ORBIT_RADIANS_PER_PIXEL, pitch = dy * ORBIT_RADIANS_PER_PIXEL;
    offset = d_rotate(offset, up, yaw);
    f = d_rotate(f, up, yaw);
    /* A turn by a about R = up x F lowers the direction's elevation by a: clamped there. */
    dvec right = d_unit(d_cross(up, f));
    double elevation = asin(fmax(-1.0, fmin(1.0, d_dot(f, up))));
    double target = fmax(-ORBIT_MAX_ELEVATION, fmin(ORBIT_MAX_ELEVATION, elevation - pitch));
    offset = d_rotate(offset, right, elevation - target);
    f = d_rotate(f, right, elevation - target);
    return (view_camera){f_of(d_add(pivot, offset)), f_of(f), d->start.up};
}

/* The distance from the image plane to the camera (scenes/README.md: 2 x width, or set by fov). */
static double plane_distance(const scene *s) {
    if (s->camera_fov > 0.0f) return 0.5 * s->plane_width / tan(s->camera_fov * VIEW_PI / 360.0);
    return 2.0 * s->plane_width;
}

view_camera view_camera_pan(const scene *s, const view_drag *d, int dx, int dy) {
    dvec o = d_of(d->start.position), f = d_unit(d_of(d->start.direction));
    dvec right = d_unit(d_cross(d_of(d->start.up), f)), up = d_cross(f, right);
    /* A pixel at the pivot's depth spans pixel x depth / plane distance of the scene. */
    double depth = fabs(d_dot(d_sub(pivot_of(d), o), f));
    double step = s->pixel_size * depth / plane_distance(s);
    dvec move = d_add(d_scale(right, -dx * step), d_scale(up, dy * step));
    return (view_camera){f_of(d_add(o, move)), d->start.direction, d->start.up};
}

view_camera view_camera_dolly(const view_drag *d, int steps) {
    dvec o = d_of(d->start.position), f = d_unit(d_of(d->start.direction));
    double depth = fabs(d_dot(d_sub(pivot_of(d), o), f));
    double move = depth * (1.0 - pow(1.0 - DOLLY_STEP, steps));
    return (view_camera){f_of(d_add(o, d_scale(f, move))), d->start.direction, d->start.up};
}

int view_camera_line(const scene *s, view_camera c, char *out, size_t size) {
    /* %.9g: nine significant digits read back as the same float (FLT_DECIMAL_DIG). */
    int n = snprintf(out, size,
                     "camera position %.9g %.9g %.9g direction %.9g %.9g %.9g up %.9g %.9g %.9g",
                     c.position.x, c.position.y, c.position.z, c.direction.x, c.direction.y,
                     c.direction.z, c.up.x, c.up.y, c.up.z);
    size_t used = n > 0 && (size_t)n < size ? (size_t)n : size;
    if (s->camera_fov > 0.0f && used < size)
        n += snprintf(out + used, size - used, " fov %.9g", s->camera_fov);
    used = n > 0 && (size_t)n < size ? (size_t)n : size;
    if (s->camera_near > 0.0f && used < size)
        n += snprintf(out + used, size - used, " near %.9g", s->camera_near);
    used = n > 0 && (size_t)n < size ? (size_t)n : size;
    if (s->camera_aperture > 0.0f && used < size)
        n += snprintf(out + used, size - used, " aperture %.9g focus %.9g", s->camera_aperture,
                      s->camera_focus);
    used = n > 0 && (size_t)n < size ? (size_t)n : size;
    if (s->camera_orthographic && used < size)
        n += snprintf(out + used, size - used, " projection orthographic");
    return n;
}
