/* shared_layout.h: the one definition of every buffer, binding and constant the shaders read.
 * Included by C (src/render/scene_pack.c, the C integrator) and by GLSL (the shaders in
 * shaders/). std430 (the frame std140), in 16-byte groups of vec4s or four 32-bit scalars, so
 * that both rules give the same offsets; src/render/scene_pack.c asserts every size and offset. */
#ifndef TRAZADOR_SHARED_LAYOUT_H
#define TRAZADOR_SHARED_LAYOUT_H

#ifdef GL_core_profile
#define TZ_VEC4 vec4
#define TZ_UVEC4 uvec4
#define TZ_UINT uint
#define TZ_FLOAT_CONST(x) (x)
#else
#include <stdint.h>
typedef struct tz_vec4 {
    float x, y, z, w;
} tz_vec4;
typedef struct tz_uvec4 {
    uint32_t x, y, z, w;
} tz_uvec4;
#define TZ_VEC4 tz_vec4
#define TZ_UVEC4 tz_uvec4
#define TZ_UINT uint32_t
#define TZ_FLOAT_CONST(x) (x##f)
#endif

/* Ray offset: EPS * max(1, largest |coordinate| of the point), so that it grows with float
 * spacing away from the origin. */
#define TZ_EPS TZ_FLOAT_CONST(1e-4)
#define TZ_PI TZ_FLOAT_CONST(3.14159265358979)

#define TZ_MATERIAL_LAMBERTIAN 0
#define TZ_MATERIAL_PHONG 1
#define TZ_MATERIAL_MIRROR 2
#define TZ_MATERIAL_REFRACTIVE 3
/* GGX microfacet kinds (shaders/common/microfacet.h): a rough mirror (`mirror roughness` above
 * 0), glTF 2.0's metallic-roughness model (`pbr`) and rough glass (`refractive roughness` above
 * 0, shaders/common/dielectric.h). */
#define TZ_MATERIAL_CONDUCTOR 4
#define TZ_MATERIAL_PBR 5
#define TZ_MATERIAL_DIELECTRIC 6
/* The smallest GGX width (roughness^2) a material packs (scene_pack.c): below it D's peak,
 * 1 / (pi alpha^2), outgrows float and what light sampling can find; a mirror's roughness 0 is
 * the delta mirror itself. */
#define TZ_GGX_MIN_ALPHA TZ_FLOAT_CONST(1e-3)

#define TZ_FLAG_JITTER 1u
#define TZ_FLAG_INDIRECT 2u
#define TZ_FLAG_PATH 4u     /* path mode (DESIGN section 3.2), else report mode */
#define TZ_FLAG_ROULETTE 8u /* path mode: Russian roulette from the fourth vertex */
/* Path mode's light sampling alone (no MIS, emission found by BSDF rays not counted) or BSDF
 * sampling alone (emitters not sampled): for tests that the strategies agree. */
#define TZ_FLAG_LIGHTS_ONLY 16u
#define TZ_FLAG_BSDF_ONLY 32u
/* Owen-scrambled Sobol points (shaders/common/sampler.h) instead of the random stream. */
#define TZ_FLAG_SOBOL 64u
/* The scene has triangles; without it their code is dead wherever the flags are a
 * specialization constant (trace.comp's FLAGS). */
#define TZ_FLAG_TRIANGLES 128u
/* Some material has a texture (TZ_BINDING_TEXTURES): without it the lookups are dead code. */
#define TZ_FLAG_TEXTURES 256u
/* The scene has an environment map: without it the map's code is dead as the triangles' is
 * (lavapipe ran path mode 1.6x slower with it compiled in). */
#define TZ_FLAG_ENVIRONMENT 512u
/* The scene has a microfacet material (TZ_MATERIAL_CONDUCTOR, _PBR, _DIELECTRIC); without it their
 * code is dead as the triangles'. */
