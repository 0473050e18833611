/* test_gen.c: the scene generators (src/scene/gen.c) and `trazador gen` (src/cli/cmd_gen.c): sphere
 * counts, materials, the sphereflake's geometry, the random field's spacing, framing, determinism
 * per seed, usage errors that write nothing, atomic writes, and a small render of each through the
 * CPU back end. */
#include <dirent.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "cli/cli.h"
#include "render/render.h"
#include "scene/gen.h"
#include "tmp_dir.h"

/* Runs cmd_gen on a NULL-terminated argument list (argv[0] = "gen" is added). */
static int run_gen(const char *arg, ...) {
    char *argv[32] = {"gen"};
    int argc = 1;
    va_list ap;
    va_start(ap, arg);
    for (const char *a = arg; a && argc < 31; a = va_arg(ap, const char *))
        argv[argc++] = (char *)a;
    va_end(ap);
    return cmd_gen(argc, argv);
}

/* Returns the whole file in a malloc'd buffer (NULL when unreadable); *size its length. */
static char *read_all(const char *path, size_t *size) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    char *buf = malloc((size_t)n + 1);
    if (buf && fread(buf, 1, (size_t)n, fp) != (size_t)n) {
        free(buf);
        buf = NULL;
    }
    fclose(fp);
    if (buf) buf[n] = 0;
    *size = (size_t)n;
    return buf;
}

