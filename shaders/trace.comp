/* trace.comp: the per-sample compute entry point. One invocation renders `pass.sample_count`
 * samples (in sample order, over pass.chunk_count chunks) of one pixel of the tile at (pass.x0,
 * pass.y0) of the region and adds each finite one to its chunk's compensated sums exactly as the
 * C back end does, pushing each chunk it closes on the pixel's stack of chunk-tree blocks;
 * non-finite samples are counted instead. report_sample() and path_sample() are the shared texts
 * of shaders/common/report.h and path.h, which the C back end compiles too. Declares the
 * bindings and the scene accessors the included files use. */
#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
/* TZ_SUBGROUP_WALK: the module with the cooperative BVH walk; TZ_RAY_QUERY_WALK: the module that
 * walks the device's acceleration structure (CMakeLists.txt builds all three; GL_EXT_ray_query
 * needs GLSL 4.60, which changes nothing else here). */
#ifdef TZ_SUBGROUP_WALK
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
#endif
#ifdef TZ_RAY_QUERY_WALK
#extension GL_EXT_ray_query : require
#endif

#include "shared_layout.h"

layout(local_size_x = TZ_GROUP_X, local_size_y = TZ_GROUP_Y, local_size_z = 1) in;

layout(std140, set = 0, binding = TZ_BINDING_FRAME) uniform frame_block { gpu_frame frame; };
layout(set = 0, binding = TZ_BINDING_SPHERES) uniform samplerBuffer sphere_texels;
layout(set = 0, binding = TZ_BINDING_LIGHTS) uniform samplerBuffer light_texels;
/* Bound at the tile's first row (a dynamic offset): a band of rows, never the whole image, so
 * the range stays within maxStorageBufferRange for any image width up to 16384. */
layout(std430, set = 0, binding = TZ_BINDING_ACCUM) buffer accum_block { vec4 accum[]; };
layout(std430, set = 0, binding = TZ_BINDING_ACCUM_COMP) buffer accum_comp_block {
    vec4 accum_comp[];
};
layout(std430, set = 0, binding = TZ_BINDING_COUNTERS) buffer counter_block {
    uint nonfinite;
    uint overflow;
    uint rays;
    uint rays_high;
};
layout(set = 0, binding = TZ_BINDING_NODES) uniform usamplerBuffer node_texels;
layout(set = 0, binding = TZ_BINDING_EMITTERS) uniform samplerBuffer emitter_texels;
/* Bound at the tile's first row, as the sums are. */
layout(std430, set = 0, binding = TZ_BINDING_STACK) buffer stack_block { float stack[]; };
layout(set = 0, binding = TZ_BINDING_TRIANGLES) uniform samplerBuffer triangle_texels;
layout(set = 0, binding = TZ_BINDING_MATERIALS) uniform samplerBuffer material_texels;
layout(set = 0, binding = TZ_BINDING_NORMALS) uniform samplerBuffer normals_texels;
layout(set = 0, binding = TZ_BINDING_WIDE_NODES) uniform usamplerBuffer wide_node_texels;
layout(set = 0, binding = TZ_BINDING_TEXTURES) uniform usamplerBuffer texture_texels;
layout(set = 0, binding = TZ_BINDING_ENVIRONMENT) uniform samplerBuffer environment_texels;
layout(set = 0, binding = TZ_BINDING_INSTANCES) uniform usamplerBuffer instance_texels;
#ifdef TZ_RAY_QUERY_WALK
/* The scene's primitives as one AABB geometry of one instance (src/render/vk/vk_accel.c). */
layout(set = 0, binding = TZ_BINDING_ACCEL) uniform accelerationStructureEXT scene_accel;
#endif
layout(push_constant) uniform pass_block { gpu_pass pass; };
layout(constant_id = TZ_SPEC_UNROLLED_SPHERES) const uint UNROLLED_SPHERES = 0u;
layout(constant_id = TZ_SPEC_UNROLLED_LIGHTS) const uint UNROLLED_LIGHTS = 0u;
layout(constant_id = TZ_SPEC_FLAGS) const uint FLAGS = 0u; /* frame.flags */
layout(constant_id = TZ_SPEC_WALK_BUDGET) const uint WALK_BUDGET = 0u;
layout(constant_id = TZ_SPEC_WIDE_BVH) const uint WIDE_BVH = 0u;