#define TZ_FLAG_MICROFACET 1024u
/* A thin lens camera (gpu_frame.lens): its numbers are drawn after the jitter's, only then, so
 * that pinhole scenes keep their numbers (shaders/common/camera.h). */
#define TZ_FLAG_LENS 2048u
/* An orthographic camera: rays along F from the plane's points (camera.h). */
#define TZ_FLAG_ORTHOGRAPHIC 4096u
/* Some light is a spot or a sun (gpu_light.shape): without it shapes are not read, and the
 * lights may be unrolled (their shapes are no specialization constants). */
#define TZ_FLAG_SHAPED_LIGHTS 8192u
/* Path mode: the sun has a disc (angle > 0), an emitter of the emitter table (TZ_SUN_PRIMITIVE)
 * sampled in its cone and found by rays that leave the scene (common/emitter.h). */
#define TZ_FLAG_SUN_DISC 16384u
/* Some face's material has an alpha map (a cut-out, common/primitive.h's face_cut): without it no
 * walk looks one up. */
#define TZ_FLAG_CUTOUTS 65536u
/* The scene places models as instances (struct gpu_instance): its walks take the two levels. */
#define TZ_FLAG_INSTANCES 131072u

/* Compute workgroup: 8 x 4 invocations, four lavapipe subgroups of 8 (each a row of 8 neighbouring
 * pixels, whose rays stay coherent; 4 x 8 ran more instructions: docs/PERF.md), 32 lanes on real
 * GPUs. */
#define TZ_GROUP_X 8
#define TZ_GROUP_Y 4
/* Rows of the accumulation band a dispatch binds (its dynamic offsets are whole bands, aligned
 * for any device); a dispatch's tile lies within one band and is at most this wide. */
#define TZ_BAND_ROWS 256u

/* Descriptor bindings of set 0. Spheres and lights are uniform texel buffers (RGBA32F) over the
 * very bytes of the gpu_sphere and gpu_light arrays: a sphere is texels 2k, 2k+1, a light texels
 * 3k to 3k+2. lavapipe gathers texels with a few vector loads where a storage buffer read at a
 * per-lane index costs a scalar loop over the lanes; no size limit short of
 * maxTexelBufferElements. */
#define TZ_BINDING_FRAME 0
#define TZ_BINDING_SPHERES 1
#define TZ_BINDING_LIGHTS 2
/* Dynamic: bound at the first row of each band of tiles. A vec4 a pixel: the RGB sums of the
 * open chunk and the count of finite samples of the whole part. */
#define TZ_BINDING_ACCUM 3
/* TZ_COUNTER_WORDS uints since the last reset: samples dropped as non-finite, samples dropped
 * for running out of TZ_SPEC_WALK_BUDGET, and rays traced as low and high 32 bits (a pass over a
 * big image traces more than 2^32 rays; the shader carries into the high word). */
#define TZ_BINDING_COUNTERS 4
#define TZ_COUNTER_WORDS 4
/* Texels 4k..4k+3: gpu_bvh_node k, read as uints (one zeroed node without a BVH). */
#define TZ_BINDING_NODES 5
/* Dynamic, bound as TZ_BINDING_ACCUM: a vec4 a pixel, the compensation of the open chunk's RGB
 * sums (Kahan summation, common/film_sum.h), w unused. A buffer of its own, so that each
 * stays within the 32-bit dynamic offsets as the sums alone did. */
#define TZ_BINDING_ACCUM_COMP 6
/* Texels 2e, 2e + 1: gpu_emitter e (one zeroed emitter without any). */
#define TZ_BINDING_EMITTERS 7
/* Dynamic, bound as TZ_BINDING_ACCUM: pass.stack_depth blocks of 3 floats a pixel, the values of
 * the pixel's chunk-tree blocks (src/render/chunk_tree.h), bottom first. */
