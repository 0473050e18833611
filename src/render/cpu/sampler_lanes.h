/* sampler_lanes.h: shaders/common/sampler.h over the LANES lanes of a packet build, each lane its
 * own sample's sampler, kept as arrays of its fields (an array of structs keeps gcc from
 * vectorizing the loops that copy them). The includer defines LANES and LANE_FN first. */
#ifndef TRAZADOR_RENDER_CPU_SAMPLER_LANES_H
#define TRAZADOR_RENDER_CPU_SAMPLER_LANES_H

#include "common/sampler.h"

typedef struct sampler_lanes {
    uint32_t state[LANES], reversed[LANES], dimension[LANES];
} sampler_lanes;

/* Lane k's sampler_state. */
LANE_FN sampler_state lane_sampler(const sampler_lanes *s, int k) {
    sampler_state one = {s->state[k], s->reversed[k], s->dimension[k]};
    return one;
}

/* Lane k takes one where on, else keeps its sampler. */
LANE_FN void lane_sampler_set(sampler_lanes *s, int k, int on, sampler_state one) {
    s->state[k] = on ? one.state : s->state[k];
    s->reversed[k] = on ? one.reversed : s->reversed[k];
    s->dimension[k] = on ? one.dimension : s->dimension[k];
}

/* sample_1d of each lane where take[k], else 0 with its sampler left as it is: the loops over
 * lanes stay branch-free, so they compile to SIMD. */
LANE_FN void draw_lanes_1d(uint32_t flags, sampler_lanes *s, const int *take, float *u) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) { /* the stream: only its state moves */
        for (int k = 0; k < LANES; k++) {
            sampler_state one = {s->state[k], 0u, 0u};
            float x = sample_1d(0u, &one);
            s->state[k] = take[k] ? one.state : s->state[k];
            u[k] = take[k] ? x : 0.0f;
        }
        return;
    }
    for (int k = 0; k < LANES; k++) {
        sampler_state one = lane_sampler(s, k);
        float x = sample_1d(TZ_FLAG_SOBOL, &one);
        lane_sampler_set(s, k, take[k], one);
        u[k] = take[k] ? x : 0.0f;
    }
}

/* sample_2d of each lane where take[k] into u and v, else 0 and 0, as draw_lanes_1d. */
LANE_FN void draw_lanes_2d(uint32_t flags, sampler_lanes *s, const int *take, float *u, float *v) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) {
        for (int k = 0; k < LANES; k++) {
            sampler_state one = {s->state[k], 0u, 0u};
            float x, y;
            sample_2d(0u, &one, &x, &y);
            s->state[k] = take[k] ? one.state : s->state[k];
            u[k] = take[k] ? x : 0.0f;
            v[k] = take[k] ? y : 0.0f;
        }
        return;
    }
    for (int k = 0; k < LANES; k++) {
        sampler_state one = lane_sampler(s, k);
        float x, y;
        sample_2d(TZ_FLAG_SOBOL, &one, &x, &y);
        lane_sampler_set(s, k, take[k], one);
        u[k] = take[k] ? x : 0.0f;
        v[k] = take[k] ? y : 0.0f;
    }
}

#endif
