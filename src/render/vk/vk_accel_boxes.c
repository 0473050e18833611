/* vk_accel_boxes.c: the ray query walk's bottom-level ranges and padded boxes (see
 * vk_accel_boxes.h). */
#include "render/vk/vk_accel_boxes.h"

#include <math.h>
#include <stdlib.h>

#include "util/log.h"

/* Padding of a box, as a share of the largest coordinate a ray or the box can have in the
 * box's space: 2^-16 is 128 float ulps, far past the few roundings of a slab test and of the
 * device's move of a ray into an instance's space (position errors of a few ulps of the ray
 * origin and the box, which a padding widens every slab by at least as much). */
#define BOX_PAD_SHARE (1.0 / 65536.0)

static double max_abs3(double x, double y, double z) {
    return fmax(fabs(x), fmax(fabs(y), fabs(z)));
}

/* The exact box of primitive k (spheres first, then triangles), in double. */
static void primitive_box(const packed_scene *p, uint32_t k, double lo[3], double hi[3]) {
    if (k < p->frame.sphere_count) {
        const tz_vec4 *c = &p->spheres[k].center_radius;
        double centre[3] = {c->x, c->y, c->z};
        for (int a = 0; a < 3; a++) lo[a] = centre[a] - c->w, hi[a] = centre[a] + c->w;
        return;
    }
    const struct gpu_triangle *t = &p->triangles[k - p->frame.sphere_count];
    const tz_vec4 *v[3] = {&t->v0, &t->v1, &t->v2};
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int c = 0; c < 3; c++) {
        double x[3] = {v[c]->x, v[c]->y, v[c]->z};
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], x[a]), hi[a] = fmax(hi[a], x[a]);
    }
}

/* The largest coordinate of primitives [first, first + count), and their box. */
static double range_reach(const packed_scene *p, accel_range r, double lo[3], double hi[3]) {
    double reach = 0.0;
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t k = r.first; k < r.first + r.count; k++) {
        double l[3], h[3];
        primitive_box(p, k, l, h);
        reach = fmax(reach, fmax(max_abs3(l[0], l[1], l[2]), max_abs3(h[0], h[1], h[2])));
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], l[a]), hi[a] = fmax(hi[a], h[a]);
    }
    return reach;
}

/* x as a float no greater (down) or no less than it. */
static float round_out(double x, bool down) {
    float f = (float)x;
    if (down && (double)f > x) return nextafterf(f, -INFINITY);
    if (!down && (double)f < x) return nextafterf(f, INFINITY);
    return f;
}

static int by_first(const void *a, const void *b) {
    uint32_t x = *(const uint32_t *)a, y = *(const uint32_t *)b;
    return (x > y) - (x < y);
}

uint32_t accel_ranges(const packed_scene *p, accel_range **ranges) {
    uint32_t n = p->frame.instance_count, total = p->frame.sphere_count + p->frame.triangle_count;
    uint32_t *firsts = malloc((n ? n : 1) * sizeof *firsts);
    *ranges = malloc((n + 1) * sizeof **ranges);
    if (!firsts || !*ranges) {
        free(firsts), free(*ranges);
        *ranges = NULL;
        log_error("out of memory laying out %u instances' acceleration structures", n);
        return 0;
    }
    for (uint32_t i = 0; i < n; i++) firsts[i] = p->instances[i].model.y;
    qsort(firsts, n, sizeof *firsts, by_first);
    uint32_t models = 0;
    for (uint32_t i = 0; i < n; i++)
        if (models == 0 || firsts[models - 1] != firsts[i]) firsts[models++] = firsts[i];
    /* The models' faces follow the scene's own, each model's up to the next one's. */
    uint32_t own = models ? p->frame.sphere_count + firsts[0] : total;
    (*ranges)[0] = (accel_range){0, own};
    for (uint32_t m = 0; m < models; m++) {
        uint32_t first = p->frame.sphere_count + firsts[m];
        uint32_t end = m + 1 < models ? p->frame.sphere_count + firsts[m + 1] : total;
        (*ranges)[1 + m] = (accel_range){first, end - first};
    }
    free(firsts);
    return 1 + models;
}