#define TZ_BINDING_STACK 8
/* Texels 3t..3t+2: gpu_triangle t (one zeroed triangle without any). */
#define TZ_BINDING_TRIANGLES 9
/* Texels 3m..3m+2: gpu_material m, the materials of the spheres and the triangles (one zeroed
 * without any). */
#define TZ_BINDING_MATERIALS 10
/* Texels 3s..3s+2: gpu_normals s, the shading normals of the smooth triangles (one zeroed). */
#define TZ_BINDING_NORMALS 11
/* Texels 4k..4k+3: gpu_wide_node k, read as uints (one zeroed node without a BVH). */
#define TZ_BINDING_WIDE_NODES 12
/* Words (R32_UINT texels) of the texture table, TZ_TEXTURE_* below (one zeroed word without
 * textures). */
#define TZ_BINDING_TEXTURES 13
/* The environment map (common/emitter.h): texels 0..w*h-1 the map, rows top down (rgb its
 * radiance, w the pdf of its texel over the unit square of the map), then the sampling tables
 * as floats, four a texel: the marginal cdf of the rows (h + 1), then each row's conditional cdf
 * (w + 1 each). One zeroed texel without a map. */
#define TZ_BINDING_ENVIRONMENT 14
/* Texels 7i..7i+6: gpu_instance i, read as uints (its model's node and face indices are no
 * floats), one zeroed instance without any. */
#define TZ_BINDING_INSTANCES 15
#define TZ_BINDING_COUNT 16
/* The ray query module only: the top-level acceleration structure of the scene's primitives
 * (AABB primitive k is primitive id k), one binding past the others. */
#define TZ_BINDING_ACCEL 16

/* Specialization constants of trace.comp: the sphere and light counts when their loops are
 * unrolled (constant indices, no loop bookkeeping), 0 for a plain loop over frame.sphere_count
 * and light_count (src/render/vk/render_vk.c decides); and frame.flags (TZ_FLAG_*), so that code
 * a render never runs is compiled out (lavapipe pays for masked-off SIMD code). */
#define TZ_SPEC_UNROLLED_SPHERES 0
#define TZ_SPEC_UNROLLED_LIGHTS 1
#define TZ_SPEC_FLAGS 2
/* Loop passes one ray's BVH walk may take (a pop, a node visit and a sphere test a pass)
 * before the sample is dropped and counted, rather than cut short silently by lavapipe's loop
 * limit, which counts the passes of a whole SIMD group: bounding every walk bounds the group's
 * sum whatever the divergence. 0: unlimited (real GPUs have no such limit). */
#define TZ_SPEC_WALK_BUDGET 3
/* 1: the walk per invocation reads the wide BVH (struct gpu_wide_node), 0: the binary one. */
#define TZ_SPEC_WIDE_BVH 4
/* The most spheres and lights whose loops are unrolled. Their data are specialization constants
 * too, the floats of struct gpu_unrolled from constant_id TZ_SPEC_SCENE on, so that lavapipe
 * compiles the unrolled tests with immediate operands: no texel fetch (a call that spills every
 * live register) and no per-lane gather. */
#define TZ_UNROLL_MAX_SPHERES 16
#define TZ_UNROLL_MAX_LIGHTS 4
#define TZ_SPEC_SCENE 5

/* One sphere, 32 bytes. Its indices are exactly representable floats (texel buffers and
 * specialization constants are floats; there are at most SCENE_MAX_PRIMITIVES of each). */
struct gpu_sphere {
    TZ_VEC4 center_radius; /* xyz centre, w radius */
    float material;        /* its gpu_material */
    float emitter;         /* its gpu_emitter + 1 (0: none) */
    float pad0, pad1;      /* 0 */
};

/* One triangle, 48 bytes: its corners, what the walks read (the watertight test needs them, not
 * edges). Primitive ids number the spheres first, then the triangles: triangle t is primitive
 * frame.sphere_count + t. */
