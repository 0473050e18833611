/* cli.h: what the subcommands share (argument numbers, rendering with a chosen back end) and
 * bench_command, which main.c dispatches to. */
#ifndef TRAZADOR_CLI_H
#define TRAZADOR_CLI_H

#include <stdbool.h>

#include "render/render.h"

typedef enum backend_choice { BACKEND_AUTO = 0, BACKEND_VULKAN, BACKEND_CPU } backend_choice;

/* A macro's value as a string literal, so that messages state limits from their macros. */
#define CLI_AS_TEXT(x) CLI_AS_TEXT_(x)
#define CLI_AS_TEXT_(x) #x

/* Parses a whole decimal integer in [min, max]; false on anything else. */
bool cli_parse_int(const char *text, long long min, long long max, long long *out);
/* Parses a whole decimal number, or "inf" (no hex, nan or spaces); false on anything else. */
bool cli_parse_number(const char *text, double *out);
/* Renders with the chosen back end (auto: Vulkan when a device exists); false on failure. */
bool cli_render(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                const char **used);

/* `trazador bench`: fixed workloads on the back ends; 0, or 1 on a failure, 2 on usage. */
int bench_command(int argc, char **argv);

#endif
