/* big_memory.c: malloc, calloc and realloc, then madvise(MADV_HUGEPAGE) on the whole 2 MB pages
 * inside a big block. glibc gives such blocks a mapping of their own (or the heap's top), and
 * the advice holds for the pages not yet touched, so a later first touch faults a huge page
 * where the kernel's transparent huge pages are "madvise" (Debian's default) or "always"; where
 * they are off the advice is refused and nothing changes. */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include "util/big_memory.h"

#include <limits.h>
#include <malloc.h>
#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#define HUGE_PAGE ((uintptr_t)2 << 20)
/* madvise's ranges start at a page (a larger page is a run of these). */
#define PAGE ((uintptr_t)4096)
/* Below two huge pages a block holds at most one whole one: not worth a system call. */
#define BIG_BYTES (2 * HUGE_PAGE)
/* big_memory_reserve_heap's blocks (malloc serves them from the heap up to twice this) and its
 * most. */
#define RESERVE_BLOCK ((size_t)16 << 20)
#define RESERVE_MAX ((size_t)1 << 30)

/* AddressSanitizer's allocator would poison a whole reserve: none there. */
#if defined(__SANITIZE_ADDRESS__)
#define RESERVE_HEAP 0
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define RESERVE_HEAP 0
#endif
#endif
#ifndef RESERVE_HEAP
#define RESERVE_HEAP 1
#endif

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

size_t big_alignment(size_t bytes, size_t align) {
    return bytes >= BIG_BYTES && align < HUGE_PAGE ? (size_t)HUGE_PAGE : align;
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

void big_memory_reserve_heap(size_t bytes) {
    if (!RESERVE_HEAP) return;
    if (bytes > RESERVE_MAX) bytes = RESERVE_MAX;
    long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0 && bytes > (size_t)pages / 4 * (size_t)page)
        bytes = (size_t)pages / 4 * (size_t)page;
    /* Under a limit on address space or data (ulimit -v, -d) the reserve takes a quarter of it
     * at most, so that it never leaves the process short of what it would have had. */
    const int limits[] = {RLIMIT_AS, RLIMIT_DATA};
    for (size_t k = 0; k < sizeof limits / sizeof limits[0]; k++) {
        struct rlimit l;
        if (getrlimit(limits[k], &l) == 0 && l.rlim_cur != RLIM_INFINITY && bytes > l.rlim_cur / 4)
            bytes = (size_t)(l.rlim_cur / 4);
    }
    mallopt(M_TRIM_THRESHOLD, INT_MAX); /* the reserve stays in the heap once freed */
    mallopt(M_MMAP_THRESHOLD, (int)RESERVE_BLOCK * 2); /* blocks to 32 MB come from the heap */
    enum { BLOCKS = RESERVE_MAX / RESERVE_BLOCK };
    void *block[BLOCKS];
    size_t n = 0;
    uintptr_t low = UINTPTR_MAX, high = 0;
    for (; n < bytes / RESERVE_BLOCK && (block[n] = malloc(RESERVE_BLOCK - 64)); n++) {
        uintptr_t at = (uintptr_t)block[n];
        if (at < low) low = at;
        if (at + RESERVE_BLOCK > high) high = at + RESERVE_BLOCK;
    }
    if (n > 0) advise((void *)low, high - low);
    while (n > 0) free(block[--n]);
}
