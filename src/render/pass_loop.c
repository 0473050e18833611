/* pass_loop.c: the pass loop of both back ends (see pass_loop.h). */
#include "render/pass_loop.h"

#include "util/log.h"

bool pass_loop_run(const render_opts *opts, part *p, uint32_t end_chunk, const char *name,
                   const pass_backend *be) {
    const render_control *control = opts->control;
    uint32_t done = p->stack.end;
    bool sync = false, ok = true;
    uint32_t next =
        control ? control->next_pass(control->user, p->meta.sample_end, &sync) : end_chunk - done;
    if (sync) ok = control->synced(control->user, p); /* nothing rendered yet: p is current */
    while (ok && done < end_chunk && next > 0) {
        uint32_t chunks = next < end_chunk - done ? next : end_chunk - done;
        pass_result result = be->run(be->user, p, done, chunks);
        if (result == PASS_FAILED) return false;
        if (result != PASS_DONE) { /* a stop: the part as the pass began, and the render ends */
            ok = be->sync(be->user, p, done, result);
            next = control->next_pass(control->user, p->meta.sample_end, &sync);
            if (ok && sync) ok = control->synced(control->user, p);
            if (ok && next > 0) {
                log_error("%s back end: a pass was abandoned, yet the render was not stopped",
                          name);
                ok = false;
            }
            return ok;
        }
        done += chunks;
        sync = false;
        next = done < end_chunk && control
                   ? control->next_pass(control->user, part_sample_of(p, done), &sync)
                   : 0u;
        if (sync || next == 0 || done == end_chunk) {
            ok = be->sync(be->user, p, done, PASS_DONE);
            if (ok && sync) ok = control->synced(control->user, p);
        }
    }
    return ok;
}
