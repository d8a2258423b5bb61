/* One allocation per workspace (see block.h). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "util/block.h"

static size_t round_up(size_t x)
{
  return (x + RR_BLOCK_ALIGN - 1) / RR_BLOCK_ALIGN * RR_BLOCK_ALIGN;
}

void *rr_block_take(rr_block *b, size_t n, size_t elem_bytes)
{
  size_t start = round_up(b->used);
  size_t bytes = elem_bytes && n > SIZE_MAX / elem_bytes ? SIZE_MAX : n * elem_bytes;
  b->used = bytes > SIZE_MAX - start ? SIZE_MAX : start + bytes; /* saturates: alloc refuses */
  return b->base ? b->base + start : NULL;
}

int rr_block_alloc(rr_block *b)
{
  if (b->used >= SIZE_MAX - RR_BLOCK_ALIGN) return -1;
  size_t bytes = b->used ? round_up(b->used) : RR_BLOCK_ALIGN;
  b->base = aligned_alloc(RR_BLOCK_ALIGN, bytes);
  if (!b->base) return -1;
  memset(b->base, 0, bytes);
  b->used = 0;
  return 0;
}
