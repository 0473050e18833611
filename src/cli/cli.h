/* cli.h: the subcommands main.c dispatches to, each in its own cmd_*.c. Each takes its argv with
 * argv[0] the subcommand's name and returns the exit code: 0 success, 1 runtime failure, 2 usage
 * or scene error (diff: 0 within its thresholds, 1 past one, 2 when it cannot compare). */
#ifndef TRAZADOR_CLI_H
#define TRAZADOR_CLI_H

#include <stdbool.h>

/* A macro's value as a string literal, so that messages state limits from their macros. */
#define CLI_AS_TEXT(x) CLI_AS_TEXT_(x)
#define CLI_AS_TEXT_(x) #x

/* Warns once about --tonemap (*tm) or --exr-type (*exr_type), -1 when not given, given for an
 * output of `format` ("png", ..., "exr"; part: an EXR part) that has no use for it, then sets
 * the ones not given to their defaults (sRGB, half); never fails. */
void cli_warn_unused(const char *format, bool part, int *tm, int *exr_type);
/* --width N (N >= 0; -1: not given): N pixels across scene s's plane, the height whole too;
 * false (said in one line) when it is not. */
struct scene;
bool cli_apply_width(long long width, struct scene *s);
/* `trazador render`: renders a scene into an image. */
int cmd_render(int argc, char **argv);
/* `trazador merge PARTS... -o OUT`: merges render parts into the whole render. */
int cmd_merge(int argc, char **argv);
/* `trazador diff A B`: image metrics against thresholds. */
int cmd_diff(int argc, char **argv);
/* `trazador gen sphereflake|random`: writes a generated scene. */
int cmd_gen(int argc, char **argv);
/* `trazador devices`: lists the Vulkan devices. */
int cmd_devices(int argc, char **argv);
/* `trazador formats`: lists the model formats assimp reads. */
int cmd_formats(int argc, char **argv);
/* `trazador info MODEL`: lists a model file's faces, cameras and lights. */
int cmd_info(int argc, char **argv);
/* `trazador bench`: fixed workloads timed on the back ends. */
int cmd_bench(int argc, char **argv);
/* `trazador view SCENE`: a window showing the render converge, its camera moved by the mouse. */
int cmd_view(int argc, char **argv);

#endif
