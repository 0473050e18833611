/* test_threads.c: the CPU film is bit-identical for every thread count (tiles are scheduled
 * dynamically, but each pixel sums its samples in sample order), and stays so run to run. */
#include <string.h>

#include "check.h"
#include "render/render.h"

int main(void) {
    scene s;
    scene_error err;
    if (!scene_parse_file(TRAZADOR_SOURCE_DIR "/scenes/cornell.scene", &s, &err)) {
        scene_error_print(&err);
        return 1;
    }
    /* 100 x 100 of the default scene, indirect light on, 8 samples. */
    s.pixel_size = s.plane_width / 100.0f;
    s.width = s.height = 100;
    render_opts o;
    render_opts_from_scene(&s, &o);
    o.spp = 8;
    film reference = {0};
    o.threads = 1;
    CHECK(render_film(&render_backend_cpu, &s, &o, &reference), "render with 1 thread failed");
    const int counts[] = {2, 3, 7, 16, 1};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0] && reference.accum; k++) {
        film f = {0};
        o.threads = counts[k];
        CHECK(render_film(&render_backend_cpu, &s, &o, &f), "render with %d threads failed",
              counts[k]);
        size_t bytes = (size_t)s.width * s.height * 4 * sizeof(float);
        CHECK(f.accum && memcmp(f.accum, reference.accum, bytes) == 0,
              "%d threads: film differs from 1 thread", counts[k]);
        film_free(&f);
    }
    /* And the film is not trivially equal: it has light in it. */
    double sum = 0.0;
    for (int k = 0; reference.accum && k < s.width * s.height; k++) sum += reference.accum[k * 4];
    CHECK(sum > 100.0, "the reference film is dark (%g)", sum);
    film_free(&reference);
    scene_free(&s);
    return check_summary("test_threads");
}
