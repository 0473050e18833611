/* big_memory.c: malloc, calloc and realloc, then madvise(MADV_HUGEPAGE) on the whole 2 MB pages
 * inside a big block. glibc gives such blocks a mapping of their own (or the heap's top), and
 * the advice holds for the pages not yet touched, so a later first touch faults a huge page
 * where the kernel's transparent huge pages are "madvise" (Debian's default) or "always"; where
 * they are off the advice is refused and nothing changes. */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include "util/big_memory.h"

#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>

#define HUGE_PAGE ((uintptr_t)2 << 20)
/* madvise's ranges start at a page (a larger page is a run of these). */
#define PAGE ((uintptr_t)4096)
/* Below two huge pages a block holds at most one whole one: not worth a system call. */
#define BIG_BYTES (2 * HUGE_PAGE)

/* Advises the whole huge pages within [p, p + bytes); returns p. */
static void *advise(void *p, size_t bytes) {
#ifdef MADV_HUGEPAGE
    if (p && bytes >= BIG_BYTES) {
        uintptr_t begin = ((uintptr_t)p + HUGE_PAGE - 1) & ~(HUGE_PAGE - 1);
        uintptr_t end = ((uintptr_t)p + bytes) & ~(HUGE_PAGE - 1);
        if (end > begin) madvise((void *)begin, end - begin, MADV_HUGEPAGE); /* advice only */
    }
#endif
    return p;
}

void big_memory_advise(void *p, size_t bytes) {
    advise(p, bytes);
#ifdef MADV_POPULATE_WRITE /* Linux 5.14 */
    if (p && bytes >= BIG_BYTES) {
        uintptr_t begin = (uintptr_t)p & ~(uintptr_t)(PAGE - 1);
        madvise((void *)begin, (uintptr_t)p + bytes - begin, MADV_POPULATE_WRITE); /* advice */
    }
#endif
}

void *big_malloc(size_t bytes) { return advise(malloc(bytes), bytes); }

void *big_calloc(size_t count, size_t size) {
    return advise(calloc(count, size), count && size <= SIZE_MAX / count ? count * size : 0);
}

void *big_realloc(void *p, size_t bytes) { return advise(realloc(p, bytes), bytes); }
