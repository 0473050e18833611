/* integrator_sample.c: both modes' one-sample C integrators, the shared texts of
 * shaders/common/ (report.h, path.h) over the packed scene: the references that the packet
 * builds are checked against (test_packet); and a sample's first-hit features (aov.h). */
#include "render/cpu/scene_accessors.h"

/* The shared texts call the accessors above. */
#include "common/aov.h"
#include "common/path.h"
#include "common/report.h"

vec3 integrator_report_sample(const packed_scene *p, uint32_t i, uint32_t j,
                              uint32_t sample_index) {
    return report_sample(p, i, j, sample_index);
}

vec3 integrator_path_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    return path_sample(p, i, j, sample_index);
}

integrator_aov integrator_aov_sample(const packed_scene *p, uint32_t i, uint32_t j,
                                     uint32_t sample_index) {
    aov_features a = aov_sample(p, i, j, sample_index);
    return (integrator_aov){.albedo = a.albedo,
                            .normal = a.normal,
                            .depth = a.depth,
                            .position = a.position,
                            .emission = a.emission,
                            .hit = a.hit};
}
