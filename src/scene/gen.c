/* gen.c: the scene generators of gen.h (the `trazador gen` subcommand is src/cli/cmd_gen.c).
 *
 * - sphereflake: Eric Haines' SPD "balls": every sphere carries 9 children of a third of its
 *   radius, touching it, 6 around its equator and 3 on its upper hemisphere, turned towards the
 *   direction it grew in, over a floor, lit by the SPD's three lights under its sky colour.
 * - random: the final scene of "Ray Tracing in One Weekend": three big spheres and N small ones
 *   on a jittered grid that grows with N, all resting on a huge ground sphere.
 *
 * Scenes are streamed through one buffer with a hand-made fixed-point number formatter (no
 * per-sphere allocation, no printf per number): millions of spheres are written at the speed of
 * the disk, not of printf.
 * Random choices come from the project's counter-based RNG, one stream per sphere, so a seed
 * gives the same bytes on every machine. */
#include "scene/gen.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "common/rng.h"
#include "scene/scene.h"
#include "util/atomic_file.h"
#include "util/log.h"

_Static_assert(GEN_MAX_COUNT + 4 <= SCENE_MAX_SPHERES, "random scenes must stay parseable");

/* The sample_index argument of rng_seed, one per kind of stream, so no two streams meet. */
#define STREAM_FLAKE_SPHERE 0x464c4b31u  /* per flake sphere: its colour */
#define STREAM_RANDOM_PICK 0x524e4431u   /* which grid cells hold a small sphere */
#define STREAM_RANDOM_SPHERE 0x524e4432u /* per small sphere: place, material, colour */

/* Decimal places written: positions keep more digits than a float holds (depth-7 flake spheres
 * have radii of 4.6e-4), colours and material constants need few. */
#define FLAKE_PLACES 9
#define RANDOM_PLACES 6
#define COLOR_PLACES 4

/* ---- output: one buffer, numbers formatted by hand ---- */

#define OUT_CAPACITY ((size_t)1 << 20)
#define OUT_LINE_MAX 512 /* room left before each line; the longest line is under 300 bytes */

typedef struct out {
    FILE *fp;
    char *buf;
    size_t len;
    int err; /* errno of the first failure, 0 while all is well */
} out;

static void out_flush(out *o) {
    if (o->len && !o->err && fwrite(o->buf, 1, o->len, o->fp) != o->len)
        o->err = errno ? errno : EIO;
    o->len = 0;
}

/* Call before each line: makes room for OUT_LINE_MAX bytes. */
static void out_line(out *o) {
    if (o->len > OUT_CAPACITY - OUT_LINE_MAX) out_flush(o);
}

static void out_str(out *o, const char *s) {
    size_t n = strlen(s);
    memcpy(o->buf + o->len, s, n);
    o->len += n;
}

/* Appends v rounded to `places` decimals (0..9), trailing zeros dropped: plain decimal text that
   the parser reads back (no exponent, never "-0"). Generated values are finite and far below
   1e6; a non-finite one is a bug, reported as a failed write rather than written. */
