/* Counter-based random numbers (see rng.h): splitmix64's finaliser applied to a
 * combination of the key's words, which passes BigCrush as a counter-mode generator. */
#include "hairkit/rng.h"

static uint64_t mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

uint64_t hk_rng_bits(uint64_t seed, uint64_t a, uint64_t b)
{
    /* Chain the words through the mixer so that (a, b) and (b, a) differ. */
    uint64_t h = mix(seed + 0x9E3779B97F4A7C15ULL);
    h = mix(h ^ (a + 0x632BE59BD9B4E019ULL));
    return mix(h ^ (b + 0x85157AF5ULL * 0x9E3779B97F4A7C15ULL));
}

double hk_rng_uniform(uint64_t seed, uint64_t a, uint64_t b)
{
    return (double)(hk_rng_bits(seed, a, b) >> 11) * (1.0 / 9007199254740992.0);
}
