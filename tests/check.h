/* check.h: the tiny assertion helpers of the C tests: count, report each failure, summarize. */
#ifndef TRAZADOR_CHECK_H
#define TRAZADOR_CHECK_H

#include <stdio.h>

static int check_passed, check_failed;

#define CHECK(cond, ...)                                                    \
    do {                                                                    \
        if (cond) {                                                         \
            check_passed++;                                                 \
        } else {                                                            \
            check_failed++;                                                 \
            fprintf(stderr, "FAIL %s:%d: %s: ", __FILE__, __LINE__, #cond); \
            fprintf(stderr, __VA_ARGS__);                                   \
            fputc('\n', stderr);                                            \
        }                                                                   \
    } while (0)

/* The case check_case is running (NULL: none), named in EXPECT's failures. */
static const char *check_case_name;

/* CHECK with no message of its own: a failure names the running case. */
#define EXPECT(cond) CHECK(cond, "in %s", check_case_name ? check_case_name : "main")

/* Runs fn as the case `name`. */
static inline void check_case(const char *name, void (*fn)(void)) {
    check_case_name = name;
    fn();
    check_case_name = NULL;
}
#define CHECK_CASE(fn) check_case(#fn, fn)

/* Prints the closing "name: N passed, N failed" line; returns the exit code. */
static inline int check_summary(const char *name) {
    printf("%s: %d passed, %d failed\n", name, check_passed, check_failed);
    return check_failed ? 1 : 0;
}

#endif
