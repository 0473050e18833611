/* aov.h: the feature images (AOVs) a denoiser takes beside the colour: first-hit albedo (through
 * mirrors and glass, as OpenImageDenoise asks), world-space normal, depth (the camera ray's
 * distance), position and emission. Their names as EXR layers and files, the list --aov parses,
 * and their planes. */
#ifndef TRAZADOR_AOV_H
#define TRAZADOR_AOV_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum aov_kind {
    AOV_ALBEDO,
    AOV_NORMAL,
    AOV_DEPTH,
    AOV_POSITION,
    AOV_EMISSION,
    AOV_COUNT
} aov_kind;

/* The feature images of a region: plane[k] holds aov_channels(k) floats a pixel, rows top to
 * bottom, for each kind in mask (bit k), else NULL. */
typedef struct aov_set {
    uint32_t mask;
    float *plane[AOV_COUNT];
} aov_set;

/* The layer's name ("albedo", "normal", "depth", "position", "emission"). */
const char *aov_name(aov_kind k);
/* Channels of kind k: 1 for depth, 3 for the others. */
int aov_channels(aov_kind k);
/* The EXR channel c of kind k: "albedo.R", "normal.X", "depth.Z", ... into out. */
void aov_channel_name(aov_kind k, int c, char *out, size_t size);
/* Parses a comma-separated list of names into *mask; false (no log) on an unknown or empty
 * name, with the name's offset in *bad. */
bool aov_parse_list(const char *text, uint32_t *mask, size_t *bad);
/* Zeroed planes of the kinds in mask for `pixels` pixels; false (logged) on out of memory, with
 * a zeroed set. */
bool aov_alloc(aov_set *a, uint32_t mask, size_t pixels);
/* Frees the planes; safe on a zeroed set. */
void aov_free(aov_set *a);

#endif