static bool same_bytes(const char *a, const char *b) {
    size_t na = 0, nb = 0;
    char *x = read_all(a, &na), *y = read_all(b, &nb);
    bool same = x && y && na == nb && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

static bool exists(const char *path) {
    struct stat st;
    return stat(path, &st) == 0;
}

/* Number of entries in the temporary folder (leftover temporaries show up here). */
static int tmpdir_entries(void) {
    DIR *d = opendir(tmpdir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d) closedir(d);
    return n;
}

static bool parse(const char *path, scene *s) {
    scene_error err;
    if (scene_parse_file(path, s, &err)) return true;
    scene_error_print(&err);
    return false;
}

static double dist(vec3 a, vec3 b) { return v3_length(v3_sub(a, b)); }

/* Settings every generated scene shares: a 400x300 plane, 16 samples, indirect on, 2 or 3
   lights, every number valid (the parser has checked them). */
static void check_common(const char *name, const scene *s) {
    CHECK(s->width == 400 && s->height == 300, "%s: %dx%d pixels", name, s->width, s->height);
    CHECK(s->spp == 16 && s->indirect, "%s: render settings %d %d", name, s->spp, s->indirect);
    CHECK(s->light_count >= 2 && s->light_count <= 3, "%s: %d lights", name, s->light_count);
    for (int k = 0; k < s->light_count; k++)
        CHECK(s->lights[k].power > 0.0f, "%s: light %d has no power", name, k);
}

/* True when the sphere is wholly inside the camera's view (DESIGN section 3's frame). */
static bool in_view(const scene *s, vec3 c, float r) {
    vec3 f = v3_normalize(s->camera_direction);
    vec3 right = v3_normalize(v3_cross(s->camera_up, f)), up = v3_cross(f, right);
    vec3 rel = v3_sub(c, s->camera_position);
    double depth = v3_dot(rel, f), focal = 2.0 * s->plane_width;
    if (depth <= r) return false;
    double x = v3_dot(rel, right) * focal / depth, y = v3_dot(rel, up) * focal / depth;
    double margin = r * focal / depth * 1.2; /* the projected radius, and a little more */
    return fabs(x) + margin <= s->plane_width / 2 && fabs(y) + margin <= s->plane_height / 2;
}

static void count_materials(const scene *s, int counts[4]) {
    memset(counts, 0, 4 * sizeof counts[0]);
    for (int k = 0; k < s->sphere_count; k++) counts[sphere_material(s, &s->spheres[k])->kind]++;
}

/* ---- sphereflake ---- */

typedef struct flake_check {
    const scene *s;
    int next; /* index of the next sphere in depth-first order */
    int bad_touch, bad_radius, bad_layout, bad_overlap;
    double worst_touch; /* largest relative error of |c_child - c_parent| vs r_parent + r_child */
} flake_check;

/* Walks the children of sphere p (grown along dir) depth-first, as the generator writes them. */
static void walk_flake(flake_check *fc, int p, vec3 dir, int grandparent, int depth_left) {
    if (depth_left == 0) return;
    const sphere *parent = &fc->s->spheres[p];
    int equator = 0, upper = 0;
    for (int k = 0; k < 9; k++) {
        int c = fc->next++;
        if (c >= fc->s->sphere_count) return;
        const sphere *child = &fc->s->spheres[c];
        double d = dist(child->center, parent->center), want = parent->radius + child->radius;
        double rel = fabs(d - want) / want;
        if (rel > fc->worst_touch) fc->worst_touch = rel;
        fc->bad_touch += rel > 1e-4;
        fc->bad_radius += fabs(child->radius * 3.0 - parent->radius) > 1e-5 * parent->radius;
        /* the SPD's layout: 6 on the parent's equator, 3 at sin(elevation) = sqrt(2/3) */
        vec3 out = v3_normalize(v3_sub(child->center, parent->center));
        double elevation = v3_dot(out, dir);
        if (fabs(elevation) < 1e-3)
            equator++;
        else if (fabs(elevation - sqrt(2.0 / 3.0)) < 1e-3)
            upper++;
        /* growing outward: no child reaches into its grandparent */
        if (grandparent >= 0) {
            const sphere *g = &fc->s->spheres[grandparent];
            fc->bad_overlap += dist(child->center, g->center) < (g->radius + child->radius) * 0.999;
        }
        walk_flake(fc, c, out, p, depth_left - 1);
    }
    fc->bad_layout += equator != 6 || upper != 3;
}

static void test_sphereflake(void) {
    for (int depth = 0; depth <= 3; depth++) {
        char name[64], arg[8];
        snprintf(name, sizeof name, "flake%d.scene", depth);
        snprintf(arg, sizeof arg, "%d", depth);
        const char *path = tmp_path(name);
        CHECK(run_gen("sphereflake", "--depth", arg, "-o", path, NULL) == 0, "depth %d failed",
              depth);
        scene s = {0};
        if (!parse(path, &s)) {
            CHECK(false, "depth %d: the generated scene does not parse", depth);
            continue;
        }
        long flake = 0, level = 1;
        for (int k = 0; k <= depth; k++, level *= 9) flake += level;
        gen_desc desc = {.kind = GEN_SPHEREFLAKE, .depth = depth};
        CHECK(s.sphere_count == flake + 1, "depth %d: %d spheres, want %ld + ground", depth,
              s.sphere_count, flake);
        CHECK(gen_sphere_count(&desc) == s.sphere_count, "depth %d: gen_sphere_count %ld", depth,
              gen_sphere_count(&desc));
        check_common(name, &s);
        /* sphere 0 is the ground: a huge Lambertian sphere whose top the flake rests on */
        const sphere *ground = &s.spheres[0];
        CHECK(sphere_material(&s, ground)->kind == TZ_MATERIAL_LAMBERTIAN &&
                  ground->radius >= 1000.0f,
              "depth %d: sphere 0 is not the ground", depth);
        double top = ground->center.y + ground->radius, lowest = 1e30;
        for (int k = 1; k < s.sphere_count; k++) {
            lowest = fmin(lowest, s.spheres[k].center.y - s.spheres[k].radius);
            CHECK(in_view(&s, s.spheres[k].center, s.spheres[k].radius),
                  "depth %d: sphere %d is out of view", depth, k);
        }
        CHECK(fabs(lowest - top) < 1e-4, "depth %d: the flake's lowest point %g, ground top %g",
              depth, lowest, top);
        int counts[4];
        count_materials(&s, counts);
        if (depth >= 1)
            CHECK(counts[0] && counts[1] && counts[2] && counts[3],
                  "depth %d: materials %d %d %d %d, want all four", depth, counts[0], counts[1],
                  counts[2], counts[3]);
        flake_check fc = {.s = &s, .next = 2};
        walk_flake(&fc, 1, v3(0, 1, 0), -1, depth);
        CHECK(fc.next == s.sphere_count, "depth %d: walked %d of %d spheres", depth, fc.next,
              s.sphere_count);
        CHECK(!fc.bad_touch, "depth %d: %d children do not touch their parent (worst %g)", depth,
              fc.bad_touch, fc.worst_touch);
        CHECK(!fc.bad_radius, "depth %d: %d children are not a third of their parent", depth,
              fc.bad_radius);
        CHECK(!fc.bad_layout, "depth %d: %d parents without 6 equator + 3 upper children", depth,
              fc.bad_layout);
        CHECK(!fc.bad_overlap, "depth %d: %d children reach into their grandparent", depth,
              fc.bad_overlap);
        scene_free(&s);
    }
    /* the same seed gives the same bytes; the seed only varies colours */
    const char *a = tmp_path("fa.scene"), *b = tmp_path("fb.scene"), *c = tmp_path("fc.scene");
    CHECK(run_gen("sphereflake", "--depth", "2", "--seed", "7", "-o", a, NULL) == 0, "seed 7 a");
    CHECK(run_gen("sphereflake", "--seed", "7", "-o", b, "--depth", "2", NULL) == 0, "seed 7 b");
    CHECK(run_gen("sphereflake", "--depth", "2", "--seed", "8", "-o", c, NULL) == 0, "seed 8");
    CHECK(same_bytes(a, b), "sphereflake: seed 7 twice gives different files");
    CHECK(!same_bytes(a, c), "sphereflake: seeds 7 and 8 give the same file");
}

/* ---- random ---- */

static void test_random(void) {
    const long counts[] = {1, 10, 500, 2000};
    for (size_t t = 0; t < sizeof counts / sizeof counts[0]; t++) {
        long n = counts[t];
        char name[64], arg[16];
        snprintf(name, sizeof name, "random%ld.scene", n);
        snprintf(arg, sizeof arg, "%ld", n);
        const char *path = tmp_path(name);
        CHECK(run_gen("random", "--count", arg, "-o", path, NULL) == 0, "count %ld failed", n);
        scene s = {0};
        if (!parse(path, &s)) {
            CHECK(false, "count %ld: the generated scene does not parse", n);
            continue;
        }
        gen_desc desc = {.kind = GEN_RANDOM, .count = n};
        CHECK(s.sphere_count == n + 4, "count %ld: %d spheres, want %ld + 4", n, s.sphere_count, n);
        CHECK(gen_sphere_count(&desc) == s.sphere_count, "count %ld: gen_sphere_count %ld", n,
              gen_sphere_count(&desc));
        check_common(name, &s);
        /* the ground, then the book's three: brown Lambertian, glass, metal */
        const sphere *ground = &s.spheres[0];
        CHECK(sphere_material(&s, ground)->kind == TZ_MATERIAL_LAMBERTIAN &&
                  ground->radius >= 1000.0f,
              "count %ld: sphere 0 is not the ground", n);
        CHECK(sphere_material(&s, &s.spheres[1])->kind == TZ_MATERIAL_LAMBERTIAN &&
                  sphere_material(&s, &s.spheres[2])->kind == TZ_MATERIAL_REFRACTIVE &&
                  sphere_material(&s, &s.spheres[3])->kind == TZ_MATERIAL_MIRROR,
              "count %ld: the three big spheres", n);
        for (int k = 1; k <= 3; k++)
            CHECK(in_view(&s, s.spheres[k].center, s.spheres[k].radius),
                  "count %ld: big sphere %d out of view", n, k);
        /* everything rests on the ground; the small ones touch nothing else */
        int floating = 0, overlaps = 0, sizes = 0;
        for (int k = 1; k < s.sphere_count; k++) {
            const sphere *a = &s.spheres[k];
            double gap = dist(a->center, ground->center) - (ground->radius + a->radius);
            floating += fabs(gap) > 2e-3;
            if (k < 4) continue;
            sizes += fabsf(a->radius - 0.2f) > 1e-6f;
            for (int j = 1; j < k; j++) {
                const sphere *b = &s.spheres[j];
                overlaps += dist(a->center, b->center) < (a->radius + b->radius) * 0.9999;
            }
        }
        CHECK(!floating, "count %ld: %d spheres do not rest on the ground", n, floating);
        CHECK(!overlaps, "count %ld: %d overlapping pairs", n, overlaps);
        CHECK(!sizes, "count %ld: %d small spheres not of radius 0.2", n, sizes);
        int m[4];
        count_materials(&s, m);
        if (n >= 500) {
            int small[4] = {m[0] - 2, m[1], m[2] - 1, m[3] - 1}; /* less the ground and big ones */
            CHECK(small[0] > small[1] && small[1] > small[2] && small[2] > 0 && small[3] > 0,
                  "count %ld: small spheres by material %d %d %d %d", n, small[0], small[1],
                  small[2], small[3]);
        }
        /* random colours: some dark, some bright */
        double lo = 1, hi = 0;
        for (int k = 4; k < s.sphere_count; k++) {
            lo = fmin(lo, sphere_material(&s, &s.spheres[k])->color.x);
            hi = fmax(hi, sphere_material(&s, &s.spheres[k])->color.x);
        }
        if (n >= 500) CHECK(lo < 0.1 && hi > 0.9, "count %ld: colours span %g..%g", n, lo, hi);
        scene_free(&s);
    }
    /* a grid that grows: 100000 spheres still parse and still do not overlap the big ones */
    const char *big = tmp_path("big.scene");
    CHECK(run_gen("random", "--count", "100000", "-o", big, NULL) == 0, "count 100000 failed");
    scene s = {0};
    if (parse(big, &s)) {
        CHECK(s.sphere_count == 100004, "count 100000: %d spheres", s.sphere_count);
        int close = 0;
        for (int k = 4; k < s.sphere_count; k++)
            for (int j = 1; j <= 3; j++)
                close += dist(s.spheres[k].center, s.spheres[j].center) < 1.2 * 0.9999;
        CHECK(!close, "count 100000: %d small spheres overlap a big one", close);
        scene_free(&s);
    } else {
        CHECK(false, "count 100000: does not parse");
    }
    remove(big);
    /* same seed, same bytes; another seed, other bytes */
    const char *a = tmp_path("ra.scene"), *b = tmp_path("rb.scene"), *c = tmp_path("rc.scene");
    const char *d = tmp_path("rd.scene");
    CHECK(run_gen("random", "--count", "300", "--seed", "42", "-o", a, NULL) == 0, "seed 42 a");
    CHECK(run_gen("random", "-o", b, "--seed", "42", "--count", "300", NULL) == 0, "seed 42 b");
    CHECK(run_gen("random", "--count", "300", "--seed", "43", "-o", c, NULL) == 0, "seed 43");
    CHECK(run_gen("random", "--count", "300", "-o", d, NULL) == 0, "default seed");
    CHECK(same_bytes(a, b), "random: seed 42 twice gives different files");
    CHECK(!same_bytes(a, c), "random: seeds 42 and 43 give the same file");
    CHECK(!same_bytes(a, d), "random: seed 42 and the default give the same file");
}

/* ---- command line: usage errors write nothing, failures leave nothing behind ---- */

static void test_usage(void) {
    const char *p = tmp_path("usage.scene");
    int before = tmpdir_entries();
    struct {
        const char *args[8];
    } bad[] = {
        {{NULL}},
        {{"bogus", "-o", p}},
        {{"sphereflake", "-o", p}},
        {{"sphereflake", "--depth", "8", "-o", p}},
        {{"sphereflake", "--depth", "-1", "-o", p}},
        {{"sphereflake", "--depth", "2x", "-o", p}},
        {{"sphereflake", "--depth", "", "-o", p}},
        {{"sphereflake", "-o", p, "--depth"}},
        {{"sphereflake", "--count", "5", "-o", p}},
        {{"random", "--depth", "2", "-o", p}},
        {{"random", "-o", p}},
        {{"random", "--count", "0", "-o", p}},
        {{"random", "--count", "3999989", "-o", p}},
        {{"random", "--count", "5", "--seed", "-1", "-o", p}},
        {{"random", "--count", "5", "--seed", "4294967296", "-o", p}},
        {{"random", "--count", "5", "--bogus", "-o", p}},
        {{"random", "--count", "5", "-o"}},
        {{"random", "--count", "5", "-o", ""}},
        {{"random", "extra", "--count", "5", "-o", p}},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        const char *const *a = bad[k].args;
        int rc = run_gen(a[0], a[1], a[2], a[3], a[4], a[5], NULL);
        CHECK(rc == 2, "usage case %zu (%s %s %s): exit %d, want 2", k, a[0] ? a[0] : "",
              a[1] ? a[1] : "", a[2] ? a[2] : "", rc);
        CHECK(!exists(p), "usage case %zu created the output", k);
    }
    CHECK(tmpdir_entries() == before, "usage errors left files behind");
    /* a usage error leaves an existing file alone */
    FILE *fp = fopen(p, "w");
    if (fp) {
        fputs("precious\n", fp);
        fclose(fp);
    }
    CHECK(run_gen("sphereflake", "--depth", "9", "-o", p, NULL) == 2, "depth 9");
    size_t n = 0;
    char *text = read_all(p, &n);
    CHECK(text && !strcmp(text, "precious\n"), "a usage error changed the existing file");
    free(text);
    /* a successful run replaces it */
    CHECK(run_gen("sphereflake", "--depth", "0", "-o", p, NULL) == 0, "depth 0 over a file");
    text = read_all(p, &n);
    CHECK(text && strstr(text, "sphere mirror"), "the existing file was not replaced");
    free(text);
    remove(p);
    /* write failures: exit 1, no file, no temporary left */
    before = tmpdir_entries();
    CHECK(run_gen("random", "--count", "5", "-o", tmp_path("no/such/dir.scene"), NULL) == 1,
          "missing folder: want exit 1");
    const char *folder = tmp_path("folder");
    mkdir(folder, 0755);
    CHECK(run_gen("random", "--count", "5", "-o", folder, NULL) == 1,
          "renaming over a folder: want exit 1");
    struct stat st;
    CHECK(stat(folder, &st) == 0 && S_ISDIR(st.st_mode), "the folder was replaced");
    rmdir(folder);
    CHECK(tmpdir_entries() == before, "failed writes left %d files behind",
          tmpdir_entries() - before);
    /* the generated file gets the mode of any file the user writes: 0666 less the umask */
    const char *mode = tmp_path("mode.scene");
    mode_t mask = umask(022);
    CHECK(run_gen("random", "--count", "1", "-o", mode, NULL) == 0, "mode.scene");
    umask(mask);
    CHECK(stat(mode, &st) == 0 && (st.st_mode & 0777) == 0644, "mode %o, want 644",
          (unsigned)(st.st_mode & 0777));
    remove(mode);
    /* --help prints the usage and succeeds */
    CHECK(run_gen("--help", NULL) == 0, "gen --help");
    CHECK(run_gen("random", "--help", NULL) == 0, "gen random --help");
}

/* ---- end to end: a small render of each kind is not black ---- */

static void render_small(const char *what, const char *path) {
    scene s = {0};
    if (!parse(path, &s)) {
        CHECK(false, "%s: does not parse", what);
        return;
    }
    s.pixel_size = s.plane_width / 40.0f; /* 40 x 30 */
    s.width = 40;
    s.height = 30;
    render_opts o;
    render_opts_from_scene(&s, &o);
    o.spp = 2;
    film f = {0};
    CHECK(render_film(&render_backend_cpu, &s, &o, &f), "%s: render failed", what);
    int lit = 0;
    for (int k = 0; f.accum && k < s.width * s.height; k++) {
        const float *p = &f.accum[k * 4];
        vec3 mean = v3_scale(v3(p[0], p[1], p[2]), 1.0f / p[3]);
        lit += dist(mean, s.background) > 0.05 && v3_dot(mean, v3(1, 1, 1)) > 0.05f;
    }
    /* the objects, not the sky, fill a good part of the frame, and they are lit */
    CHECK(lit > s.width * s.height / 5, "%s: only %d of %d pixels are lit objects", what, lit,
          s.width * s.height);
    CHECK(f.nonfinite == 0, "%s: %llu non-finite samples", what, (unsigned long long)f.nonfinite);
    film_free(&f);
    scene_free(&s);
}

static void test_render(void) {
    const char *flake = tmp_path("render_flake.scene"), *field = tmp_path("render_random.scene");
    CHECK(run_gen("sphereflake", "--depth", "2", "-o", flake, NULL) == 0, "render flake");
    CHECK(run_gen("random", "--count", "200", "-o", field, NULL) == 0, "render random");
    render_small("sphereflake", flake);
    render_small("random", field);
}

static void remove_tree(void) {
    DIR *d = opendir(tmpdir);
    for (struct dirent *e; d && (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) remove(tmp_path(e->d_name));
    if (d) closedir(d);
    rmdir(tmpdir);
}

int main(void) {
    if (!tmp_dir_make("test_gen")) {
        perror("mkdtemp");
        return 1;
    }
    test_sphereflake();
    test_random();
    test_usage();
    test_render();
    remove_tree();
    return check_summary("test_gen");
}
