/* run_time_lib.c: dlopen and dlsym for the libraries trazador opens at run time. */
#include "util/run_time_lib.h"

#include <dlfcn.h>
#include <stdio.h>
#include <string.h>

bool run_time_lib_open(const char *soname, const char *what, const run_time_symbol *symbols,
                       int count, char *why, size_t why_size) {
    void *handle = dlopen(soname, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char *e = dlerror();
        snprintf(why, why_size, "cannot open %s: %s", what, e ? e : soname);
        return false;
    }
    for (int k = 0; k < count; k++) {
        void *f = dlsym(handle, symbols[k].name);
        if (!f) {
            snprintf(why, why_size, "%s has no %s", soname, symbols[k].name);
            return false;
        }
        /* a data pointer's bits as a function pointer's, as dlsym means */
        memcpy(symbols[k].slot, &f, sizeof f);
    }
    return true;
}
