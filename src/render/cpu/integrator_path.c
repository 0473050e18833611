/* integrator_path.c: path mode (DESIGN section 3.2) in C, one sample at a time: the reference
 * that the path packet builds (integrator_path_packet.c) are checked against. */
#include "render/cpu/path_accessors.h"

vec3 integrator_path_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    return path_sample(p, i, j, sample_index);
}