#include "spec_scene.glsl"

/* The fields of struct gpu_material m (params: alpha, ior, kind, reserved0). */
vec4 material_color_ks(int m) { return texelFetch(material_texels, 4 * m); }
vec4 material_params(int m) { return texelFetch(material_texels, 4 * m + 1); }
uvec4 material_maps(int m) { return floatBitsToUint(texelFetch(material_texels, 4 * m + 3)); }
/* Word i of the texture table (shared_layout.h, TZ_TEXTURE_*). */
uint texture_word(uint i) { return texelFetch(texture_texels, int(i)).x; }
/* Float i of the GGX tables (TZ_TEXTURE_GGX, common/microfacet.h). */
float ggx_table(uint i) { return uintBitsToFloat(texture_word(TZ_TEXTURE_GGX + i)); }
/* The fields of struct gpu_sphere k and its material (sphere_params: alpha, ior, kind and its
 * emitter + 1), and of gpu_light k: specialization constants when their loops are unrolled
 * (struct gpu_unrolled), else from the texel buffers (see TZ_BINDING_SPHERES). */
vec4 sphere_center_radius(int k) {
    return UNROLLED_SPHERES > 0u ? spec_sphere_center_radius(k) : texelFetch(sphere_texels, 2 * k);
}
vec4 sphere_color_ks(int k) {
    return UNROLLED_SPHERES > 0u
               ? spec_sphere_color_ks(k)
               : material_color_ks(int(texelFetch(sphere_texels, 2 * k + 1).x));
}
/* The material of sphere k (scenes with textures are never unrolled: render_vk.c). */
int sphere_material_index(int k) { return int(texelFetch(sphere_texels, 2 * k + 1).x); }
vec4 sphere_params(int k) {
    if (UNROLLED_SPHERES > 0u) return spec_sphere_params(k);
    vec4 links = texelFetch(sphere_texels, 2 * k + 1); /* material, emitter */
    return vec4(material_params(int(links.x)).xyz, links.y);
}
vec4 light_position_power(int k) {
    return UNROLLED_LIGHTS > 0u ? spec_light_position_power(k) : texelFetch(light_texels, 3 * k);
}
vec4 light_color(int k) {
    return UNROLLED_LIGHTS > 0u ? spec_light_color(k) : texelFetch(light_texels, 3 * k + 1);
}
/* A spot's or a sun's shape; a point light's (and every light without shaped ones): zero. */
vec4 light_shape(int k) {
    return (FLAGS & TZ_FLAG_SHAPED_LIGHTS) != 0u ? texelFetch(light_texels, 3 * k + 2) : vec4(0.0);
}
/* The fields of struct gpu_triangle t and gpu_normals n. */
vec4 triangle_v0(int t) { return texelFetch(triangle_texels, 3 * t); }
vec4 triangle_v1(int t) { return texelFetch(triangle_texels, 3 * t + 1); }
vec4 triangle_v2(int t) { return texelFetch(triangle_texels, 3 * t + 2); }
vec4 normals_n0(int n) { return texelFetch(normals_texels, 3 * n); }
vec4 normals_n1(int n) { return texelFetch(normals_texels, 3 * n + 1); }
vec4 normals_n2(int n) { return texelFetch(normals_texels, 3 * n + 2); }
/* The fields of struct gpu_emitter e (path mode). */
vec4 emitter_emission_pick(int e) { return texelFetch(emitter_texels, 2 * e); }
vec4 emitter_primitive_cdf(int e) { return texelFetch(emitter_texels, 2 * e + 1); }
/* Texel k of the environment map and float k of its sampling tables, four a texel after it. */
vec4 environment_texel(int k) { return texelFetch(environment_texels, k); }
float environment_float(int k) {
    int map = int(frame.env_width * frame.env_height);
    return texelFetch(environment_texels, map + k / 4)[k & 3];
}
/* vec4 f of struct gpu_bvh_node k as uints (0 left_lo, 1 left_hi, 2 right_lo, 3 right_hi). */
uvec4 node_field(uint k, uint f) { return texelFetch(node_texels, int(4u * k + f)); }
/* vec4 f of struct gpu_wide_node k (0 origin_exponents, 1 refs, 2 lo, 3 hi). */
uvec4 wide_node_field(uint k, uint f) { return texelFetch(wide_node_texels, int(4u * k + f)); }

