/* render_part_args.c: --region, --samples, --resume and the finished checkpoint of `trazador
 * render` (see render_part_args.h). */
#include "cli/render_part_args.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "util/log.h"

bool render_parse_region(const char *text, part_meta *m) {
    long long v[4];
    char rest[2];
    if (text) {
        /* Digits and commas only, as --spp takes digits only: no spaces, no signs. */
        if (strspn(text, "0123456789,") != strlen(text) ||
            sscanf(text, "%lld,%lld,%lld,%lld%1s", &v[0], &v[1], &v[2], &v[3], rest) != 4 ||
            v[0] < 0 || v[0] >= v[1] || v[1] > m->width || v[2] < 0 || v[2] >= v[3] ||
            v[3] > m->height) {
            fprintf(stderr,
                    "trazador: render: --region '%s' must be X0,X1,Y0,Y1 with 0 <= X0 < X1 <= %d "
                    "and 0 <= Y0 < Y1 <= %d (the image is %dx%d)\n",
                    text, m->width, m->height, m->width, m->height);
            return false;
        }
        m->x0 = (int)v[0], m->x1 = (int)v[1], m->y0 = (int)v[2], m->y1 = (int)v[3];
    }
    return true;
}

bool render_parse_samples(const char *text, part_meta *m, uint32_t *end) {
    *end = m->spp;
    if (!text) return true;
    long long v[2];
    char rest[2];
    if (strspn(text, "0123456789:") != strlen(text) ||
        sscanf(text, "%lld:%lld%1s", &v[0], &v[1], rest) != 2 || v[0] < 0 || v[0] >= v[1] ||
        v[1] > m->spp || v[0] % TZ_CHUNK_SAMPLES != 0 ||
        (v[1] % TZ_CHUNK_SAMPLES != 0 && v[1] != m->spp)) {
        fprintf(stderr,
                "trazador: render: --samples '%s' must be A:B with 0 <= A < B <= %u (the samples "
                "per pixel), A a multiple of %u and B one too or %u: parts merge exactly in "
                "whole chunks of %u samples\n",
                text, m->spp, TZ_CHUNK_SAMPLES, m->spp, TZ_CHUNK_SAMPLES);
        return false;
    }
    m->sample_begin = (uint32_t)v[0];
    *end = (uint32_t)v[1];
    return true;
}

/* What keeps checkpoint m from going on to this render (want, to sample end) into why, naming
 * both sides: the fields the digest covers first, the digest (the scene, other settings) last;
 * "" when nothing does. */
static void resume_difference(const part_meta *m, const part_meta *want, uint32_t end, bool open,
                              char *why, size_t size) {
    why[0] = '\0';
    if (strcmp(m->version, want->version))
        snprintf(why, size, "another trazador version: %s, this one %s", m->version, want->version);
    else if (m->seed != want->seed)
        snprintf(why, size, "another seed: %u, this render %u", m->seed, want->seed);
    else if (strcmp(m->mode, want->mode))
        snprintf(why, size, "another mode: %s, this render %s", m->mode, want->mode);
    else if (m->spp != want->spp)
        snprintf(why, size, "other samples per pixel: %u, this render %u", m->spp, want->spp);
    else if (m->width != want->width || m->height != want->height)
        snprintf(why, size, "another image size: %dx%d, this render %dx%d", m->width, m->height,
                 want->width, want->height);
    else if (strcmp(m->digest, want->digest))
        snprintf(why, size,
                 "another scene or other settings: digest %s, this render %s (the scene, bounces, "
                 "indirect, jitter, roulette, sampler or light_samples)",
                 m->digest, want->digest);
    else if (m->x0 != want->x0 || m->x1 != want->x1 || m->y0 != want->y0 || m->y1 != want->y1)
        snprintf(why, size, "another region: this render %d,%d,%d,%d", want->x0, want->x1, want->y0,
                 want->y1);
    else if (m->sample_begin != want->sample_begin)
        snprintf(why, size, "another first sample: this render starts at %u", want->sample_begin);
    else if (m->sample_end > end)
        snprintf(why, size, "samples past this render's end, %u", end);
    else if (open)
        snprintf(why, size, "a chunk left open");
}

/* The back end asked for that cannot go on from a part of the back end `had` ("cpu" or
 * "vulkan: ..."): the other one; NULL for auto, which takes the part's (render_choose_part). */
static const char *other_backend(int backend, const char *had) {
    bool cpu = !strcmp(had, "cpu");
    return backend == BACKEND_CPU && !cpu     ? "cpu"
           : backend == BACKEND_VULKAN && cpu ? "vulkan"
                                              : NULL;
}

bool render_load_resume(const char *path, const part_meta *want, uint32_t end, int backend,
                        part *p) {
    if (!part_read(path, p)) return false;
    const part_meta *m = &p->meta;
    const char *asked = other_backend(backend, m->backend);
    if (asked) {
        log_error(
            "%s: cannot resume this render from it: it was rendered by the %s back end, and "
            "--backend %s asks for the other: the two differ by rounding, so their samples do "
            "not mix (resume it with --backend %s)",
            path, m->backend, asked, strcmp(asked, "cpu") ? "cpu" : "vulkan");
        part_free(p);
        return false;
    }
    char why[2 * PART_TEXT_MAX + 160];
    resume_difference(m, want, end, p->open != NULL, why, sizeof why);
    if (why[0]) {
        log_error(
            "%s: cannot resume this render from it: it holds %s (region %d,%d,%d,%d, "
            "samples %u:%u, digest %s)",
            path, why, m->x0, m->x1, m->y0, m->y1, m->sample_begin, m->sample_end, m->digest);
        part_free(p);
        return false;
    }
    log_info("%s: resuming at sample %u of %u", path, m->sample_end, end);
    return true;
}

bool render_finish_checkpoint(const char *path, bool keep, const part *p) {
    if (keep) return part_write(path, p);
    if (unlink(path) == 0) {
        log_debug("checkpoint: %s removed, the render being complete", path);
    } else if (errno != ENOENT) {
        log_warn("%s: cannot remove the finished render's checkpoint: %s", path, strerror(errno));
    }
    return true;
}
