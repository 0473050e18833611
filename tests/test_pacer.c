/* test_pacer.c: src/cli/render_pacer.c driving a real render on the back end argv[1] names
 * ("cpu", or "vulkan": exit 77 when no device exists): SIGINT or SIGTERM during a pass makes
 * the back end abandon it (the CPU back end at its next tile, the Vulkan one at its next
 * submission) rather than finish it (a stop does not wait for a whole pass; the checkpoint holds
 * the part as before it); one that comes after the
 * last pass, which no next pass sees, is obeyed as between passes (a checkpoint of the finished
 * part, the render stopped, so `trazador render` exits 128 + signal without an output), where it
 * was lost. The signals are raised from the render's own control, so nothing depends on
 * timing. */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "cli/render_pacer.h"
#include "render/part.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "scene/scene.h"
#include "tmp_dir.h"
#include "util/log.h"

static bool use_vulkan;

/* The pacer's control, raising `sig` once the first pass is decided. */
typedef struct signalling {
    render_control inner;
    int sig;
} signalling;

static uint32_t next_then_raise(void *user, uint32_t done, bool *sync) {
    signalling *s = user;
    uint32_t chunks = s->inner.next_pass(s->inner.user, done, sync);
    if (s->sig) raise(s->sig);
    s->sig = 0;
    return chunks;
}

static bool forward_synced(void *user, const part *p) {
    signalling *s = user;
    return s->inner.synced(s->inner.user, p);
}

/* Renders 16 spp (one chunk: the first pass is the last) with sig raised during that pass
 * (after: raised once the back end has returned, before the pacer stops); the pacer's verdict in
 * *stopped_by, the samples its checkpoint holds in *samples (-1: none written). */
static bool render_signalled(int sig, bool after, const char *checkpoint, int *stopped_by,
                             int *samples) {
    static const char text[] =
        "camera position 0 0 -5\nplane width 1 height 1 pixel 0.125\n"
        "light position 0 3 -3 power 20\nsphere lambertian center 0 0 0 radius 1\n";
    scene s;
    scene_error err;
    if (!scene_parse_string(text, sizeof text - 1, "pacer.scene", &s, &err)) return false;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.spp = 16;
    opts.threads = 1;
    part_meta meta;
    render_part_meta(&s, &opts, &meta);
    part p;
    bool ok = part_init(&p, &meta);
    render_pacer pc = {.checkpoint = checkpoint, .every = 1000.0};
    signalling sg = {.sig = after ? 0 : sig};
    render_pacer_start(&pc, &sg.inner);
    render_control control = sg.inner;
    control.next_pass = next_then_raise;
    control.synced = forward_synced;
    control.user = &sg;
    opts.control = &control;
    const render_backend *b = use_vulkan ? &render_backend_vulkan : &render_backend_cpu;
    char reason[RENDER_REASON_SIZE];
    ok = ok && b->render_part(&s, &opts, &p, meta.spp, reason) == RENDER_DONE;
    if (after) raise(sig);
    ok = render_pacer_stop(&pc, ok ? &p : NULL) && ok;
    *stopped_by = pc.stopped_by;
    part back;
    *samples = -1;
    if (part_read(checkpoint, &back)) {
        *samples = (int)(back.meta.sample_end - back.meta.sample_begin);
        part_free(&back);
    }
    part_free(&p);
    scene_free(&s);
    return ok;
}

int main(int argc, char **argv) {
    log_set_level(LOG_ERROR);
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        fprintf(stderr, "test_pacer: no Vulkan device; skipped\n");
        return 77;
    }
    if (!tmp_dir_make(use_vulkan ? "test_pacer_vulkan" : "test_pacer")) return 1;
    static const int stops[2] = {SIGTERM, SIGINT};
    static const char *const names[2] = {"SIGTERM", "SIGINT"};
    const char *path = tmp_path("ck.exr");
    for (int k = 0; k < 2; k++) {
        int by = -1, samples = -1;
        /* During a pass, the back end abandons it (the part as before it): the stop does
         * not wait for the pass; the checkpoint holds what was whole, here nothing. */
        CHECK(render_signalled(stops[k], false, path, &by, &samples), "%s in the pass", names[k]);
        CHECK(by == stops[k] && samples == 0, "%s in the pass: stopped by %d, checkpoint of %d",
              names[k], by, samples);
        unlink(path);
        /* After the last pass, before the pacer stops: obeyed all the same. */
        CHECK(render_signalled(stops[k], true, path, &by, &samples), "%s after the last pass",
              names[k]);
        CHECK(by == stops[k] && samples == 16,
              "%s after the last pass: stopped by %d, checkpoint of %d", names[k], by, samples);
        unlink(path);
    }
    /* SIGUSR1 checkpoints and lets the render end as usual, its pass whole. */
    int by = -1, samples = -1;
    CHECK(render_signalled(SIGUSR1, false, path, &by, &samples), "SIGUSR1 in the pass");
    CHECK(by == 0 && samples == 16, "SIGUSR1 in the pass: stopped by %d, checkpoint of %d", by,
          samples);
    unlink(path);
    rmdir(tmpdir);
    return check_summary(use_vulkan ? "test_pacer vulkan" : "test_pacer cpu");
}
