/* rng.h: the counter-based RNG for C code outside the integrators (the scene generators, tests);
 * its one text is shaders/common/rng.h, which the shaders compile too. */
#ifndef TRAZADOR_RNG_H
#define TRAZADOR_RNG_H

#include "common/rng.h"

#endif
