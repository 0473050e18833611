/* loop_probe.comp: measures how many loop iterations an invocation really completes. Each of the
 * 64 invocations of a workgroup (eight lavapipe subgroups) runs two counting loops one after the
 * other, N1 then N2 iterations (push constants), and writes how many of each ran: lavapipe stops
 * loops silently past a budget: src/render/vk/vk_probe.c measures it for the renderer's guard,
 * and tests/test_vk_loop_limit.c proves the guard with it. */
#version 450

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

layout(push_constant) uniform probe_block { uvec4 n; }; /* x N1, y N2, z step (1) */
layout(std430, set = 0, binding = 0) buffer result_block { uvec2 completed[]; };

void main() {
    /* The step comes from the host so that no compiler can fold a loop into its trip count. */
    uint a = 0u;
    for (uint k = 0u; k < n.x; k++) a += n.z;
    uint b = 0u;
    for (uint k = 0u; k < n.y; k++) b += n.z;
    completed[gl_GlobalInvocationID.x] = uvec2(a, b);
}
