/* test_diff.c: diff_images metrics against known values and diff_command exit codes and output. */
#include <fcntl.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "check.h"
#include "cli/cli.h"
#include "image/diff.h"
#include "image/image.h"
#include "tmp_dir.h"
#include "util/log.h"

static bool near(double got, double want, double tol) { return fabs(got - want) <= tol; }

enum { W = 6, H = 5 };

/* Values in [0.2, 0.7], each the decoded value of an sRGB byte so that a PPM holds it exactly. */
static void make_image(image *img) {
    image_init(img, W, H);
    for (int i = 0; i < W * H * 3; i++) {
        float v = 0.2f + 0.5f * (float)i / (W * H * 3);
        img->rgb[i] = tonemap_decode(tonemap_channel(v, TONEMAP_SRGB), TONEMAP_SRGB);
    }
}

static void copy_image(image *dst, const image *src) {
    image_init(dst, src->width, src->height);
    memcpy(dst->rgb, src->rgb, sizeof(float) * 3 * (size_t)src->width * (size_t)src->height);
}

static void test_identical(void) {
    image a, b;
    make_image(&a);
    copy_image(&b, &a);
    b.rgb[5] = a.rgb[5] = INFINITY; /* equal infinities count as equal, and two NaNs */
    b.rgb[6] = a.rgb[6] = NAN;
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(s.rmse == 0.0);
    EXPECT(isinf(s.psnr) && s.psnr > 0);
    EXPECT(s.max_diff == 0.0);
    EXPECT(s.differ_share == 0.0 && s.differ_count == 0);
    image_free(&a);
    image_free(&b);
}

static void test_constant_offset(void) {
    image a, b;
    make_image(&a);
    copy_image(&b, &a);
    for (int i = 0; i < W * H * 3; i++) b.rgb[i] += 0.01f;
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(near(s.rmse, 0.01, 1e-6)); /* sqrt(mean(0.01^2)) */
    EXPECT(near(s.max_diff, 0.01, 1e-6));
    EXPECT(isfinite(s.psnr) && s.psnr > 20 && s.psnr < 60);
    /* 0.01 linear is over 1/255 after sRGB encoding everywhere in [0.2, 0.7] */
    EXPECT(s.differ_count == W * H && s.differ_share == 1.0);

    for (int i = 0; i < W * H * 3; i++) b.rgb[i] = a.rgb[i] + 1e-4f; /* below 1/255 displayed */
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(near(s.rmse, 1e-4, 1e-7));
    EXPECT(s.differ_count == 0 && s.differ_share == 0.0);
    image_free(&a);
    image_free(&b);
}

static void test_psnr_known(void) {
    /* every byte two steps apart: 8-bit MSE 4, PSNR 10 log10(255^2 / 4) */
    image a, b;
    image_init(&a, W, H);
    image_init(&b, W, H);
    for (int i = 0; i < W * H * 3; i++) {
        a.rgb[i] = tonemap_decode((uint8_t)(10 + i), TONEMAP_SRGB);
        b.rgb[i] = tonemap_decode((uint8_t)(12 + i), TONEMAP_SRGB);
    }
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(near(s.psnr, 10.0 * log10(255.0 * 255.0 / 4.0), 1e-9));
    EXPECT(s.differ_count == W * H);
    image_free(&a);
    image_free(&b);
}

static void test_single_pixel(void) {
    image a, b;
    make_image(&a);
    copy_image(&b, &a);
    b.rgb[(2 * W + 3) * 3 + 1] += 0.2f;
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(s.differ_count == 1);
    EXPECT(s.differ_share == 1.0 / (W * H));
    EXPECT(near(s.rmse, sqrt(0.04 / (W * H * 3)), 1e-6));
    EXPECT(near(s.max_diff, 0.2, 1e-6));
    image_free(&a);
    image_free(&b);
}

static void test_nonfinite(void) {
    image a, b;
    make_image(&a);
    copy_image(&b, &a);
    b.rgb[7] = NAN;
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(isnan(s.rmse) && isnan(s.max_diff)); /* so that every threshold on them fails */
    /* The broken pixel also fails --min-psnr and --max-diff-share: the largest 8-bit difference
     * in one channel of 90 (10 log10(90) dB), though a NaN is written as black. */
    EXPECT(s.differ_count == 1);
    EXPECT(near(s.psnr, 10.0 * log10(90.0), 1e-9));
    b.rgb[7] = INFINITY; /* an infinity against a finite value: the same */
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(s.differ_count == 1 && near(s.psnr, 10.0 * log10(90.0), 1e-9));
    image_free(&a);
    image_free(&b);
}

