/* test_pacer.c: src/cli/render_pacer.c driving a real CPU render: a signal that comes during the
 * last pass, which no next pass sees, is obeyed as between passes (a checkpoint of the finished
 * part; SIGINT and SIGTERM stop the render, so `trazador render` exits 128 + signal without an
 * output), where it was lost and the render ended as if never signalled. The signal is raised
 * from the render's own first pass, so nothing depends on timing. */
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "cli/render_pacer.h"
#include "render/part.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmp_dir.h"
#include "util/log.h"

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

/* Renders 16 spp (one chunk: the first pass is the last) with sig raised during it; the pacer's
 * verdict in *stopped_by, whether its checkpoint holds samples 0:16. */
static bool render_signalled(int sig, const char *checkpoint, int *stopped_by) {
    static const char text[] =
        "camera position 0 0 -5\nplane width 1 height 1 pixel 0.125\n"
        "light position 0 3 -3 power 20\nsphere lambertian center 0 0 0 radius 1\n";
    scene s;
    scene_error err;
    if (!scene_parse_string(text, sizeof text - 1, "pacer.scene", &s, &err)) return false;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.samples = 16;
    opts.threads = 1;
    part_meta meta;
    render_part_meta(&s, &opts, &meta);
    part p;
    bool ok = part_init(&p, &meta);
    render_pacer pc = {.checkpoint = checkpoint, .every = 1000.0};
    signalling sg = {.sig = sig};
    render_pacer_start(&pc, &sg.inner);
    render_control control = {.next_pass = next_then_raise, .synced = forward_synced, .user = &sg};
    opts.control = &control;
    ok = ok && render_cpu_part(&s, &opts, &p, meta.spp);
    ok = render_pacer_stop(&pc, ok ? &p : NULL) && ok;
    *stopped_by = pc.stopped_by;
    part back;
    bool written = part_read(checkpoint, &back);
    ok = ok && written && back.meta.sample_end == 16 && back.meta.sample_begin == 0;
    if (written) part_free(&back);
    part_free(&p);
    scene_free(&s);
    return ok;
}

int main(void) {
    log_set_level(LOG_WARN);
    if (!tmp_dir_make("test_pacer")) return 1;
    int stopped_by = -1;
    CHECK(render_signalled(SIGTERM, tmp_path("term.exr"), &stopped_by),
          "SIGTERM in the last pass: no checkpoint of the finished part");
    CHECK(stopped_by == SIGTERM, "SIGTERM in the last pass: stopped by %d", stopped_by);
    CHECK(render_signalled(SIGINT, tmp_path("int.exr"), &stopped_by),
          "SIGINT in the last pass: no checkpoint of the finished part");
    CHECK(stopped_by == SIGINT, "SIGINT in the last pass: stopped by %d", stopped_by);
    /* SIGUSR1 checkpoints and lets the render end as usual. */
    CHECK(render_signalled(SIGUSR1, tmp_path("usr1.exr"), &stopped_by),
          "SIGUSR1 in the last pass: no checkpoint of the finished part");
    CHECK(stopped_by == 0, "SIGUSR1 in the last pass: stopped by %d", stopped_by);
    unlink(tmp_path("term.exr"));
    unlink(tmp_path("int.exr"));
    unlink(tmp_path("usr1.exr"));
    rmdir(tmpdir);
    return check_summary("test_pacer");
}
