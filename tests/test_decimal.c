/* test_decimal.c: the parser's fast decimal conversion (src/scene/decimal.h) against strtod, bit
 * for bit: fixed edge cases, then a million random decimals of every shape the scene syntax allows;
 * and the fast path must take the short decimals that scene files are made of. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "scene/decimal.h"

/* 1 when the fast path took s (and then gave strtod's double), 0 when it left s to strtod. */
static int agrees(const char *s) {
    double fast = 0.0, slow = strtod(s, NULL);
    if (!decimal_fast(s, (int)strlen(s), &fast)) return 0;
    CHECK(memcmp(&fast, &slow, sizeof fast) == 0, "'%s': %.17g, strtod %.17g", s, fast, slow);
    return 1;
}

static void test_cases(void) {
    static const struct {
        const char *text;
        int fast;
    } cases[] = {
        {"0", 1},
        {"-0", 1},
        {"-0.0", 1},
        {".5", 1},
        {"5.", 1},
        {"+3", 1},
        {"0.1", 1},
        {"-13.000001", 1},
        {"1e22", 1},
        {"1e23", 0},
        {"1E-22", 1},
        {"1e-23", 0},
        {"0.5e-21", 1},
        {"12e+10", 1},
        {"0e999999", 0},
        {"1e0000000000001", 1},
        {"123456789012345", 1},
        {"1234567890123456", 0},
        {"0.000000000000000000001", 1},
        {"9007199254740993", 0},
        {"1.7976931348623157e308", 0},
        {"000000000000000000000000012.5", 1},
        {"3.4028235e38", 0},
        {"100000000000000000000", 0},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        int took = agrees(cases[k].text);
        CHECK(took == cases[k].fast, "'%s': fast path %s", cases[k].text,
              took ? "taken" : "not taken");
    }
}

/* A random decimal: sign, 1 to 20 digits (some leading zeros), a point anywhere or none, an
 * exponent of -40..40 or none. */
static void random_decimal(char *out, unsigned *state) {
    int n = 0, digits = 1 + rand_r(state) % 20, point = rand_r(state) % (digits + 2) - 1;
    if (rand_r(state) % 2) out[n++] = rand_r(state) % 2 ? '-' : '+';
    for (int k = 0; k < digits; k++) {
        if (k == point) out[n++] = '.';
        out[n++] = (char)('0' + (k < 2 && rand_r(state) % 4 == 0 ? 0 : rand_r(state) % 10));
    }
    if (point == digits) out[n++] = '.';
    if (rand_r(state) % 2) n += sprintf(out + n, "e%d", rand_r(state) % 81 - 40);
    out[n] = '\0';
}

static void test_random(void) {
    unsigned state = 1u;
    long taken = 0, count = 1000000;
    for (long k = 0; k < count; k++) {
        char text[64];
        random_decimal(text, &state);
        taken += agrees(text);
    }
    CHECK(taken > count / 3, "the fast path took only %ld of %ld", taken, count);
}

/* The numbers trazador gen writes ("%.6f" and friends) all take the fast path. */
static void test_generated_forms(void) {
    unsigned state = 7u;
    int slow = 0;
    for (int k = 0; k < 100000; k++) {
        char text[64];
        double v = (rand_r(&state) / (double)RAND_MAX - 0.5) * 2000.0;
        snprintf(text, sizeof text, k % 2 ? "%.6f" : "%g", v);
        slow += !agrees(text);
    }
    CHECK(slow == 0, "%d generated numbers left to strtod", slow);
}

int main(void) {
    test_cases();
    test_random();
    test_generated_forms();
    return check_summary("test_decimal");
}