/* PSNR and the share are on the 8-bit sRGB values an image shows: values above 1 that differ
 * show the same white and count only in rmse and max_diff. */
static void test_over_white(void) {
    image a, b;
    make_image(&a);
    copy_image(&b, &a);
    a.rgb[4] = 2.0f, b.rgb[4] = 5.0f;
    diff_stats s;
    EXPECT(diff_images(&a, &b, &s));
    EXPECT(s.max_diff == 3.0 && near(s.rmse, sqrt(9.0 / 90.0), 1e-12));
    EXPECT(s.differ_count == 0 && isinf(s.psnr));
    image_free(&a);
    image_free(&b);
}

static void test_size_mismatch(void) {
    image a, b;
    image_init(&a, W, H);
    image_init(&b, H, W);
    diff_stats s;
    EXPECT(!diff_images(&a, &b, &s));
    image_free(&b);
    image_init(&b, W, H + 1);
    EXPECT(!diff_images(&a, &b, &s));
    image_free(&a);
    image_free(&b);
}

static char cmd_out[8192], cmd_err[8192];
static log_level quiet_level = LOG_INFO;

static void read_capture(const char *path, char *buf, size_t cap) {
    FILE *fp = fopen(path, "rb");
    size_t n = fp ? fread(buf, 1, cap - 1, fp) : 0;
    buf[n] = '\0';
    if (fp) fclose(fp);
}

/* Runs `diff ARGS...` (NULL-terminated) with stdout and stderr captured into cmd_out, cmd_err. */
static int run_diff(const char *first, ...) {
    char *argv[16] = {"diff"};
    int argc = 1;
    va_list ap;
    va_start(ap, first);
    for (const char *arg = first; arg && argc < 15; arg = va_arg(ap, const char *))
        argv[argc++] = (char *)arg;
    va_end(ap);
    argv[argc] = NULL;

    char out_path[600], err_path[600];
    snprintf(out_path, sizeof out_path, "%s/stdout.txt", tmpdir);
    snprintf(err_path, sizeof err_path, "%s/stderr.txt", tmpdir);
    fflush(stdout);
    fflush(stderr);
    int saved_out = dup(1), saved_err = dup(2);
    int fo = open(out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    int fe = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fo, 1);
    dup2(fe, 2);
    close(fo);
    close(fe);
    log_set_level(LOG_INFO); /* captured, so the errors can be checked */
    int rc = cmd_diff(argc, argv);
    log_set_level(quiet_level);
    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
    read_capture(out_path, cmd_out, sizeof cmd_out);
    read_capture(err_path, cmd_err, sizeof cmd_err);
    return rc;
}

static void write_fixtures(void) {
    image a, b;
    make_image(&a);
    image_write(tmp_path("a.pfm"), &a, TONEMAP_SRGB);
    image_write(tmp_path("a.ppm"), &a, TONEMAP_SRGB);
    image_write(tmp_path("a.png"), &a, TONEMAP_SRGB);
    copy_image(&b, &a);
    for (int i = 0; i < W * H * 3; i++) b.rgb[i] += 0.01f;
    image_write(tmp_path("offset.pfm"), &b, TONEMAP_SRGB);
    memcpy(b.rgb, a.rgb, sizeof(float) * W * H * 3);
    b.rgb[(2 * W + 3) * 3 + 1] += 0.2f;
    image_write(tmp_path("pixel.pfm"), &b, TONEMAP_SRGB);
    image_free(&b);
    image_init(&b, W + 1, H);
    image_write(tmp_path("wide.pfm"), &b, TONEMAP_SRGB);
    image_free(&a);
    image_free(&b);
    FILE *fp = fopen(tmp_path("bad.ppm"), "wb");
    if (fp) {
        fputs("P6\n6 5\n255\nshort", fp);
        fclose(fp);
    }
}

