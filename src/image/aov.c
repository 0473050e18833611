/* aov.c: the feature images' names, the --aov list and their planes (aov.h). */
#include "image/aov.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/big_memory.h"
#include "util/log.h"

static const char *const names[AOV_COUNT] = {"albedo", "normal", "depth", "position", "emission"};
/* OpenEXR's usual channel letters: colours R G B, vectors X Y Z, depth Z. */
static const char *const letters[AOV_COUNT] = {"RGB", "XYZ", "Z", "XYZ", "RGB"};

const char *aov_name(aov_kind k) { return names[k]; }

int aov_channels(aov_kind k) { return k == AOV_DEPTH ? 1 : 3; }

void aov_channel_name(aov_kind k, int c, char *out, size_t size) {
    snprintf(out, size, "%s.%c", names[k], letters[k][c]);
}

bool aov_parse_list(const char *text, uint32_t *mask, size_t *bad) {
    *mask = 0;
    const char *at = text;
    for (;;) {
        size_t len = strcspn(at, ",");
        int found = -1;
        for (int k = 0; k < AOV_COUNT; k++)
            if (len == strlen(names[k]) && !strncmp(at, names[k], len)) found = k;
        if (found < 0) {
            *bad = (size_t)(at - text);
            return false;
        }
        *mask |= 1u << found;
        if (!at[len]) return true;
        at += len + 1;
    }
}

bool aov_alloc(aov_set *a, uint32_t mask, size_t pixels) {
    *a = (aov_set){.mask = mask};
    for (int k = 0; k < AOV_COUNT; k++) {
        if (!(mask & 1u << k)) continue;
        a->plane[k] = big_calloc(pixels * (size_t)aov_channels((aov_kind)k), sizeof(float));
        if (!a->plane[k]) {
            log_error("out of memory for the %s image of %zu pixels", names[k], pixels);
            aov_free(a);
            return false;
        }
    }
    return true;
}

void aov_free(aov_set *a) {
    for (int k = 0; k < AOV_COUNT; k++) free(a->plane[k]);
    *a = (aov_set){0};
}
