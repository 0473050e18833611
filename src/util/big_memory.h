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

/* The alignment for an aligned block of `bytes` that must be aligned to `align` (a power of
 * two): a huge page where the block is big, so that it starts on one; `align` otherwise. */
size_t big_alignment(size_t bytes, size_t align);

/* Memory mapped from elsewhere (a Vulkan driver's host memory) that is about to be written
 * whole: its whole huge pages advised, and every page of it mapped at once (MADV_POPULATE_WRITE)
 * instead of a fault at each first touch; the kernel may refuse either, nothing else happens. */
void big_memory_advise(void *p, size_t bytes);

/* For a process about to make many small allocations (assimp's child, a Vulkan driver opening a
 * device and compiling a pipeline): its heap grown by up to `bytes` (at most 1 GB, a quarter of
 * the memory and a quarter of an address-space or data limit) in blocks, advised as huge pages,
 * freed and never trimmed, so that its allocations fault 2 MB pages; only the blocks' headers are
 * touched, and nothing happens under AddressSanitizer. */
void big_memory_reserve_heap(size_t bytes);

#endif
