/* ggx_albedo.h: the tables of the GGX lobes' multiple scattering (shared_layout.h,
 * TZ_TEXTURE_GGX), computed once a process by deterministic quadrature, so that every run, the
 * C integrators and (through the texture table) the shaders read the same bits. */
#ifndef TRAZADOR_GGX_ALBEDO_H
#define TRAZADOR_GGX_ALBEDO_H

/* The tables themselves, TZ_GGX_TABLE_WORDS floats; shaders/common/microfacet.h reads them in C. */
extern float ggx_albedo_words[];

/* Fills ggx_albedo_words once (thread-safe, idempotent); every caller after the first returns
 * at once. */
void ggx_albedo_prepare(void);

#endif
