/* test_texture_models.c: textured models of Debian's assimp-testmodels rendered as the scene (CPU
 * back end, 64 pixels across): BoxTextured as GLB and as glTF with the image embedded in a data
 * URI render the same film, and it and the glTF with an external PNG (whose sampler mirrors u
 * and clamps v where the others repeat) hold the Cesium logo's green and blue where the
 * untextured box is grey; spider.obj's JPEG maps (map_Kd) give its film many more
 * distinct chromaticities than its five materials' flat colours could; TextureTransformTest's
 * KHR_texture_transform offsets, rotation and scale reach the slots as glTF's formula says.
 * Exits 77 without the models. */
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

/* glTF's KHR_texture_transform of offset (ox, oy), rotation r and scale (sx, sy), uv' = o + R S
 * uv in glTF's UVs (v down) with R = (cos r, sin r; -sin r, cos r) by rows, the rotation with
 * which TextureTransformTest's arrows point at its "correct" marks, as rows in trazador's UVs
 * (v up): v = 1 - v_glTF on both sides. */
static void gltf_rows(double ox, double oy, double r, double sx, double sy, double rows[6]) {
    double c = cos(r), s = sin(r);
    double out[6] = {c * sx, -s * sy, ox + s * sy, s * sx, c * sy, 1 - c * sy - oy};
    memcpy(rows, out, sizeof out);
}

/* TextureTransformTest.gltf's six transforms (offsets, a rotation, a scale and all three) are
 * each some slot's UV transform, within float rounding. */
static void test_texture_transform(void) {
    const char *path = MODELS "glTF2/textureTransform/TextureTransformTest.gltf";
    scene s;
    scene_error err;
    model_scene_opts mo = {.camera = NULL, .width = 64, .mode = -1};
    CHECK(model_scene_parse(path, &mo, &s, &err), "%s: %s", path, err.message);
    if (!s.slots) return;
    double want[6][6];
    gltf_rows(0.5, 0, 0, 1, 1, want[0]);
    gltf_rows(0, 0.5, 0, 1, 1, want[1]);
    gltf_rows(0.5, 0.5, 0, 1, 1, want[2]);
    gltf_rows(0, 0, 0.39269908169872414, 1, 1, want[3]);
    gltf_rows(0, 0, 0, 1.5, 1.5, want[4]);
    gltf_rows(-0.2, -0.1, 0.3, 1.5, 1.5, want[5]);
    for (int w = 0; w < 6; w++) {
        bool found = false;
        for (int k = 0; k < s.slot_count && !found; k++) {
            bool near = true;
            for (int r = 0; r < 6; r++) near &= fabs(s.slots[k].transform[r] - want[w][r]) < 1e-5;
            found = near;
        }
        CHECK(found, "transform %d (%g %g %g, %g %g %g) is no slot's", w, want[w][0], want[w][1],
              want[w][2], want[w][3], want[w][4], want[w][5]);
    }
    scene_free(&s);
}

int main(void) {
    if (access(MODELS "OBJ/spider.obj", R_OK) != 0 ||
        access(MODELS "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb", R_OK) != 0) {
        printf("test_texture_models: assimp-testmodels not installed, skipped\n");
        return 77;
    }
    CHECK_CASE(test_box_textured);
    CHECK_CASE(test_spider);
    CHECK_CASE(test_texture_transform);
    return check_summary("test_texture_models");
}
