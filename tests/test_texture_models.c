/* test_texture_models.c: textured models of Debian's assimp-testmodels rendered as the scene (CPU
 * back end, 64 pixels across): BoxTextured as GLB and as glTF with the image embedded in a data
 * URI render the same film, and it and the glTF with an external PNG (whose sampler mirrors u
 * and clamps v where the others repeat) hold the Cesium logo's green and blue where the
 * untextured box is grey; spider.obj's JPEG maps (map_Kd) give its film many more
 * distinct chromaticities than its five materials' flat colours could. Exits 77 without the
 * models. */
#include <math.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "render/render.h"
#include "scene/model_scene.h"
#include "test_scenes.h"

#define MODELS "/usr/share/assimp/models/"

/* Renders model path as its scene at 64 pixels across, 4 samples; false on failure. */
static bool render_model(const char *path, film *f) {
    scene s;
    scene_error err;
    model_scene_opts mo = {.camera = NULL, .width = 64, .mode = -1};
    if (!model_scene_parse(path, &mo, &s, &err)) {
        scene_error_print(&err);
        return false;
    }
    render_opts o;
    render_opts_from_scene(&s, &o);
    o.spp = 4;
    bool ok = render_on(false, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* Pixel k's mean radiance. */
static void mean_of(const film *f, size_t k, float rgb[3]) {
    const float *p = &f->accum[k * 4];
    for (int c = 0; c < 3; c++) rgb[c] = p[3] > 0 ? p[c] / p[3] : 0;
}

static void test_box_textured(void) {
    static const char *const paths[3] = {MODELS "glTF2/BoxTextured-glTF/BoxTextured.gltf",
                                         MODELS "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
                                         MODELS "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf"};
    film f[3] = {{0}};
    for (int k = 0; k < 3; k++) CHECK(render_model(paths[k], &f[k]), "%s", paths[k]);
    if (!f[0].accum || !f[1].accum || !f[2].accum) return;
    size_t pixels = (size_t)f[0].width * f[0].height;
    CHECK(f[2].width == f[1].width && f[2].height == f[1].height &&
              !memcmp(f[2].accum, f[1].accum, pixels * 4 * sizeof(float)),
          "%s renders another film than %s", paths[2], paths[1]);
    for (int m = 0; m < 2; m++) {
        size_t green = 0, blue = 0;
        for (size_t k = 0; k < pixels; k++) {
            float c[3];
            mean_of(&f[m], k, c);
            green += c[1] > 1.3f * c[0] && c[1] > 1.3f * c[2];
            blue += c[2] > 1.3f * c[0] && c[2] > 1.1f * c[1];
        }
        CHECK(green > 20 && blue > 20, "%s: %zu green and %zu blue pixels", paths[m], green, blue);
    }
    for (int k = 0; k < 3; k++) film_free(&f[k]);
}

static void test_spider(void) {
    film f = {0};
    CHECK(render_model(MODELS "OBJ/spider.obj", &f), "spider.obj");
    if (!f.accum) return;
    /* Chromaticities r / (r + g + b), g / (r + g + b) in buckets of 0.01. */
    static bool seen[100][100];
    int distinct = 0;
    for (size_t k = 0; k < (size_t)f.width * f.height; k++) {
        float c[3];
        mean_of(&f, k, c);
        float sum = c[0] + c[1] + c[2];
        if (!(sum > 0.05f) || (c[0] == c[1] && c[1] == c[2])) continue;
        int r = (int)(100 * c[0] / sum), g = (int)(100 * c[1] / sum);
        if (r < 0 || r > 99 || g < 0 || g > 99 || seen[r][g]) continue;
        seen[r][g] = true;
        distinct++;
    }
    CHECK(distinct > 40, "spider.obj: %d distinct chromaticities", distinct);
    film_free(&f);
}

int main(void) {
    if (access(MODELS "OBJ/spider.obj", R_OK) != 0 ||
        access(MODELS "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", R_OK) != 0) {
        printf("test_texture_models: assimp-testmodels not installed, skipped\n");
        return 77;
    }
    CHECK_CASE(test_box_textured);
    CHECK_CASE(test_spider);
    return check_summary("test_texture_models");
}