struct gpu_triangle {
    TZ_VEC4 v0; /* xyz corner 0, w its material (uint bits: a gpu_material index) */
    TZ_VEC4 v1; /* xyz corner 1, w its shading normals (uint bits: a gpu_normals index, or
                 * TZ_FLAT for a flat face) */
    TZ_VEC4 v2; /* xyz corner 2, w its emitter + 1 (0: none), as gpu_sphere params.w */
};
#define TZ_FLAT 0xffffffffu

/* A material of spheres and triangles (struct material of the scene, packed once), 64 bytes.
 * The kind is an exactly representable float, as gpu_sphere's indices. Room is left for what
 * later materials add (roughness, metallic: the reserved floats). */
struct gpu_material {
    TZ_VEC4 color_ks; /* rgb the colour (kd of lambertian and phong, the tint of mirror and
                       * refractive, the base colour of pbr), w the Phong specular weight ks (0:
                       * no lobe), pbr's metallic */
    float alpha;      /* the Phong exponent, the GGX width (roughness^2) of microfacet kinds */
    float ior;        /* the refractive index (1 but for refractive) */
    float kind;       /* TZ_MATERIAL_* */
    float reserved0;  /* 0 */
    TZ_VEC4 emission; /* rgb the radiance emitted (path mode reads it through gpu_emitter),
                       * w reserved (0) */
    TZ_UVEC4 maps;    /* its textures, each a texture slot + 1 (0: none) in 16 bits, map
                       * TZ_MAP_k in bits 16 (k & 1) of word k / 2 (texture.h's map_slot) */
};
/* The maps of a material (scene.h's MAP_*, in that order) and the most texture slots. */
#define TZ_MAP_COLOR 0
#define TZ_MAP_EMISSION 1
#define TZ_MAP_NORMAL 2
#define TZ_MAP_ALPHA 3
#define TZ_MAP_METALLIC_ROUGHNESS 4 /* glTF's: blue metallic, green roughness */
#define TZ_MAP_ROUGHNESS 5          /* MTL's map_Pr: red */
#define TZ_MAP_METALLIC 6           /* MTL's map_Pm: red */
#define TZ_MAX_SLOTS 65535u

/* The unit shading normals at a smooth triangle's corners, 48 bytes. */
struct gpu_normals {
    TZ_VEC4 n0, n1, n2; /* w unused (0) */
};

/* The texture table (TZ_BINDING_TEXTURES), 32-bit words: what decodes an 8-bit channel (word k
 * of TZ_TEXTURE_SRGB the float bits of sRGB value k decoded, of TZ_TEXTURE_LINEAR k / 255), the
 * GGX tables (TZ_TEXTURE_GGX, zero in a scene without microfacet materials), a header
 * (TZ_TEXTURE_HEADER: the first word of the slots, of the images, of the faces' UVs), the slots
 * (TZ_SLOT_WORDS each: an image, how it is read, and a transform of the UVs), the images
 * (TZ_IMAGE_WORDS each: the first word of its texels, width, height, TZ_TEXEL_*), the UVs of the
 * faces that have them (six floats, u and v of corners 0, 1, 2, at the face's gpu_normals index),
 * then the texels, rows top first. */
#define TZ_TEXTURE_SRGB 0u
#define TZ_TEXTURE_LINEAR 256u
/* The multiple-scattering tables of the GGX lobes (Kulla and Conty 2017; src/render/ggx_albedo.c
 * computes them, shaders/common/microfacet.h reads them bilinearly): the directional albedo E of
 * a white GGX conductor at TZ_GGX_TABLE_SIZE square roots of cosines 0..1 of the way back
 * (fastest) by as many roughnesses 0..1 (square roots of the GGX width), then its
 * cosine-weighted mean E_avg at each roughness, floats. The table exists where a scene has
 * textures or a microfacet material; these words are zero without the latter. */
