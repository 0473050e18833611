/* run_time_lib.h: a shared library opened at run time (dlopen) and its functions looked up by
 * name, so that trazador starts where an optional library (assimp, SDL2) is missing. */
#ifndef TRAZADOR_UTIL_RUN_TIME_LIB_H
#define TRAZADOR_UTIL_RUN_TIME_LIB_H

#include <stdbool.h>
#include <stddef.h>

/* A function to look up: its name and where its address goes (a function pointer's address). */
typedef struct run_time_symbol {
    const char *name;
    void *slot;
} run_time_symbol;

/* Opens soname and fills the slots of symbols[0..count); false with why set ("cannot open WHAT:
 * dlerror's words", or that the library lacks a function) when it cannot. */
bool run_time_lib_open(const char *soname, const char *what, const run_time_symbol *symbols,
                       int count, char *why, size_t why_size);

#endif
