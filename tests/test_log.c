/* test_log.c: the message sink's held errors (src/util/log.c): every line kept whole and in order,
 * however long, and nothing held once released. */
#include <string.h>

#include "check.h"
#include "util/log.h"

static void test_hold_long_errors(void) {
    /* Validation-layer messages run to a kilobyte or more: five of them and a summary line. */
    char line[1201];
    memset(line, 'x', sizeof line - 1);
    line[sizeof line - 1] = '\0';
    log_hold_errors();
    for (int k = 0; k < 5; k++) log_error("%d %s", k, line);
    log_error("stopping after 5 errors");
    const char *held = log_release_errors();
    const char *at = held;
    for (int k = 0; k < 5; k++) {
        char start[8];
        snprintf(start, sizeof start, "%d x", k);
        EXPECT(!strncmp(at, start, strlen(start)));
        const char *end = strchr(at, '\n');
        EXPECT(end && (size_t)(end - at) == strlen(start) - 1 + strlen(line));
        if (!end) return;
        at = end + 1;
    }
    EXPECT(!strcmp(at, "stopping after 5 errors\n"));
}

static void test_release_stops_holding(void) {
    log_hold_errors();
    log_error("held");
    EXPECT(!strcmp(log_release_errors(), "held\n"));
    log_set_level(LOG_ERROR + 1); /* printed now, not held: keep the test's output clean */
    log_error("printed");
    log_set_level(LOG_INFO);
    EXPECT(!strcmp(log_release_errors(), "held\n"));
    log_hold_errors();
    EXPECT(!strcmp(log_release_errors(), ""));
}

int main(void) {
    CHECK_CASE(test_hold_long_errors);
    CHECK_CASE(test_release_stops_holding);
    return check_summary("test_log");
}