static void out_num(out *o, double v, int places) {
    static const double scale[] = {1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
    double scaled = v * scale[places];
    if (!(fabs(scaled) < 9e15)) {
        if (!o->err) o->err = EDOM;
        out_str(o, "0");
        return;
    }
    long long q = llround(scaled);
    if (q < 0) o->buf[o->len++] = '-';
    unsigned long long u = (unsigned long long)(q < 0 ? -q : q);
    char digits[24]; /* least significant first; at least places + 1 of them */
    int n = 0;
    do {
        digits[n++] = (char)('0' + u % 10);
        u /= 10;
    } while (u || n <= places);
    int zeros = 0;
    while (zeros < places && digits[zeros] == '0') zeros++;
    for (int k = n - 1; k >= places; k--) o->buf[o->len++] = digits[k];
    if (zeros < places) {
        o->buf[o->len++] = '.';
        for (int k = places - 1; k >= zeros; k--) o->buf[o->len++] = digits[k];
    }
}

static void out_vec(out *o, const char *key, double x, double y, double z, int places) {
    out_str(o, key);
    out_num(o, x, places);
    out_str(o, " ");
    out_num(o, y, places);
    out_str(o, " ");
    out_num(o, z, places);
}

static double clamp01(double v) { return v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v; }

/* Starts a sphere line: material, center, radius and color; the caller adds the material's keys
   and the newline. */
static void out_sphere(out *o, const char *material, const double c[3], double radius,
                       const double color[3], int places) {
    out_line(o);
    out_str(o, "sphere ");
    out_str(o, material);
    out_vec(o, " center ", c[0], c[1], c[2], places);
    out_str(o, " radius ");
    out_num(o, radius, places);
    out_vec(o, " color ", clamp01(color[0]), clamp01(color[1]), clamp01(color[2]), COLOR_PLACES);
}

/* camera, plane, lights, background and render lines shared by both scenes; the camera looks
   from `from` at `at`; lights are {x, y, z, power}. */
static void out_setup(out *o, const double from[3], const double at[3], const double lights[][4],
                      int light_count, const double background[3], int places) {
    out_line(o);
    out_vec(o, "camera position ", from[0], from[1], from[2], places);
    out_vec(o, " direction ", at[0] - from[0], at[1] - from[1], at[2] - from[2], places);
    out_str(o, " up 0 1 0\nplane width 4 height 3 pixel 0.01\n");
    for (int k = 0; k < light_count; k++) {
        out_line(o);
        out_vec(o, "light position ", lights[k][0], lights[k][1], lights[k][2], places);
        out_str(o, " power ");
        out_num(o, lights[k][3], 3);
        out_str(o, "\n");
    }
    out_vec(o, "background ", background[0], background[1], background[2], COLOR_PLACES);
    out_str(o, "\nrender samples 16 indirect on\n");
}

/* ---- sphereflake ---- */

/* Level colours of the diffuse and Phong spheres, cycled from level 1 down. */
static const double flake_palette[][3] = {
    {0.85, 0.35, 0.2}, {0.2, 0.55, 0.85},  {0.35, 0.75, 0.3},  {0.9, 0.75, 0.25},
    {0.7, 0.3, 0.75},  {0.25, 0.75, 0.75}, {0.95, 0.55, 0.65},
};
static const double flake_gold[3] = {1.0, 0.9, 0.7}; /* the SPD's object colour */

typedef struct flake {
    out *o;
    uint32_t seed;
    uint32_t index;    /* spheres written so far: the RNG stream of the next one */
    double dirs[9][3]; /* child directions around +z: slots 0-5 the equator, 6-8 above it */
} flake;

/* The SPD's 9 directions: 6 on the equator every 60 degrees from 15, and 3 at 54.7 degrees of
   elevation (1/sqrt(3) from the axis horizontally) every 120 degrees from 45, between them.
   Built from square roots only (correctly rounded everywhere, unlike sin and cos), so that the
   scene's bytes do not depend on the C library. */
static void flake_init_dirs(flake *f) {
    const double c15 = (sqrt(6.0) + sqrt(2.0)) / 4.0, s15 = (sqrt(6.0) - sqrt(2.0)) / 4.0;
    const double h = sqrt(0.5), r3 = sqrt(3.0);
    /* cos and sin of 15, 75, 135, 195, 255, 315 degrees, then of 45, 165, 285 */
    const double cs[9][2] = {{c15, s15}, {s15, c15}, {-h, h},     {-c15, -s15}, {-s15, -c15},
                             {h, -h},    {h, h},     {-c15, s15}, {s15, -c15}};
    for (int k = 0; k < 9; k++) {
        double across = k < 6 ? 1.0 : 1.0 / r3;
        f->dirs[k][0] = cs[k][0] * across;
        f->dirs[k][1] = cs[k][1] * across;
        f->dirs[k][2] = k < 6 ? 0.0 : sqrt(2.0 / 3.0);
    }
}

/* The smallest rotation taking +z to the unit vector d (Rodrigues), as the SPD builds it; a half
   turn about y when d is -z, where that rotation is not unique. */
static void rotation_from_z(const double d[3], double m[3][3]) {
    double c = d[2];
    if (c < -1.0 + 1e-12) {
        static const double half_turn[3][3] = {{-1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
        memcpy(m, half_turn, sizeof half_turn);
        return;
    }
    /* R = I + [v]x + [v]x^2 / (1 + c) with v = z x d = (-dy, dx, 0) */
    double vx = -d[1], vy = d[0], h = 1.0 / (1.0 + c);
    m[0][0] = 1.0 - h * vy * vy, m[0][1] = h * vx * vy, m[0][2] = vy;
    m[1][0] = h * vx * vy, m[1][1] = 1.0 - h * vx * vx, m[1][2] = -vx;
    m[2][0] = -vy, m[2][1] = vx, m[2][2] = c;
}

/* Writes one flake sphere. The flake is built z-up like the SPD, with a root of radius 1 at the
   origin, and written y-up resting on the floor: (x, y, z) -> (x, z + 1, -y). Materials: the
   root and the upper children of even levels are mirrors, upper children of odd levels glass,
   equator children Phong on odd levels and Lambertian on even ones. */
static void flake_write_sphere(flake *f, const double c[3], double r, int level, int slot) {
    uint32_t state = rng_seed(f->seed, f->index++, STREAM_FLAKE_SPHERE);
    const double *base = level == 0 ? flake_gold : flake_palette[(level - 1) % 7];
    double color[3];
    for (int k = 0; k < 3; k++) color[k] = base[k] + 0.2 * (rng_next(&state) - 0.5);
    double w[3] = {c[0], c[2] + 1.0, -c[1]};
    bool upper = slot >= 6, odd = level % 2 == 1;
    out *o = f->o;
    if (level == 0 || (upper && !odd)) {
        if (level > 0)
            for (int k = 0; k < 3; k++) color[k] = 0.7 + 0.3 * color[k];
        out_sphere(o, "mirror", w, r, color, FLAKE_PLACES);
        out_str(o, "\n");
    } else if (upper) {
        for (int k = 0; k < 3; k++) color[k] = 0.8 + 0.2 * color[k];
        out_sphere(o, "refractive", w, r, color, FLAKE_PLACES);
        out_str(o, " ior 1.5\n");
    } else if (odd) {
        out_sphere(o, "phong", w, r, color, FLAKE_PLACES);
        out_str(o, " ks 0.5 alpha 37\n"); /* the SPD's shiny surface */
    } else {
        out_sphere(o, "lambertian", w, r, color, FLAKE_PLACES);
        out_str(o, "\n");
    }
}

/* Writes the sphere at c and, depth_left levels down, its children, grown along dir. */
static void flake_grow(flake *f, const double c[3], double r, const double dir[3], int level,
                       int slot, int depth_left) {
    if (f->o->err) return;
    flake_write_sphere(f, c, r, level, slot);
    if (depth_left == 0) return;
    double m[3][3];
    rotation_from_z(dir, m);
    double dist = r * (4.0 / 3.0); /* the child, of radius r/3, touches its parent */
    for (int k = 0; k < 9; k++) {
        const double *s = f->dirs[k];
        double d[3], child[3];
        for (int i = 0; i < 3; i++) {
            d[i] = m[i][0] * s[0] + m[i][1] * s[1] + m[i][2] * s[2];
            child[i] = c[i] + dist * d[i];
        }
        flake_grow(f, child, r / 3.0, d, level + 1, k, depth_left - 1);
    }
}

static long flake_count(int depth) {
    long n = 1, level = 1;
    for (int k = 1; k <= depth; k++) n += (level *= 9);
    return n;
}

static void sphereflake_write(out *o, int depth, uint32_t seed) {
    char line[OUT_LINE_MAX];
    snprintf(line, sizeof line,
             "# trazador gen sphereflake --depth %d --seed %lu: Eric Haines' sphereflake (SPD "
             "\"balls\"),\n# %ld sphere%s and the ground sphere\n",
             depth, (unsigned long)seed, flake_count(depth), flake_count(depth) == 1 ? "" : "s");
    out_line(o);
    out_str(o, line);
    /* The SPD's view, lights and sky, turned y-up and scaled to a root of radius 1 (the SPD's is
       0.5); the camera stands back along the SPD's view direction until the whole flake (within
       2 root radii of the root's centre) fits the 21-degree vertical field of view. */
    const double at[3] = {0.0, 1.2, 0.0};
    const double view[3] = {2.1, 1.7, -1.3}, view_len = sqrt(2.1 * 2.1 + 1.7 * 1.7 + 1.3 * 1.3);
    double from[3];
    for (int k = 0; k < 3; k++) from[k] = at[k] + 12.5 * view[k] / view_len;
    const double lights[3][4] = {{8, 5, -6, 150}, {2, 9, 8, 150}, {-6, 11, -2, 150}};
    const double sky[3] = {0.078, 0.361, 0.753};
    out_setup(o, from, at, lights, 3, sky, 4);
    /* the SPD's beige floor, as a huge sphere touching the root from below */
    const double ground[3] = {0.0, -1000.0, 0.0}, beige[3] = {0.8, 0.6, 0.264};
    out_sphere(o, "lambertian", ground, 1000.0, beige, 1);
    out_str(o, "\n");
    flake f = {.o = o, .seed = seed};
    flake_init_dirs(&f);
    const double root[3] = {0.0, 0.0, 0.0}, up[3] = {0.0, 0.0, 1.0};
    flake_grow(&f, root, 1.0, up, 0, 0, depth);
}

/* ---- random spheres ---- */

#define SMALL_RADIUS 0.2
/* The small spheres' centres stay within [0.2, 0.8] of their unit cell, so that two never
   overlap; cells closer than this to a big sphere's foot stay empty. */
#define CELL_MARGIN 0.2
#define BIG_CLEARANCE 1.0

static const double big_x[3] = {-4.0, 0.0, 4.0};

/* Height of the centre of a sphere of radius r resting on the ground sphere (radius R, top at
   the origin) at horizontal distance d from its axis: sqrt((R + r)^2 - d^2) - R, without the
   cancellation. */
static double rest_height(double R, double r, double d) {
    return (2.0 * R * r + r * r - d * d) / (sqrt((R + r) * (R + r) - d * d) + R);
}

/* True when a small sphere anywhere in cell (x0, z0)-(x0 + 1, z0 + 1) could touch a big one. */
static bool cell_blocked(double x0, double z0) {
    for (int b = 0; b < 3; b++) {
        double dx =
            fmax(fmax(x0 + CELL_MARGIN - big_x[b], big_x[b] - (x0 + 1.0 - CELL_MARGIN)), 0.0);
        double dz = fmax(fmax(z0 + CELL_MARGIN, -(z0 + 1.0 - CELL_MARGIN)), 0.0);
        if (dx * dx + dz * dz < BIG_CLEARANCE * BIG_CLEARANCE) return true;
    }
    return false;
}

/* Side of the square grid, in cells: even (so the big spheres stand on cell corners), at least
   the 22 of the book, and large enough for count free cells. */
static long random_grid_side(long count) {
    long side = 22;
    while (side * side - 12 < count) side += 2; /* each big sphere blocks the 4 cells at its foot */
    return side;
}

static void random_small_sphere(out *o, uint32_t seed, uint32_t cell, double x0, double z0,
                                double ground_radius) {
    uint32_t state = rng_seed(seed, cell, STREAM_RANDOM_SPHERE);
    double u[8];
    for (int k = 0; k < 8; k++) u[k] = rng_next(&state);
    const double span = 1.0 - 2.0 * CELL_MARGIN;
    double c[3] = {x0 + CELL_MARGIN + span * u[0], 0.0, z0 + CELL_MARGIN + span * u[1]};
    c[1] = rest_height(ground_radius, SMALL_RADIUS, sqrt(c[0] * c[0] + c[2] * c[2]));
    double color[3] = {u[3], u[4], u[5]};
    if (u[2] < 0.6) {
        out_sphere(o, "lambertian", c, SMALL_RADIUS, color, RANDOM_PLACES);
        out_str(o, "\n");
    } else if (u[2] < 0.8) {
        out_sphere(o, "phong", c, SMALL_RADIUS, color, RANDOM_PLACES);
        out_str(o, " ks ");
        out_num(o, 0.1 + 0.5 * u[6], COLOR_PLACES);
        out_str(o, " alpha ");
        out_num(o, floor(8.0 + 120.0 * u[7]), 0);
        out_str(o, "\n");
    } else if (u[2] < 0.92) {
        for (int k = 0; k < 3; k++) color[k] = 0.5 + 0.5 * color[k]; /* the book's metal */
        out_sphere(o, "mirror", c, SMALL_RADIUS, color, RANDOM_PLACES);
        out_str(o, "\n");
    } else {
        for (int k = 0; k < 3; k++) color[k] = 0.85 + 0.15 * color[k];
        out_sphere(o, "refractive", c, SMALL_RADIUS, color, RANDOM_PLACES);
        out_str(o, " ior ");
        out_num(o, 1.3 + 0.4 * u[6], COLOR_PLACES);
        out_str(o, "\n");
    }
}

static void random_write(out *o, long count, uint32_t seed) {
    long side = random_grid_side(count);
    double half = (double)(side / 2);
    double ground_radius = fmax(1000.0, 2.0 * (double)side); /* stays a ground, not a hill */
    double k = (double)side / 22.0; /* the book's view and lights, grown with the grid */
    char line[OUT_LINE_MAX];
    snprintf(line, sizeof line,
             "# trazador gen random --count %ld --seed %lu: the final scene of \"Ray Tracing in "
             "One Weekend\",\n# %ld small spheres on a %ldx%ld grid, 3 big ones and the ground "
             "sphere\n",
             count, (unsigned long)seed, count, side, side);
    out_line(o);
    out_str(o, line);
    const double from[3] = {13.0 * k, 2.0 * k, 3.0 * k}, at[3] = {0.0, 0.0, 0.0};
    const double lights[3][4] = {{6.0 * k, 14.0 * k, 10.0 * k, 650.0 * k * k},
                                 {-10.0 * k, 12.0 * k, 6.0 * k, 350.0 * k * k},
                                 {2.0 * k, 10.0 * k, -12.0 * k, 250.0 * k * k}};
    const double sky[3] = {0.7, 0.8, 1.0};
    out_setup(o, from, at, lights, 3, sky, RANDOM_PLACES);
    const double ground[3] = {0.0, -ground_radius, 0.0}, grey[3] = {0.5, 0.5, 0.5};
    out_sphere(o, "lambertian", ground, ground_radius, grey, RANDOM_PLACES);
    out_str(o, "\n");
    /* the book's three: glass in the middle, brown Lambertian behind, metal in front */
    const char *big_material[3] = {"lambertian", "refractive", "mirror"};
    const double big_color[3][3] = {{0.4, 0.2, 0.1}, {1, 1, 1}, {0.7, 0.6, 0.5}};
    for (int b = 0; b < 3; b++) {
        double c[3] = {big_x[b], rest_height(ground_radius, 1.0, fabs(big_x[b])), 0.0};
        out_sphere(o, big_material[b], c, 1.0, big_color[b], RANDOM_PLACES);
        out_str(o, b == 1 ? " ior 1.5\n" : "\n");
    }
    /* Exactly count of the free cells, each kept with probability needed / remaining (Knuth's
       selection sampling): spread over the whole grid, in one pass, no memory. */
    long free_cells = 0;
    for (long i = 0; i < side; i++)
        for (long j = 0; j < side; j++)
            free_cells += !cell_blocked((double)i - half, (double)j - half);
    uint32_t pick = rng_seed(seed, 0, STREAM_RANDOM_PICK);
    long needed = count;
    for (long i = 0; i < side && needed > 0 && !o->err; i++) {
        for (long j = 0; j < side && needed > 0; j++) {
            double x0 = (double)i - half, z0 = (double)j - half;
            if (cell_blocked(x0, z0)) continue;
            if ((double)rng_next(&pick) * (double)free_cells-- < (double)needed) {
                random_small_sphere(o, seed, (uint32_t)(i * side + j), x0, z0, ground_radius);
                needed--;
            }
        }
    }
}

/* ---- API ---- */

static bool desc_valid(const gen_desc *d) {
    if (d->kind == GEN_SPHEREFLAKE) return d->depth >= 0 && d->depth <= GEN_MAX_DEPTH;
    if (d->kind == GEN_RANDOM) return d->count >= 1 && d->count <= GEN_MAX_COUNT;
    return false;
}

long gen_sphere_count(const gen_desc *desc) {
    if (!desc_valid(desc)) return 0;
    return desc->kind == GEN_SPHEREFLAKE ? flake_count(desc->depth) + 1 : desc->count + 4;
}

/* Streams the scene into fp; 0 or an errno value. */
static int generate(const gen_desc *desc, FILE *fp) {
    out o = {.fp = fp, .buf = malloc(OUT_CAPACITY)};
    if (!o.buf) return ENOMEM;
    if (desc->kind == GEN_SPHEREFLAKE)
        sphereflake_write(&o, desc->depth, desc->seed);
    else
        random_write(&o, desc->count, desc->seed);
    out_flush(&o);
    free(o.buf);
    return o.err;
}

bool gen_write(const gen_desc *desc, FILE *fp) {
    if (!desc_valid(desc)) {
        log_error("gen: invalid generator settings");
        return false;
    }
    int err = generate(desc, fp);
    if (!err && fflush(fp) != 0) err = errno ? errno : EIO;
    if (err) log_error("gen: cannot write the scene: %s", strerror(err));
    return !err;
}

static int write_scene(FILE *fp, const void *context) { return generate(context, fp); }

bool gen_write_file(const gen_desc *desc, const char *path) {
    if (!path || !strcmp(path, "-")) return gen_write(desc, stdout);
    if (!desc_valid(desc)) {
        log_error("gen: invalid generator settings");
        return false;
    }
    /* A failed run leaves no truncated scene and any old file intact. */
    return atomic_file_write(path, write_scene, desc);
}