#define TZ_TEXTURE_GGX 512u
#define TZ_GGX_TABLE_SIZE 32u
#define TZ_GGX_TABLE_WORDS 1056u /* TZ_GGX_TABLE_SIZE^2 + TZ_GGX_TABLE_SIZE */
#define TZ_TEXTURE_HEADER 1568u  /* TZ_TEXTURE_GGX + TZ_GGX_TABLE_WORDS */
#define TZ_TEXTURE_FIRST_SLOT 1572u
/* A slot: image index, flags (wrap of u in bits 0-3, of v in 4-7, TZ_SLOT_SRGB), a parameter
 * (the alpha cutoff, the normal scale), the UV transform u' = m0 u + m1 v + m2, v' = m3 u + m4 v
 * + m5 in words 3-8 (float bits), words 9-11 zero. */
#define TZ_SLOT_WORDS 12u
#define TZ_IMAGE_WORDS 4u
#define TZ_WRAP_REPEAT 0u
#define TZ_WRAP_CLAMP 1u
#define TZ_WRAP_MIRROR 2u
#define TZ_SLOT_SRGB 256u      /* an 8-bit image's RGB is sRGB (colour and emission maps) */
#define TZ_SLOT_ALPHA_RED 512u /* an alpha map whose image has no alpha: its red is the alpha */
/* glTF's BLEND: the alpha is the share of rays that meet the face (texture.h's alpha_cut). */
#define TZ_SLOT_STOCHASTIC 1024u
/* Texel formats: a word a texel (R in bits 0-7, G, B, A), or four floats a texel. */
#define TZ_TEXEL_RGBA8 0u
#define TZ_TEXEL_RGBA32F 1u

/* One point light, 32 bytes. */
/* A light, 48 bytes: a point light, a spot (shape.w > 0) or a sun (shape.w < 0). A spot's
 * falloff is glTF KHR_lights_punctual's, clamp(cd scale + offset, 0, 1)^2 of the cosine cd
 * between its axis and the way the light goes. */
struct gpu_light {
    TZ_VEC4 position_power; /* xyz position (a sun: the unit direction toward it), w power (a
                             * sun: its irradiance) */
    TZ_VEC4 color;          /* rgb colour, w: a spot's offset, 0 otherwise */
    TZ_VEC4 shape;          /* a spot: xyz its unit axis, w its scale (> 0); a sun: w -1; a point
                             * light: 0 (read only under TZ_FLAG_SHAPED_LIGHTS) */
};

/* Everything per render that is not per sphere or light: camera, plane, counts, settings. */
struct gpu_frame {
    TZ_VEC4 origin;        /* camera position, w pixel size */
    TZ_VEC4 right;         /* R, w -width/2 */
    TZ_VEC4 up;            /* U, w height/2 */
    TZ_VEC4 forward;       /* F, w distance to the plane (2 width) */
    TZ_VEC4 background;    /* rgb, w unused (0) */
    TZ_UINT width, height; /* of the image, in pixels */
    TZ_UINT sphere_count, light_count;
    TZ_UINT seed, bounces;
    TZ_UINT flags;          /* TZ_FLAG_* */
    TZ_UINT node_count;     /* of the BVH, 0 without one */
    float near_distance;    /* camera rays start this far along their direction (`near`) */
    TZ_UINT emitter_count;  /* path mode's emissive spheres and triangles */
    TZ_UINT triangle_count; /* primitives sphere_count to sphere_count + triangle_count - 1 */
    TZ_UINT light_samples;  /* path mode: emitter samples a diffuse vertex, at least 1 */
    /* The environment map's frame: the rows of the rotation from world to map directions (w
     * unused, 0), then its size in texels (0 without a map: the background is seen) and its
     * emitter slot + 1 in path mode (0: not sampled). */
    TZ_VEC4 env_x, env_y, env_z;
    TZ_UINT env_width, env_height, env_slot;
    TZ_UINT sun_slot; /* path mode: the sun disc's emitter slot + 1 (TZ_FLAG_SUN_DISC) */
    TZ_VEC4 lens;     /* x the lens radius, y the distance to the plane in focus (TZ_FLAG_LENS) */
    TZ_VEC4 sun; /* the sun disc: xyz the unit direction toward it, w 1 - cos(half its angle) */
    TZ_UINT instance_count; /* struct gpu_instance, 0 without instances */
    TZ_UINT instance_leaf;  /* the id of instance 0 in the BVH's leaves (instances follow the
                             * triangles, the models' included) */
    TZ_UINT instance_shift; /* an instance's faces' keys: bits of its index's shift (below) */
    TZ_UINT pad0;           /* 0 */
};

