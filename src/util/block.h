/* A workspace's arrays carved from one allocation: a layout function hands
 * out every array through rr_block_take twice, once to size the block (base
 * NULL: the pointers are NULL) and once to carve it, so that an object has
 * one malloc, one check and one free, and its sizes are size_t throughout.
 *
 *   rr_block b = {0};
 *   layout(obj, &b);                      sizing pass
 *   if (rr_block_alloc(&b)) ... ENOMEM
 *   layout(obj, &b);                      the pointers
 *   ... free(b.base) when the object goes
 */
#ifndef RR_BLOCK_H
#define RR_BLOCK_H

#include <stddef.h>

#define RR_BLOCK_ALIGN 64 /* a cache line: SIMD loads never straddle one at an array's start */

typedef struct rr_block {
  char *base;  /* NULL while sizing */
  size_t used; /* bytes handed out so far (the size, after the sizing pass) */
} rr_block;

/* n elements of elem_bytes, aligned to RR_BLOCK_ALIGN; NULL while sizing. */
void *rr_block_take(rr_block *b, size_t n, size_t elem_bytes);
/* After the sizing pass: the block (zeroed), ready for the carving pass.
   Returns 0, or -1 when out of memory (or the size overflowed). */
int rr_block_alloc(rr_block *b);

#endif
