/* Seeded, reproducible random numbers: xoshiro256** seeded by splitmix64.
 * State lives in the caller's struct: no global state. */
#ifndef RR_RNG_H
#define RR_RNG_H
#include <stdint.h>

typedef struct rr_rng {
  uint64_t s[4];
} rr_rng;

static inline uint64_t rr_splitmix64(uint64_t *x)
{
  uint64_t z = (*x += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

static inline void rr_rng_seed(rr_rng *r, uint64_t seed)
{
  for (int i = 0; i < 4; i++) r->s[i] = rr_splitmix64(&seed);
}

static inline uint64_t rr_rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

static inline uint64_t rr_rng_next(rr_rng *r)
{
  uint64_t *s = r->s, res = rr_rotl(s[1] * 5, 7) * 9, t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rr_rotl(s[3], 45);
  return res;
}

/* Uniform on [0, 1). */
static inline double rr_rng_uniform(rr_rng *r)
{
  return (double)(rr_rng_next(r) >> 11) * 0x1.0p-53; /* 53 bits: exact */
}
#endif