/* Row r of struct gpu_instance i's to_object and to_world, and its model (common/instance.h). */
vec4 instance_to_object(int i, int r) {
    return uintBitsToFloat(texelFetch(instance_texels, 7 * i + r));
}
vec4 instance_to_world(int i, int r) {
    return uintBitsToFloat(texelFetch(instance_texels, 7 * i + 3 + r));
}
uvec4 instance_model(int i) { return texelFetch(instance_texels, 7 * i + 6); }

/* Loop counts: a specialization constant when small enough to unroll, else the frame's. */
uint sphere_count() { return UNROLLED_SPHERES > 0u ? UNROLLED_SPHERES : frame.sphere_count; }
uint light_count() { return UNROLLED_LIGHTS > 0u ? UNROLLED_LIGHTS : frame.light_count; }
#ifdef TZ_PATH_REGENERATE_MODULE
/* This module serves the scenes walked without a BVH alone (render_vk.c): no walk to compile. */
bool use_bvh() { return false; }
#else
/* The BVH serves the scenes too big to unroll, when it was built (frame.node_count nodes). */
bool use_bvh() { return UNROLLED_SPHERES == 0u && frame.node_count > 0u; }
#endif

#include "intersect.glsl"
#include "common/path.h"
#include "common/report.h"
#include "common/film_sum.h"
#include "common/adaptive.h"

/* The pixel of this invocation within the tile. Workgroup n of the dispatch takes block
 * (n * pass.group_stride) mod (the dispatch's workgroups), a stride coprime with that count:
 * lavapipe gives each of its threads one run of consecutive workgroups (Mesa 22.3,
 * lp_cs_tpool), so a run covers the whole tile, not a band of it with more or less work than the
 * others. */
uvec2 tile_pixel() {
    uint groups = gl_NumWorkGroups.x * gl_NumWorkGroups.y;
    uint n = gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    uint block = (n * pass.group_stride) % groups;
    uvec2 corner = uvec2(block % gl_NumWorkGroups.x, block / gl_NumWorkGroups.x);
    return corner * gl_WorkGroupSize.xy + gl_LocalInvocationID.xy;
}

/* chunk_push's stack: the blocks of the pixel at slot, pass.stack_depth of 3 floats each. */
#define CHUNK_STACK_PARAM uint slot,
#define CHUNK_STACK_ARG slot,
#define CHUNK_STACK_FLOAT(k, c) stack[((slot) * pass.stack_depth + (k)) * 3u + (c)]
#include "common/chunk_push.h"

/* Sample l into the chunk's compensated sums, or counted: dropped where it is not finite,
 * overflowed where a walk was cut short (the sample would be wrong). */
void add_sample(vec3 l, inout vec4 sum, inout vec3 comp, inout uint dropped, inout uint overflowed) {
    if (loop_overflow) {
        overflowed++;
        loop_overflow = false;
    } else if (sample_finite(l)) {
        vec3 rgb = sum.xyz;
        film_sum_add(rgb, comp, l);
        sum = vec4(rgb, sum.w + 1.0);
    } else {
        dropped++;
    }
}

