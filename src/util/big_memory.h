/* big_memory.h: arrays of megabytes (a million faces' triangles, a BVH's nodes, the packed
 * scene), allocated with malloc and freed with free, whose pages the kernel is asked to back
 * with transparent huge pages: their first touch then faults 2 MB at a time instead of 4 KB,
 * which a virtual machine charges microseconds each (docs/PERF.md, "Huge pages"). */
#ifndef TRAZADOR_BIG_MEMORY_H
#define TRAZADOR_BIG_MEMORY_H

#include <stddef.h>

/* malloc(bytes), advised as huge pages when it is big; NULL when out of memory. */
void *big_malloc(size_t bytes);

/* calloc(count, size), advised as huge pages when it is big; NULL when out of memory. */
void *big_calloc(size_t count, size_t size);

/* realloc(p, bytes), advised as huge pages when it is big; NULL (p kept) when out of memory. */
void *big_realloc(void *p, size_t bytes);

/* Advises the whole huge pages within [p, p + bytes) (memory mapped from elsewhere: a Vulkan
 * driver's host memory); the kernel may refuse, nothing else happens then. */
void big_memory_advise(void *p, size_t bytes);

#endif
