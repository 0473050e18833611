/* integrator.h: the seed integrator of DESIGN section 3 in C, one sample at a time; the twin of
 * shaders/trace.comp and the oracle the Vulkan back end is checked against. */
#ifndef TRAZADOR_INTEGRATOR_H
#define TRAZADOR_INTEGRATOR_H

#include <stdint.h>

#include "scene_pack.h"

/* Radiance of sample `sample_index` of pixel (i, j), i to the right and j down; never fails. */
vec3 integrator_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index);

/* Nearest sphere hit by the ray o + t d (|d| = 1) with t > EPS, -1 on a miss; `self` is the
 * sphere the ray leaves (-1 for none): its near root is the ray's own origin and is ignored. */
int integrator_nearest(const packed_scene *p, vec3 o, vec3 d, int self, float *t_out);
/* Rays (nearest-hit and shadow) the calling thread has traced so far; never fails. */
uint64_t integrator_rays_traced(void);
/* 1 when a sphere (glass too, as in the seed) blocks o + t d for EPS < t < dist, else 0. */
int integrator_occluded(const packed_scene *p, vec3 o, vec3 d, float dist, int self);

#endif