void main() {
    uvec2 at = tile_pixel();
    uint ri = pass.x0 + at.x, rj = pass.y0 + at.y; /* in the region */
    if (ri >= pass.region_width || rj >= pass.region_height) return;
    uint i = pass.region_x0 + ri;
    uint j = pass.region_y0 + rj;
    uint slot = (rj % TZ_BAND_ROWS) * pass.region_width + ri; /* in the band bound */
    /* A chunk's sums start from zero (chunk_tree.h); the count goes on over the whole part. The
     * samples span pass.chunk_count chunks: the first opens as the flags say, the last closes as
     * they say, the ones between are whole. */
    precise vec4 sum = accum[slot];
    vec3 comp = accum_comp[slot].xyz;
    uint dropped = 0u, overflowed = 0u;
    loop_overflow = false;
    rays_traced = 0u;
    uint s = pass.first_sample, left = pass.sample_count;
    /* The noise threshold's state (common/adaptive.h) in the pixel's last two blocks: the odd
     * chunks' sum, the chunk it stopped at (0 while sampled). */
    bool adaptive = pass.noise_threshold != 0u;
    float threshold = uintBitsToFloat(pass.noise_threshold);
    uint state = pass.stack_depth - 2u;
    vec3 odd = adaptive ? chunk_stack_load(slot, state) : vec3(0.0);
    uint stopped = adaptive ? uint(CHUNK_STACK_FLOAT(state + 1u, 0u)) : 0u;
    for (uint c = 0u; c < pass.chunk_count; c++) {
        if (c > 0u || (pass.chunk_flags & TZ_CHUNK_OPEN) != 0u) {
            sum = vec4(0.0, 0.0, 0.0, sum.w);
            comp = vec3(0.0);
        }
        bool last = c + 1u == pass.chunk_count;
        uint n = last ? left : TZ_CHUNK_SAMPLES - s % TZ_CHUNK_SAMPLES;
        uint chunk = s / TZ_CHUNK_SAMPLES;
        if (adaptive && stopped == 0u && s % TZ_CHUNK_SAMPLES == 0u &&
            !adaptive_goes_on(chunk_stack_total(slot, pass.stack_slot[c] & 0xffffu), odd, chunk,
                              threshold))
            stopped = chunk;
        if (stopped != 0u) { /* its samples are not drawn: the chunk is zero */
            s += n;
            left -= n;
            if (!last || (pass.chunk_flags & TZ_CHUNK_CLOSE) != 0u)
                chunk_push(slot, pass.stack_slot[c] & 0xffffu, pass.stack_slot[c] >> 16u,
                           film_sum_value(sum.xyz, comp));
            continue;
        }
#if defined(TZ_PATH_REGENERATE_MODULE)
        /* A pass a vertex, a lane whose path ended starting its pixel's next sample at once: the
         * batch's loop runs its longest lane's vertices, not each sample's longest path. For the
         * scenes walked without a BVH: lanes at different vertices walk a BVH less alike. */
        path_state p = path_start(i, j, s);
        for (uint k = 0u; k < n;) {
            p = path_step(p);
            if (p.k != 0u) continue;
            add_sample(p.radiance, sum, comp, dropped, overflowed);
            if (++k < n) p = path_start(i, j, s + k);
        }
#else
        for (uint k = 0u; k < n; k++) {
#if defined(TZ_PATH_MODULE) /* a module of one mode: less for the driver to compile */
            vec3 l = path_sample(i, j, s + k);
#elif defined(TZ_REPORT_MODULE)
            vec3 l = report_sample(i, j, s + k);
#else
            vec3 l = (FLAGS & TZ_FLAG_PATH) != 0u ? path_sample(i, j, s + k)
                                                  : report_sample(i, j, s + k);
#endif
            add_sample(l, sum, comp, dropped, overflowed);
        }
#endif
        s += n;
        left -= n;
        if (!last || (pass.chunk_flags & TZ_CHUNK_CLOSE) != 0u) {
            vec3 v = film_sum_value(sum.xyz, comp);
            chunk_push(slot, pass.stack_slot[c] & 0xffffu, pass.stack_slot[c] >> 16u, v);
            if (adaptive && chunk % 2u == 1u) odd = odd + v;
        }
    }
    if (adaptive) {
        chunk_stack_store(slot, state, odd);
        chunk_stack_store(slot, state + 1u, vec3(float(stopped), 0.0, 0.0));
    }
    accum[slot] = sum;
    if ((pass.chunk_flags & TZ_CHUNK_CLOSE) == 0u) accum_comp[slot] = vec4(comp, 0.0);
    if (dropped > 0u) atomicAdd(nonfinite, dropped);
    if (overflowed > 0u) atomicAdd(overflow, overflowed);
    uint before = atomicAdd(rays, rays_traced);
    if (before + rays_traced < before) atomicAdd(rays_high, 1u); /* the low word wrapped */
}