uint32_t accel_range_of(const packed_scene *p, const accel_range *ranges, uint32_t count,
                        uint32_t i) {
    uint32_t first = p->frame.sphere_count + p->instances[i].model.y, lo = 1, hi = count;
    while (hi - lo > 1) { /* the last range starting at or before first */
        uint32_t mid = lo + (hi - lo) / 2;
        if (ranges[mid].first <= first)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* How far from its model's origin a ray moved into instance i's space can start, for rays
 * that start within `reach` of the world's (each row's absolute sum times reach, plus its
 * translation). */
static double instance_reach(const struct gpu_instance *in, double reach) {
    double most = 0.0;
    for (int r = 0; r < 3; r++) {
        const tz_vec4 *row = &in->to_object[r];
        most = fmax(most, (fabs(row->x) + fabs(row->y) + fabs(row->z)) * reach + fabs(row->w));
    }
    return most;
}

/* The largest world coordinate of instance i's model box lo..hi moved by its transform. */
static double instance_world_reach(const struct gpu_instance *in, const double lo[3],
                                   const double hi[3]) {
    double most = 0.0;
    for (int c = 0; c < 8; c++) {
        double x[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
        for (int r = 0; r < 3; r++) {
            const tz_vec4 *row = &in->to_world[r];
            most = fmax(most, fabs(row->x * x[0] + row->y * x[1] + row->z * x[2] + row->w));
        }
    }
    return most;
}

/* Pads the boxes of range r by BOX_PAD_SHARE of reach plus each box's own largest coordinate. */
static void pad_range(const packed_scene *p, accel_range r, double reach,
                      VkAabbPositionsKHR *boxes) {
    for (uint32_t k = r.first; k < r.first + r.count; k++) {
        double lo[3], hi[3];
        primitive_box(p, k, lo, hi);
        double own = fmax(max_abs3(lo[0], lo[1], lo[2]), max_abs3(hi[0], hi[1], hi[2]));
        double pad = BOX_PAD_SHARE * fmax(reach + own, 1.0);
        boxes[k] =
            (VkAabbPositionsKHR){round_out(lo[0] - pad, true),  round_out(lo[1] - pad, true),
                                 round_out(lo[2] - pad, true),  round_out(hi[0] + pad, false),
                                 round_out(hi[1] + pad, false), round_out(hi[2] + pad, false)};
    }
}

bool accel_fill_boxes(const packed_scene *p, const accel_range *ranges, uint32_t count,
                      VkAabbPositionsKHR *boxes) {
    double(*box)[6] = malloc(count * sizeof *box);
    double *reach = malloc(count * sizeof *reach);
    if (!box || !reach) {
        free(box), free(reach);
        log_error("out of memory padding the acceleration structures' boxes");
        return false;
    }
    /* Where a world ray may start: the camera, any primitive, any instance. */
    const tz_vec4 *eye = &p->frame.origin;
    double world = max_abs3(eye->x, eye->y, eye->z) + fabs((double)p->frame.near_distance);
    for (uint32_t r = 0; r < count; r++) {
        reach[r] = range_reach(p, ranges[r], box[r], box[r] + 3);
        if (r == 0) world = fmax(world, reach[r]);
    }
    for (uint32_t i = 0; i < p->frame.instance_count; i++) {
        uint32_t r = accel_range_of(p, ranges, count, i);
        world = fmax(world, instance_world_reach(&p->instances[i], box[r], box[r] + 3));
    }
    /* A model's rays: moved from within the world's reach by each of its instances. */
    double *model = reach;
    for (uint32_t r = 1; r < count; r++) model[r] = 0.0;
    model[0] = world;
    for (uint32_t i = 0; i < p->frame.instance_count; i++) {
        uint32_t r = accel_range_of(p, ranges, count, i);
        model[r] = fmax(model[r], instance_reach(&p->instances[i], world));
    }
    for (uint32_t r = 0; r < count; r++) pad_range(p, ranges[r], model[r], boxes);
    free(box), free(reach);
    return true;
}