/* Instances (DESIGN section 3.4): one model's faces and BVH, stored once (triangles after the
 * scene's own, the model's nodes after the scene's tree) and placed by a transform. A hit on
 * face f of instance i (f counted from its model's first triangle) is primitive id
 * TZ_INSTANCE_KEY + (i << frame.instance_shift) + f: the tie rule orders instances, and a ray
 * leaving one face of one instance (`self`) still meets the same face of another. */
#define TZ_INSTANCE_KEY 0x40000000
struct gpu_instance {
    TZ_VEC4 to_object[3]; /* rows of world -> model space: xyz the 3 x 3 part, w translation */
    TZ_VEC4 to_world[3];  /* rows of model -> world space, the same way */
    TZ_UVEC4 model;       /* x its model's root node, y its first triangle, z 1 when its
                           * transform is the identity (then never applied: exact bits), w 0 */
};

/* The primitive id of the environment's gpu_emitter (uint bits): no sphere's or face's. */
#define TZ_ENV_PRIMITIVE 0xfffffffeu
/* The primitive id of the sun disc's gpu_emitter (uint bits). */
#define TZ_SUN_PRIMITIVE 0xfffffffdu
/* Where an environment light sample's shadow ray ends: the largest float, past every hit. */
#define TZ_ENV_DISTANCE TZ_FLOAT_CONST(3.40282347e38)

/* One emissive sphere or triangle of path mode, 32 bytes: emitters are picked in proportion to
 * their power by the first cdf above a uniform number. */
struct gpu_emitter {
    TZ_VEC4 emission_pick; /* rgb emitted radiance, w the probability of picking it */
    TZ_VEC4 primitive_cdf; /* x its primitive id (uint bits), y the running sum of picks, z its
                            * area (triangles) */
};

/* Samples a chunk of the chunk tree holds (src/render/chunk_tree.h; the last chunk of a render
 * may hold fewer). Sample ranges split at multiples of it merge exactly. */
#define TZ_CHUNK_SAMPLES 16u
/* The most chunks one dispatch spans: fewer dispatches, so fewer joins of lavapipe's threads. */
#define TZ_PASS_CHUNKS 8
/* Push constants of one dispatch: which tile of the region and which samples (count >= 1, taken
 * in order, over chunk_count chunks of TZ_CHUNK_SAMPLES), and where each chunk it closes goes on
 * the pixel's stack of chunk-tree blocks (src/render/chunk_tree.h). */
struct gpu_pass {
    TZ_UINT x0, y0; /* the tile's corner in pixels of the region */
    TZ_UINT first_sample, sample_count;
    TZ_UINT group_stride;         /* workgroup stride (see trace.comp) */
    TZ_UINT region_x0, region_y0; /* the region's corner in the image */
    TZ_UINT region_width, region_height;
    TZ_UINT chunk_flags; /* TZ_CHUNK_OPEN: restart the first chunk's sums; TZ_CHUNK_CLOSE: push
                          * the last one */
    TZ_UINT chunk_count; /* chunks the samples span, 1 to TZ_PASS_CHUNKS: the first and the last
                          * as the flags say, the others whole */
    TZ_UINT stack_depth; /* blocks a pixel has room for in TZ_BINDING_STACK */
    /* The noise threshold's bits (a float; 0: off). When on, a pixel's last two blocks of
     * TZ_BINDING_STACK hold its state (common/adaptive.h): the odd chunks' sum, then the chunk
     * it stopped at (0 while sampled) and two zeros. */
    TZ_UINT noise_threshold;
    TZ_UINT pad1, pad2, pad3; /* 0 */
    /* chunk_stack_push for chunk c: where its value goes (low 16 bits), merges after (high) */
    TZ_UINT stack_slot[TZ_PASS_CHUNKS];
};
#define TZ_CHUNK_OPEN 1u
#define TZ_CHUNK_CLOSE 2u

