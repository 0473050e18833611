/* gen.h: procedural scene generators (`trazador gen`): Eric Haines' sphereflake (SPD "balls")
 * and the random spheres of "Ray Tracing in One Weekend", written as trazador scene files. */
#ifndef TRAZADOR_GEN_H
#define TRAZADOR_GEN_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#define GEN_MAX_DEPTH 7 /* sphereflake: 5,380,840 spheres */
/* random: small spheres. More would spread the field past 1000 units from the origin, where the
 * ray offset (1e-4 times the coordinates) reaches half their radius and glass turns black. */
#define GEN_MAX_COUNT 3999988

typedef enum gen_kind { GEN_SPHEREFLAKE = 0, GEN_RANDOM = 1 } gen_kind;

typedef struct gen_desc {
    gen_kind kind;
    int depth;     /* sphereflake: levels of children, 0..GEN_MAX_DEPTH */
    long count;    /* random: small spheres, 1..GEN_MAX_COUNT */
    uint32_t seed; /* same seed, same bytes; the command line's default is 1 */
} gen_desc;

/* Returns the number of spheres the scene holds, ground included; 0 for an invalid desc. */
long gen_sphere_count(const gen_desc *desc);
/* Writes the scene to fp; false on an invalid desc or a write error (logged). */
bool gen_write(const gen_desc *desc, FILE *fp);
/* Writes the scene to path via a temporary file in the same folder and a rename, or to stdout
   when path is NULL or "-"; false on error (logged), leaving no file and any old one intact. */
bool gen_write_file(const gen_desc *desc, const char *path);

#endif
