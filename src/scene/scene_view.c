/* scene_view.c: where the scene's meshes lie against the camera's view: each one's bounding box
 * after its transform (--verbose), and the warning of a mesh wholly outside the view. A model's
 * own coordinates are unknown before it is loaded: the README's recipe, used as written, framed
 * nothing of two real models and rendered the background without a word. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"
#include "util/log.h"

bool parser_note_mesh(parser *p, int col, size_t faces, vec3 lo, vec3 hi, const char *path) {
    if (p->view_count == p->view_capacity) {
        size_t capacity = p->view_capacity ? 2 * p->view_capacity : 16;
        mesh_view *grown = realloc(p->views, capacity * sizeof *grown);
        if (!grown) {
            if (p->err) p->err->out_of_memory = true;
            return parser_fail(p, p->tokens[0].col, "out of memory");
        }
        p->views = grown;
        p->view_capacity = capacity;
    }
    mesh_view *v = &p->views[p->view_count++];
    *v = (mesh_view){.line = p->line, .col = col, .faces = faces, .lo = lo, .hi = hi};
    snprintf(v->path, sizeof v->path, "%s", path);
    return true;
}

/* The camera's view as the renderer builds it (scene_pack.c): a unit frame f, r, u and the
 * pyramid of the points whose r and u parts are within half the plane's width and height times
 * their f part over the plane's distance, in front of the near distance. */
typedef struct view {
    dvec3 origin, f, r, u;
    double half_width, half_height, distance, near_f; /* near_f: the least f part rays reach */
    bool orthographic;      /* a box of the plane's size along f, not a pyramid */
    double aperture, focus; /* a thin lens widens the view by aperture |1 - f part / focus| */
} view;

static dvec3 unit(dvec3 v) {
    double l = d3_length(v);
    return (dvec3){v.x / l, v.y / l, v.z / l};
}

static view view_of(const scene *s) {
    view v;
    vec3 o = s->camera_position;
    v.origin = (dvec3){o.x, o.y, o.z};
    v.f = unit(d3_sub(s->camera_direction, v3(0, 0, 0)));
    v.r = unit(d3_cross(d3_sub(s->camera_up, v3(0, 0, 0)), v.f));
    v.u = d3_cross(v.f, v.r);
    v.half_width = 0.5 * s->plane_width;
    v.half_height = 0.5 * s->plane_height;
    v.distance = s->camera_fov > 0.0f
                     ? v.half_width / tan(0.5 * s->camera_fov * (3.14159265358979323846 / 180.0))
                     : 2.0 * s->plane_width;
    /* A ray starts `near` along its unit direction, whose f part is least at the plane's corners.
     */
    double corner =
        sqrt(v.distance * v.distance + v.half_width * v.half_width + v.half_height * v.half_height);
    v.near_f = s->camera_orthographic ? s->camera_near : s->camera_near * v.distance / corner;
    v.orthographic = s->camera_orthographic;
    v.aperture = s->camera_aperture;
    v.focus = s->camera_focus;
    return v;
}

/* Whether the box lo..hi lies wholly outside the view: all its corners beyond one of the
 * pyramid's five sides (behind the near distance, or past the left, right, top or bottom edge).
 * A box that straddles two sides' corner is kept: never a warning for a mesh in view. */
static bool outside(const view *v, vec3 lo, vec3 hi) {
    int beyond[5] = {0};
    for (int k = 0; k < 8; k++) {
        dvec3 c = {(k & 1 ? hi.x : lo.x) - v->origin.x, (k & 2 ? hi.y : lo.y) - v->origin.y,
                   (k & 4 ? hi.z : lo.z) - v->origin.z};
        double a = d3_dot(c, v->f), b = d3_dot(c, v->r), h = d3_dot(c, v->u);
        /* the sides at depth a, over the plane's distance (a pyramid) or over 1 (a box) */
        double scale = v->orthographic ? 1.0 : v->distance, depth = v->orthographic ? 1.0 : a;
        double lens = v->aperture > 0.0 ? v->aperture * fabs(1.0 - a / v->focus) * scale : 0.0;
        beyond[0] += a <= v->near_f;
        beyond[1] += b * scale > depth * v->half_width + lens;
        beyond[2] += -b * scale > depth * v->half_width + lens;
        beyond[3] += h * scale > depth * v->half_height + lens;
        beyond[4] += -h * scale > depth * v->half_height + lens;
    }
    for (int side = 0; side < 5; side++)
        if (beyond[side] == 8) return true;
    return false;
}

void parser_note_mesh_nodes(parser *p, size_t once, size_t shared, int shared_meshes,
                            int instances) {
    if (p->view_count == 0) return;
    mesh_view *v = &p->views[p->view_count - 1];
    v->once = once;
    v->shared = shared;
    v->shared_meshes = shared_meshes;
    v->instances = instances;
}

void parser_report_meshes(parser *p) {
    view v = view_of(&p->s);
    const mesh_view *first = NULL;
    size_t more = 0;
    for (size_t k = 0; k < p->view_count; k++) {
        const mesh_view *m = &p->views[k];
        bool out = outside(&v, m->lo, m->hi);
        char shared[160] = "";
        if (m->instances)
            snprintf(shared, sizeof shared,
                     " (%zu unique: %zu placed once, %zu in %d meshes that %d instances share)",
                     m->once + m->shared, m->once, m->shared, m->shared_meshes, m->instances);
        log_debug(
            "mesh '%s' (line %d): %zu faces%s, bounding box after its transform %g %g %g to "
            "%g %g %g%s",
            m->path, m->line, m->faces, shared, (double)m->lo.x, (double)m->lo.y, (double)m->lo.z,
            (double)m->hi.x, (double)m->hi.y, (double)m->hi.z,
            out ? ", wholly outside the camera's view" : "");
        if (out && !first)
            first = m;
        else if (out)
            more++;
    }
    if (!first) return;
    vec3 c = p->s.camera_position;
    char others[64] = "";
    if (more)
        snprintf(others, sizeof others, " (and %zu more mesh line%s)", more, more == 1 ? "" : "s");
    parser_warn(p, first->line, first->col,
                "mesh '%s' lies wholly outside the camera's view%s: its bounding box after the "
                "transform is %g %g %g to %g %g %g, and the camera at %g %g %g looks along %g %g "
                "%g; it shows only in reflections, shadows and reflected light. Move the camera "
                "or the mesh (render --verbose prints every mesh's box)",
                first->path, others, (double)first->lo.x, (double)first->lo.y, (double)first->lo.z,
                (double)first->hi.x, (double)first->hi.y, (double)first->hi.z, (double)c.x,
                (double)c.y, (double)c.z, v.f.x, v.f.y, v.f.z);
}