/* The spheres and lights of an unrolled scene, zero past the scene's (scene_pack_unrolled):
 * sphere k is vec4s 3k..3k+2, its centre and radius, then its material's colour and ks, and
 * alpha, ior, kind and its emitter + 1 (the fields a hit reads, without a fetch of its
 * material); light k is vec4s 2k, 2k + 1, its position_power and color (lights of a scene
 * without spots and suns only: their shapes are no constants). */
struct gpu_unrolled {
    TZ_VEC4 spheres[3 * TZ_UNROLL_MAX_SPHERES];
    TZ_VEC4 lights[2 * TZ_UNROLL_MAX_LIGHTS];
};

/* BVH: the inner nodes of a binary SAH tree, depth first, the root first. A node holds its two
 * children's boxes and, in lo.w (uint bits), each child's reference: a leaf's sphere count
 * (1..TZ_BVH_LEAF_MAX) in the bits from TZ_BVH_COUNT_SHIFT up and its first sphere below them,
 * or count 0 and the inner child's index. A tree that is one leaf is a root whose right child is
 * empty: a box at +infinity, which no ray enters (its slab distances are all +inf or all -inf on
 * each axis), and reference 0. */
#define TZ_BVH_MAX_DEPTH 48 /* the build never exceeds it: traversal stacks hold this many */
#define TZ_BVH_LEAF_MAX 8
#define TZ_BVH_COUNT_SHIFT 28u
#define TZ_BVH_INDEX_MASK 0x0fffffffu

struct gpu_bvh_node {
    TZ_VEC4 left_lo;  /* xyz the left child's box minimum, w its reference */
    TZ_VEC4 left_hi;  /* xyz its maximum, w unused (0) */
    TZ_VEC4 right_lo; /* the same for the right child */
    TZ_VEC4 right_hi;
};

/* The same tree with up to four children a node, for the shaders' walk per invocation (each
 * node visit four texels, as a binary node's, for twice the children): src/render/bvh_wide.c
 * collapses the binary nodes, depth first, the root first. Child c's box is quantized to 8 bits
 * an axis in the node's frame: its minimum on axis a is origin[a] + q * 2^(e[a] - 127), which
 * the product being exact makes one rounding in C and GLSL alike; the builder rounds every q
 * outwards until the decoded box holds the exact one, so the walk never misses what the binary
 * boxes find. refs[c] is a reference as in gpu_bvh_node, 0 for no child (the root is no one's
 * child). A walk pushes at most TZ_WIDE_STACK children (the builder keeps every path within). */
#define TZ_WIDE_CHILDREN 4
#define TZ_WIDE_STACK 64
struct gpu_wide_node {
    TZ_UVEC4 origin_exponents; /* xyz the frame's origin (float bits), w the biased exponents
                                * of its scale: x in bits 0-7, y 8-15, z 16-23 */
    TZ_UVEC4 refs;             /* the children's references */
    TZ_UVEC4 lo;               /* x, y, z: the children's quantized minima on that axis, child c
                                * in bits 8c..8c+7; w: their maxima on x */
    TZ_UVEC4 hi;               /* x, y: the maxima on y and z; z, w unused (0) */
};

#endif
