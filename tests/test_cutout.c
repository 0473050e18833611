/* test_cutout.c: alpha cut-outs and emission maps (shaders/common/primitive.h's face_cut,
 * emitter.h's emitted_radiance) on the back end named by argv[1] ("cpu" or "vulkan"; Vulkan
 * exits 77 without a device): a cut-out quad before a wall under a point light renders as the
 * quad's kept half alone (the cut half shows the wall and casts no shadow, the kept half casts
 * it); an emission map seen directly is its texel times the emission; light sampling finds the
 * map's radiance where BSDF sampling does (a textured emitter against the untextured one it
 * equals, pixel for pixel; light sampling alone against BSDF sampling alone in mean); glTF's
 * MASK cuts by its cutoff and BLEND lets through one minus its alpha of the rays; a fence of
 * cut-out quads, BLEND among them, gives one film on every CPU build and every Vulkan walk. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "png_test.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"
#include "tmp_dir.h"

static bool use_vulkan;

static float pixel(const film *f, int i, int j, int c) {
    const float *p = &f->accum[((size_t)j * f->width + i) * 4];
    return p[c] / p[3];
}

/* Renders scene text on the back end under test into f in `mode` with `strategy`, no jitter;
 * false when it does not parse or render. */
static bool render_text(const char *text, render_mode mode, path_strategy strategy, film *f) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.mode = mode;
    o.strategy = strategy;
    o.no_jitter = true;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* The quad (-0.5..0.5)^2 at z = 0, its alpha map opaque on the left half of u and clear on the
 * right (cut where u > 0.5: x > 0), before a red wall at z = 2, lit from (-1.5, 0, -3): the
 * same film, bit for bit, as the quad's kept half alone, but in the pixels whose wall point's
 * shadow ray crosses z = 0 within 0.02 of x = 0 (the cut's edge, filtered). The film has wall
 * pixels in the kept half's shadow seen through the cut half (black) and wall pixels lit
 * through it. */
static void test_cutout_shadow(void) {
    static const uint8_t half[8] = {255, 255, 255, 255, 255, 255, 255, 0};
    write_png(tmp_path("half.png"), 2, 1, PNG_COLOR_TYPE_RGBA, half);
    const char *head =
        "camera position 0 0 -4\nplane width 2 height 2 pixel 0.05\n"
        "light position -1.5 0 -3 power 30\nrender indirect off samples 1\n"
        "quad lambertian v0 -4 -4 2 v1 -4 4 2 v2 4 4 2 v3 4 -4 2 color 0.8 0.2 0.2\n";
    char cut[1024], kept[1024];
    snprintf(cut, sizeof cut,
             "%squad lambertian v0 -0.5 -0.5 0 v1 -0.5 0.5 0 v2 0.5 0.5 0 v3 0.5 -0.5 0 "
             "uv0 0 0 uv1 0 1 uv2 1 1 uv3 1 0 wrap clamp alpha_map %s\n",
             head, tmp_path("half.png"));
    snprintf(kept, sizeof kept,
             "%squad lambertian v0 -0.5 -0.5 0 v1 -0.5 0.5 0 v2 0 0.5 0 v3 0 -0.5 0\n", head);
    film a = {0}, b = {0};
    CHECK(render_text(cut, RENDER_MODE_REPORT, PATH_MIS, &a) &&
              render_text(kept, RENDER_MODE_REPORT, PATH_MIS, &b),
          "cut-out: render");
    if (!a.accum || !b.accum) return;
    int differ = 0, dark_through = 0, lit_through = 0;
    for (int j = 0; j < 40; j++) {
        for (int i = 0; i < 40; i++) {
            double x = -1 + (i + 0.5) * 0.05, y = 1 - (j + 0.5) * 0.05;
            /* the wall point seen there (the image plane is z = 0), its shadow ray's crossing */
            double wx = 1.5 * x, cross_x = -1.5 + 0.6 * (wx + 1.5);
            bool edge = fabs(cross_x) < 0.02 || fabs(x) < 0.02;
            bool same = !memcmp(&a.accum[((size_t)j * 40 + i) * 4],
                                &b.accum[((size_t)j * 40 + i) * 4], 4 * sizeof(float));
            differ += !same && !edge;
            bool through = x > 0.15 && x < 0.45 && fabs(y) < 0.45;
            dark_through += through && pixel(&a, i, j, 0) == 0.0f;
            lit_through += through && pixel(&a, i, j, 0) > 0.01f;
        }
    }
    CHECK(differ == 0, "cut-out: %d pixels differ from the kept half's film", differ);
    CHECK(dark_through > 20 && lit_through == 0,
          "cut-out: through the cut half %d wall pixels in shadow, %d lit", dark_through,
          lit_through);
    int lit_beside = 0; /* wall lit through the cut half's place: x from 0.72 on */
    for (int i = 35; i < 40; i++) lit_beside += pixel(&a, i, 20, 0) > 0.01f;
    CHECK(lit_beside == 5, "cut-out: %d of 5 wall pixels lit past the cut half", lit_beside);
    film_free(&a);
    film_free(&b);
}

/* sRGB's decoding of 8-bit value k. */
static double srgb(int k) {
    double c = k / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* A quad emitter with a 2 x 2 emission map seen directly (path mode, no bounce): each pixel
 * whose UV lies in a texel's inner quarter (clamped: bilinear filtering reads that texel alone)
 * is the texel's sRGB-decoded colour times the emission. */
static void test_emission_seen(void) {
    static const uint8_t texels[12] = {200, 30, 90, 10, 128, 250, 64, 255, 0, 180, 180, 20};
    write_png(tmp_path("emit.png"), 2, 2, PNG_COLOR_TYPE_RGB, texels);
    char text[1024];
    snprintf(text, sizeof text,
             "camera position 0 0 -4\nplane width 2 height 2 pixel 0.05\n"
             "render mode path bounces 0 samples 1\n"
             "quad lambertian v0 -1 -1 0 v1 -1 1 0 v2 1 1 0 v3 1 -1 0 color 0 0 0 "
             "emission 2 3 4 uv0 0 0 uv1 0 1 uv2 1 1 uv3 1 0 wrap clamp emission_map %s\n",
             tmp_path("emit.png"));
    film f = {0};
    CHECK(render_text(text, RENDER_MODE_PATH, PATH_MIS, &f), "emission map: render");
    if (!f.accum) return;
    static const double emission[3] = {2, 3, 4};
    double worst = 0;
    int checked = 0;
    for (int j = 0; j < 40; j++) {
        for (int i = 0; i < 40; i++) {
            double u = (i + 0.5) / 40, v = 1 - (j + 0.5) / 40;
            bool inner = (u < 0.25 || u > 0.75) && (v < 0.25 || v > 0.75);
            if (!inner) continue;
            int tx = u > 0.5, ty = v < 0.5; /* rows top first, v up */
            for (int c = 0; c < 3; c++) {
                double want = srgb(texels[(ty * 2 + tx) * 3 + c]) * emission[c];
                worst = fmax(worst, fabs(pixel(&f, i, j, c) - want) / (want + 1e-3));
            }
            checked++;
        }
    }
    CHECK(checked == 400 && worst < 2e-6,
          "emission map: %d pixels, off by %.3g of texel x emission", checked, worst);
    film_free(&f);
}

/* A floor lit by a quad emitter and a sphere emitter whose maps are white where their UVs read
 * them (the quad's reads the right column of an image black at UV (0, 0), the sphere's a single
 * white texel): the film of the same scene without the maps, within float rounding of the
 * texel's 1, pixel for pixel in path mode (MIS, light samples and BSDF rays alike: every random
 * decision is the same). A light sample that looked the map up elsewhere would read black. */
static void test_emission_light_sampling(void) {
    static const uint8_t map[6] = {0, 0, 0, 255, 255, 255}, white[3] = {255, 255, 255};
    write_png(tmp_path("white_right.png"), 2, 1, PNG_COLOR_TYPE_RGB, map);
    write_png(tmp_path("white.png"), 1, 1, PNG_COLOR_TYPE_RGB, white);
    const char *head =
        "camera position 0 2 -4 look_at 0 0 0\nplane width 2 height 1.5 pixel 0.05\n"
        "render mode path bounces 2 samples 16\n"
        "quad lambertian v0 -3 0 -3 v1 -3 0 3 v2 3 0 3 v3 3 0 -3 color 0.6 0.6 0.6\n"
        "quad lambertian v0 -1 1.5 -1 v1 1 1.5 -1 v2 1 1.5 1 v3 -1 1.5 1 color 0 0 0 "
        "emission 3 3 3";
    const char *sphere =
        "sphere lambertian center 1.2 0.4 0.5 radius 0.3 color 0 0 0 "
        "emission 2 2 2";
    char plain[1024], mapped[1024];
    snprintf(plain, sizeof plain, "%s\n%s\n", head, sphere);
    snprintf(mapped, sizeof mapped,
             "%s uv0 0.8 0 uv1 0.9 0 uv2 0.9 1 uv3 0.8 1 wrap clamp emission_map %s\n"
             "%s emission_map %s\n",
             head, tmp_path("white_right.png"), sphere, tmp_path("white.png"));
    film a = {0}, b = {0};
    CHECK(render_text(plain, RENDER_MODE_PATH, PATH_MIS, &a) &&
              render_text(mapped, RENDER_MODE_PATH, PATH_MIS, &b),
          "emitters: render");
    if (a.accum && b.accum) {
        double worst = 0, total = 0;
        for (size_t k = 0; k < (size_t)a.width * a.height * 4; k++) {
            worst = fmax(worst, fabs(a.accum[k] - b.accum[k]) / (fabs(a.accum[k]) + 1e-3));
            total += a.accum[k];
        }
        CHECK(total > 100 && worst < 1e-5, "white emission maps: off by %.3g of the plain (sum %g)",
              worst, total);
    }
    film_free(&a);
    film_free(&b);
}

/* The mean and its standard error over the film's pixels of channel 0. */
static void film_mean(const film *f, double *mean, double *se) {
    double s = 0, s2 = 0;
    int n = f->width * f->height;
    for (int k = 0; k < n; k++) {
        double v = f->accum[(size_t)k * 4] / f->accum[(size_t)k * 4 + 3];
        s += v, s2 += v * v;
    }
    *mean = s / n;
    *se = sqrt(fmax(0.0, s2 / n - *mean * *mean) / n);
}

/* A floor under a quad emitter whose map is black on one half and white on the other: light
 * sampling alone and BSDF sampling alone estimate the same image (their means within four
 * standard errors), as they would not if light samples read the map elsewhere than the point
 * they aim at. */
static void test_emission_strategies(void) {
    static const uint8_t map[6] = {0, 0, 0, 255, 255, 255};
    write_png(tmp_path("halves.png"), 2, 1, PNG_COLOR_TYPE_RGB, map);
    char text[1024];
    snprintf(text, sizeof text,
             "camera position 0 3 -3 look_at 0 0 0\nplane width 2 height 2 pixel 0.1\n"
             "render mode path bounces 1 samples 256\n"
             "quad lambertian v0 -3 0 -3 v1 -3 0 3 v2 3 0 3 v3 3 0 -3 color 0.6 0.6 0.6\n"
             "quad lambertian v0 -1 1 -1 v1 1 1 -1 v2 1 1 1 v3 -1 1 1 color 0 0 0 "
             "emission 4 4 4 uv0 0 0 uv1 1 0 uv2 1 1 uv3 0 1 emission_map %s\n",
             tmp_path("halves.png"));
    film l = {0}, b = {0};
    CHECK(render_text(text, RENDER_MODE_PATH, PATH_LIGHTS_ONLY, &l) &&
              render_text(text, RENDER_MODE_PATH, PATH_BSDF_ONLY, &b),
          "strategies: render");
    if (l.accum && b.accum) {
        double ml, sl, mb, sb;
        film_mean(&l, &ml, &sl);
        film_mean(&b, &mb, &sb);
        CHECK(ml > 0.05 && fabs(ml - mb) <= 4 * hypot(sl, sb),
              "strategies: light sampling %.5f+-%.5f, BSDF sampling %.5f+-%.5f", ml, sl, mb, sb);
    }
    film_free(&l);
    film_free(&b);
}

/* Writes a glTF of one quad (-1..1)^2 at z = 0, UVs over the unit square, whose material's base
 * colour texture is `image` with alpha mode `mode` and alphaCutoff `cutoff`. */
static void write_gltf_quad(const char *path, const char *image, const char *mode, double cutoff) {
    /* positions (4 x 3 floats), UVs (4 x 2 floats), indices (6 shorts), little-endian */
    static const float positions[12] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
    static const float uvs[8] = {0, 1, 1, 1, 1, 0, 0, 0};
    static const uint16_t indices[6] = {0, 1, 2, 0, 2, 3};
    uint8_t bytes[92];
    memcpy(bytes, positions, 48);
    memcpy(bytes + 48, uvs, 32);
    memcpy(bytes + 80, indices, 12);
    static const char table[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char base64[128];
    int n = 0;
    for (int k = 0; k < 92; k += 3) {
        uint32_t v = (uint32_t)bytes[k] << 16 | (k + 1 < 92 ? bytes[k + 1] << 8 : 0) |
                     (k + 2 < 92 ? bytes[k + 2] : 0);
        base64[n++] = table[v >> 18 & 63];
        base64[n++] = table[v >> 12 & 63];
        base64[n++] = k + 1 < 92 ? table[v >> 6 & 63] : '=';
        base64[n++] = k + 2 < 92 ? table[v & 63] : '=';
    }
    base64[n] = '\0';
    FILE *fp = fopen(path, "w");
    if (!fp) exit(1);
    fprintf(fp,
            "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],"
            "\"nodes\":[{\"mesh\":0}],\"meshes\":[{\"primitives\":[{\"attributes\":"
            "{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,\"material\":0}]}],"
            "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorFactor\":[0,0,0,1],"
            "\"baseColorTexture\":{\"index\":0},\"metallicFactor\":0,\"roughnessFactor\":1},"
            "\"alphaMode\":\"%s\",\"alphaCutoff\":%g}],"
            "\"textures\":[{\"source\":0}],\"images\":[{\"uri\":\"%s\"}],"
            "\"buffers\":[{\"byteLength\":92,\"uri\":\"data:application/octet-stream;base64,%s\"}],"
            "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},"
            "{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},"
            "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12}],"
            "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":"
            "\"VEC3\",\"min\":[-1,-1,0],\"max\":[1,1,0]},{\"bufferView\":1,"
            "\"componentType\":5126,\"count\":4,\"type\":\"VEC2\"},{\"bufferView\":2,"
            "\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}]}\n",
            mode, cutoff, image, base64);
    fclose(fp);
}

/* A fence of 64 cut-out quads (a grey checker alpha map at two cutoffs) and a glTF quad of BLEND
 * before a lit wall, enough faces for the BVH: report and path mode films of every CPU packet
 * build and of Vulkan's compute and cooperative walks (and ray queries where the device has
 * them) are one film, bit for bit. */
static void test_walks_agree(void) {
    if (!use_vulkan) return;
    static const uint8_t checker[4] = {255, 0, 0, 255};
    write_png(tmp_path("checker.png"), 2, 2, PNG_COLOR_TYPE_GRAY, checker);
    static char text[65536];
    int n =
        snprintf(text, sizeof text,
                 "camera position 0 1 -6 look_at 0 0 0\nplane width 2 height 1.5 pixel 0.05\n"
                 "light position -2 3 -4 power 40\nrender samples 4\n"
                 "quad lambertian v0 -6 -2 3 v1 -6 6 3 v2 6 6 3 v3 6 -2 3 color 0.8 0.5 0.3\n"
                 "quad lambertian v0 -6 -1 -6 v1 -6 -1 6 v2 6 -1 6 v3 6 -1 -6 color 0.6 0.6 0.6\n");
    for (int k = 0; k < 64; k++) {
        double x = -2.4 + 0.6 * (k % 8), y = -1 + 0.5 * (k / 8), z = 0.3 * (k % 3);
        n += snprintf(text + n, sizeof text - n,
                      "quad lambertian v0 %g %g %g v1 %g %g %g v2 %g %g %g v3 %g %g %g "
                      "color 0.9 0.9 0.9 uv1 0 2 uv2 2 2 uv3 2 0 alpha_map %s%s\n",
                      x, y, z, x, y + 0.45, z, x + 0.55, y + 0.45, z, x + 0.55, y, z,
                      tmp_path("checker.png"), k % 2 ? " alpha_cutoff 0.3" : "");
    }
    static const uint8_t texel[4] = {0, 0, 0, 128};
    write_png(tmp_path("alpha128.png"), 1, 1, PNG_COLOR_TYPE_RGBA, texel);
    write_gltf_quad(tmp_path("blend.gltf"), "alpha128.png", "BLEND", 0.5);
    snprintf(text + n, sizeof text - n, "mesh file %s scale 0.8 translate 0.3 0.2 -1\n",
             tmp_path("blend.gltf"));
    for (int mode = 0; mode < 2; mode++) {
        scene s;
        render_opts o;
        if (!parse_scene_text(text, &s, &o)) {
            CHECK(false, "fence: parse");
            return;
        }
        o.mode = mode ? RENDER_MODE_PATH : RENDER_MODE_REPORT;
        if (mode) o.bounces = 4;
        film ref = {0};
        setenv("TRAZADOR_PACKET_BUILD", "reference", 1);
        CHECK(render_on(false, &s, &o, &ref), "fence: the reference build");
        static const char *builds[] = {"x86-64-v4", "avx2", "baseline"};
        for (int b = 0; b < 3; b++) {
            film f = {0};
            setenv("TRAZADOR_PACKET_BUILD", builds[b], 1);
            CHECK(render_on(false, &s, &o, &f) && ref.accum &&
                      !memcmp(f.accum, ref.accum, (size_t)f.width * f.height * 4 * sizeof(float)),
                  "fence mode %d: CPU build '%s' differs from the reference build", mode,
                  builds[b]);
            film_free(&f);
        }
        unsetenv("TRAZADOR_PACKET_BUILD");
        static const render_walk walks[] = {RENDER_WALK_COMPUTE, RENDER_WALK_COOPERATIVE,
                                            RENDER_WALK_RAY_QUERY};
        for (int w = 0; w < 3; w++) {
            film f = {0};
            render_opts wo = o;
            wo.walk = walks[w];
            if (!render_on(true, &s, &wo, &f)) {
                CHECK(walks[w] == RENDER_WALK_RAY_QUERY, "fence mode %d: walk %d failed", mode, w);
                printf("test_cutout: no ray query walk on this device\n");
                continue;
            }
            CHECK(ref.accum &&
                      !memcmp(f.accum, ref.accum, (size_t)f.width * f.height * 4 * sizeof(float)),
                  "fence mode %d: Vulkan walk %d differs from the CPU", mode, w);
            film_free(&f);
        }
        film_free(&ref);
        scene_free(&s);
    }
}

/* A glTF quad of base colour alpha 128 / 255 (black, and nothing lights it) before a white
 * background: MASK at
 * cutoff 0.6 cuts it all (every pixel the background's 1 exactly), at 0.4 none (0); BLEND lets
 * through the share 1 - 128 / 255 of the camera rays, within four standard errors over the
 * image's samples. */
static void test_gltf_alpha_modes(void) {
    if (use_vulkan || access("/usr/share/assimp", F_OK) != 0) return;
    static const uint8_t texel[4] = {0, 0, 0, 128};
    write_png(tmp_path("alpha128.png"), 1, 1, PNG_COLOR_TYPE_RGBA, texel);
    static const struct {
        const char *mode;
        double cutoff, want, tolerance;
    } cases[3] = {{"MASK", 0.6, 1.0, 0.0}, {"MASK", 0.4, 0.0, 0.0}, {"BLEND", 0.5, 127.0 / 255, 4}};
    for (int k = 0; k < 3; k++) {
        write_gltf_quad(tmp_path("quad.gltf"), "alpha128.png", cases[k].mode, cases[k].cutoff);
        char text[1024];
        snprintf(text, sizeof text,
                 "camera position 0 0 -4\nplane width 2 height 2 pixel 0.05\nbackground 1 1 1\n"
                 "render samples 16 indirect off\nmesh file %s scale 2\n",
                 tmp_path("quad.gltf"));
        scene sc;
        render_opts o;
        film f = {0};
        if (!parse_scene_text(text, &sc, &o)) {
            CHECK(false, "%s: parse", cases[k].mode);
            continue;
        }
        CHECK(render_on(false, &sc, &o, &f), "%s: render", cases[k].mode);
        scene_free(&sc);
        if (!f.accum) continue;
        double mean, se;
        film_mean(&f, &mean, &se);
        int samples = f.width * f.height * 16;
        double bound = cases[k].tolerance * sqrt(cases[k].want * (1 - cases[k].want) / samples);
        CHECK(fabs(mean - cases[k].want) <= bound,
              "%s cutoff %g: the background's share %.5f, not %.5f within %.2g", cases[k].mode,
              cases[k].cutoff, mean, cases[k].want, bound);
        film_free(&f);
    }
}

/* Cut-outs are for faces: a sphere's alpha_map is refused where it stands. */
static void test_sphere_refused(void) {
    if (use_vulkan) return;
    expect_parse_error("sphere lambertian center 0 0 0 radius 1 alpha_map a.png\n", 1, 51,
                       "cut-outs are for faces");
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_cutout: no Vulkan device, skipped\n");
        return 77;
    }
    if (!tmp_dir_make("test_cutout")) return 1;
    CHECK_CASE(test_cutout_shadow);
    CHECK_CASE(test_emission_seen);
    CHECK_CASE(test_emission_light_sampling);
    CHECK_CASE(test_emission_strategies);
    CHECK_CASE(test_walks_agree);
    CHECK_CASE(test_gltf_alpha_modes);
    CHECK_CASE(test_sphere_refused);
    return check_summary(use_vulkan ? "test_cutout vulkan" : "test_cutout");
}
