/* scene_pack.c: fills the shared_layout.h structs from struct scene and checks their layout. */
#include "scene_pack.h"

#include <stddef.h>
#include <stdlib.h>

#include "log.h"

/* std430 with vec4 members only: the C structs must have no padding of their own. */
_Static_assert(sizeof(tz_vec4) == 16, "vec4 is 16 bytes");
_Static_assert(sizeof(tz_uvec4) == 16, "uvec4 is 16 bytes");
_Static_assert(sizeof(struct gpu_sphere) == 48, "gpu_sphere is 48 bytes");
_Static_assert(offsetof(struct gpu_sphere, center_radius) == 0, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, color_ks) == 16, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, params) == 32, "gpu_sphere layout");
_Static_assert(sizeof(struct gpu_light) == 32, "gpu_light is 32 bytes");
_Static_assert(offsetof(struct gpu_light, position_power) == 0, "gpu_light layout");
_Static_assert(offsetof(struct gpu_light, color) == 16, "gpu_light layout");
_Static_assert(sizeof(struct gpu_frame) == 112, "gpu_frame is 112 bytes");
_Static_assert(offsetof(struct gpu_frame, origin) == 0, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, right) == 16, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, up) == 32, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, forward) == 48, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, background) == 64, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, size) == 80, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, settings) == 96, "gpu_frame layout");
_Static_assert(sizeof(struct gpu_pass) == 16, "gpu_pass is 16 bytes");

static tz_vec4 vec4_from(vec3 v, float w) { return (tz_vec4){v.x, v.y, v.z, w}; }

bool scene_pack(const scene *s, const render_opts *opts, packed_scene *out) {
    *out = (packed_scene){0};
    /* One zero element when empty keeps every buffer non-empty for Vulkan. */
    out->spheres = calloc(s->sphere_count ? (size_t)s->sphere_count : 1, sizeof *out->spheres);
    out->lights = calloc(s->light_count ? (size_t)s->light_count : 1, sizeof *out->lights);
    size_t n = ((size_t)s->sphere_count + SOA_LANES - 1) / SOA_LANES * SOA_LANES;
    out->soa.cx = calloc(4 * (n ? n : SOA_LANES), sizeof(float));
    if (!out->spheres || !out->lights || !out->soa.cx) {
        log_error("out of memory packing %d spheres", s->sphere_count);
        packed_scene_free(out);
        return false;
    }
    for (int k = 0; k < s->sphere_count; k++) {
        const sphere *sp = &s->spheres[k];
        out->spheres[k] = (struct gpu_sphere){
            .center_radius = vec4_from(sp->center, sp->radius),
            .color_ks = vec4_from(sp->color, sp->ks),
            .params = {sp->alpha, sp->ior, (float)sp->material, 0.0f},
        };
        out->soa.cx[k] = sp->center.x;
        out->soa.cx[n + k] = sp->center.y;
        out->soa.cx[2 * n + k] = sp->center.z;
        out->soa.cx[3 * n + k] = sp->radius;
    }
    out->soa.cy = out->soa.cx + n;
    out->soa.cz = out->soa.cx + 2 * n;
    out->soa.r = out->soa.cx + 3 * n;
    for (int k = 0; k < s->light_count; k++) {
        const light *l = &s->lights[k];
        out->lights[k] = (struct gpu_light){
            .position_power = vec4_from(l->position, l->power),
            .color = vec4_from(l->color, 0.0f),
        };
    }
    /* Camera frame of DESIGN section 3: F forward, R = up x F to the right, U = F x R. */
    vec3 f = v3_normalize(s->camera_direction);
    vec3 r = v3_normalize(v3_cross(s->camera_up, f));
    vec3 u = v3_cross(f, r);
    uint32_t flags = (opts->no_jitter ? 0u : TZ_FLAG_JITTER) | (opts->indirect ? TZ_FLAG_INDIRECT : 0u);
    out->frame = (struct gpu_frame){
        .origin = vec4_from(s->camera_position, s->pixel_size),
        .right = vec4_from(r, -0.5f * s->plane_width),
        .up = vec4_from(u, 0.5f * s->plane_height),
        .forward = vec4_from(f, 2.0f * s->plane_width),
        .background = vec4_from(s->background, 0.0f),
        .size = {(uint32_t)s->width, (uint32_t)s->height, (uint32_t)s->sphere_count,
                 (uint32_t)s->light_count},
        .settings = {opts->seed, (uint32_t)opts->bounces, flags, 0u},
    };
    return true;
}

void packed_scene_free(packed_scene *p) {
    free(p->spheres);
    free(p->lights);
    free(p->soa.cx);
    *p = (packed_scene){0};
}