static void test_command_metrics(void) {
    const char *a = tmp_path("a.pfm"), *ppm = tmp_path("a.ppm"), *png = tmp_path("a.png");
    EXPECT(run_diff(a, a, NULL) == 0);
    EXPECT(strstr(cmd_out, "rmse 0\n") && strstr(cmd_out, "psnr inf dB\n"));
    EXPECT(strstr(cmd_out, "max_diff 0\n") && strstr(cmd_out, "differ 0.0000% (0 of 30 pixels)\n"));
    /* the 8-bit files hold exactly the same linear values */
    EXPECT(run_diff(a, ppm, "--min-psnr", "inf", "--max-rmse", "0", NULL) == 0);
    EXPECT(run_diff(png, a, "--min-psnr", "inf", "--max-diff-share", "0", NULL) == 0);
    /* Without a threshold any difference fails, as cmp (issue 24, defect 9: it exited 0). */
    EXPECT(run_diff(a, tmp_path("pixel.pfm"), NULL) == 1);
    EXPECT(strstr(cmd_out, "differ 3.3333% (1 of 30 pixels)\n") != NULL);
    EXPECT(strstr(cmd_out, "max_diff 0.2") != NULL);
    EXPECT(strstr(cmd_out, "FAIL: the images differ (max_diff 0.2") != NULL);
    EXPECT(run_diff(a, tmp_path("offset.pfm"), NULL) == 1);
    /* A threshold the difference is within passes. */
    EXPECT(run_diff(a, tmp_path("pixel.pfm"), "--max-diff-share", "0.05", NULL) == 0);
    EXPECT(strstr(cmd_out, "FAIL") == NULL);
}

static void test_command_thresholds(void) {
    const char *a = tmp_path("a.pfm"), *off = tmp_path("offset.pfm");
    const char *px = tmp_path("pixel.pfm");
    EXPECT(run_diff(a, off, "--max-rmse", "0.1", NULL) == 0);
    EXPECT(run_diff(a, off, "--max-rmse", "0.001", NULL) == 1);
    EXPECT(strstr(cmd_out, "FAIL: rmse 0.0") && strstr(cmd_out, " > 0.001\n"));
    EXPECT(run_diff(a, a, "--min-psnr", "100", NULL) == 0);
    EXPECT(run_diff(a, off, "--min-psnr", "10", NULL) == 0);
    EXPECT(run_diff(a, off, "--min-psnr", "100", NULL) == 1);
    EXPECT(strstr(cmd_out, "FAIL: psnr ") && strstr(cmd_out, " dB < 100\n"));
    EXPECT(run_diff(a, px, "--max-diff-share", "0.05", NULL) == 0);
    EXPECT(run_diff(a, px, "--max-diff-share", "0.01", NULL) == 1);
    EXPECT(strstr(cmd_out, "FAIL: differ 3.3333% > 1%\n") != NULL);
    EXPECT(run_diff(a, off, "--max-diff-share", "1", NULL) == 0);
    /* thresholds just either side of the measured values */
    image ia, ib;
    diff_stats s;
    EXPECT(image_read(a, &ia, TONEMAP_SRGB) && image_read(off, &ib, TONEMAP_SRGB));
    EXPECT(diff_images(&ia, &ib, &s));
    image_free(&ia);
    image_free(&ib);
    char below[64], above[64];
    snprintf(below, sizeof below, "%.17g", s.psnr - 0.01);
    snprintf(above, sizeof above, "%.17g", s.psnr + 0.01);
    EXPECT(run_diff(a, off, "--min-psnr", below, NULL) == 0);
    EXPECT(run_diff(a, off, "--min-psnr", above, NULL) == 1);
    snprintf(below, sizeof below, "%.17g", s.rmse * 0.999);
    snprintf(above, sizeof above, "%.17g", s.rmse * 1.001);
    EXPECT(run_diff(a, off, "--max-rmse", below, NULL) == 1);
    EXPECT(run_diff(a, off, "--max-rmse", above, NULL) == 0);
    /* all three, only the last one failing */
    EXPECT(run_diff("--max-rmse", "0.5", a, "--min-psnr", "5", px, "--max-diff-share", "0", NULL) ==
           1);
    EXPECT(!strstr(cmd_out, "FAIL: rmse") && !strstr(cmd_out, "FAIL: psnr"));
    EXPECT(strstr(cmd_out, "FAIL: differ") != NULL);
}

static void test_command_failures(void) {
    const char *a = tmp_path("a.pfm");
    /* As cmp: 2 when the images cannot be read or compared, apart from 1 (past a threshold). */
    EXPECT(run_diff(a, tmp_path("wide.pfm"), NULL) == 2);
    EXPECT(strstr(cmd_err, "6x5") && strstr(cmd_err, "7x5"));
    EXPECT(cmd_out[0] == '\0');
    EXPECT(run_diff(a, tmp_path("missing.pfm"), NULL) == 2);
    EXPECT(run_diff(tmp_path("bad.ppm"), a, NULL) == 2);
    EXPECT(run_diff(a, tmp_path("a.bmp"), NULL) == 2);
    EXPECT(run_diff(a, tmp_path("missing.pfm"), "--max-rmse", "1", NULL) == 2);
}

