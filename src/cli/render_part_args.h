/* render_part_args.h: the part `trazador render` makes: --region and --samples parsed into its
 * metadata, the checkpoint it resumes from checked against it, the checkpoint of a finished
 * render kept or removed. */
#ifndef TRAZADOR_RENDER_PART_ARGS_H
#define TRAZADOR_RENDER_PART_ARGS_H

#include <stdbool.h>
#include <stdint.h>

#include "render/part.h"

/* Parses --region X0,X1,Y0,Y1 into m's region; false (said) if it is not one inside the image. */
bool render_parse_region(const char *text, part_meta *m);
/* Parses --samples A:B into m's sample_begin and *end; false (said) if it is not a range of
 * whole chunks within the samples per pixel. */
bool render_parse_samples(const char *text, part_meta *m, uint32_t *end);
/* Reads the checkpoint to resume into p; false (said) unless it is a part of this very render
 * (scene, settings, region and first sample) that ends at or before `end`, of the back end
 * asked for. */
bool render_load_resume(const char *path, const part_meta *want, uint32_t end, int backend,
                        part *p);
/* The checkpoint of a render whose output holds all it had: with keep, written once more with the
 * finished part p (so that it exists even when the render ended before its first periodic one),
 * false (said) when it cannot be; else removed, a failure only warned, as the output is written. */
bool render_finish_checkpoint(const char *path, bool keep, const part *p);

#endif