static void test_command_usage(void) {
    const char *a = tmp_path("a.pfm");
    EXPECT(run_diff(NULL) == 2 && strstr(cmd_err, "usage: trazador diff"));
    EXPECT(run_diff(a, NULL) == 2 && strstr(cmd_err, "usage:"));
    EXPECT(run_diff(a, a, a, NULL) == 2 && strstr(cmd_err, "usage:"));
    EXPECT(run_diff(a, a, "--max-rmse", NULL) == 2 && strstr(cmd_err, "usage:"));
    EXPECT(run_diff(a, a, "--max-rmse", "abc", NULL) == 2 && strstr(cmd_err, "abc"));
    EXPECT(run_diff(a, a, "--max-rmse", "0.1x", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-rmse", "", NULL) == 2);
    EXPECT(run_diff(a, a, "--min-psnr", "nan", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-diff-share", NULL) == 2);
    /* A share is a fraction: 50 (meant as 50%) and negative values are refused, not passed. */
    EXPECT(run_diff(a, a, "--max-diff-share", "50", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-diff-share", "-0.5", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-rmse", "-1", NULL) == 2);
    /* An 8-bit PSNR is never negative; numbers are decimal, as in scene files. */
    EXPECT(run_diff(a, a, "--min-psnr", "-5", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-rmse", "0x1p-2", NULL) == 2 && strstr(cmd_err, "decimal"));
    EXPECT(run_diff(a, a, "--max-rmse", " 0.1", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-rmse", "1e999", NULL) == 2);
    EXPECT(run_diff(a, a, "--bogus", NULL) == 2 && strstr(cmd_err, "--bogus"));
    EXPECT(run_diff(a, a, "--max-rmse=abc", NULL) == 2 && strstr(cmd_err, "'abc'"));
    EXPECT(run_diff(a, a, "--max-rmse=", NULL) == 2);
    EXPECT(run_diff(a, a, "--max-rmsex=1", NULL) == 2 && strstr(cmd_err, "'--max-rmsex'"));
    EXPECT(cmd_out[0] == '\0'); /* nothing read, nothing printed */
    /* --flag=value as well as --flag value; -- ends the options. */
    EXPECT(run_diff(a, tmp_path("offset.pfm"), "--max-rmse=0.001", NULL) == 1);
    EXPECT(run_diff(a, tmp_path("offset.pfm"), "--max-rmse=0.1", NULL) == 0);
    EXPECT(run_diff("--max-rmse=0", "--", a, a, NULL) == 0);
    EXPECT(run_diff("--", a, "--max-rmse", NULL) == 2 && strstr(cmd_err, "--max-rmse"));
    EXPECT(run_diff("--help", NULL) == 0 && strstr(cmd_out, "usage:"));
    /* --help describes every flag, with its default. */
    EXPECT(strstr(cmd_out, "--max-rmse X") && strstr(cmd_out, "--min-psnr DB") &&
           strstr(cmd_out, "--max-diff-share FRACTION") && strstr(cmd_out, "(default: no limit)"));
}

int main(void) {
    if (!tmp_dir_make("test_diff")) {
        perror("mkdtemp");
        return 1;
    }
    /* the expected errors are noise; TRAZADOR_TEST_VERBOSE=1 shows them */
    if (!getenv("TRAZADOR_TEST_VERBOSE")) quiet_level = (log_level)(LOG_ERROR + 1);
    log_set_level(quiet_level);
    write_fixtures();
    CHECK_CASE(test_identical);
    CHECK_CASE(test_constant_offset);
    CHECK_CASE(test_psnr_known);
    CHECK_CASE(test_single_pixel);
    CHECK_CASE(test_nonfinite);
    CHECK_CASE(test_over_white);
    CHECK_CASE(test_size_mismatch);
    CHECK_CASE(test_command_metrics);
    CHECK_CASE(test_command_thresholds);
    CHECK_CASE(test_command_failures);
    CHECK_CASE(test_command_usage);
    const char *files[] = {"a.pfm",    "a.ppm",   "a.png",      "offset.pfm", "pixel.pfm",
                           "wide.pfm", "bad.ppm", "stdout.txt", "stderr.txt"};
    for (size_t i = 0; i < sizeof files / sizeof files[0]; i++) unlink(tmp_path(files[i]));
    rmdir(tmpdir);
    return check_summary("test_diff");
}
