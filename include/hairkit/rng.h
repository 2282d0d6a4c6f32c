/* Counter-based random numbers: a value is a pure function of (seed, stream, index),
 * so results do not depend on the order in which threads draw them. */
#ifndef HAIRKIT_RNG_H
#define HAIRKIT_RNG_H

#include <stdint.h>

#include "hairkit/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 64 well-mixed bits for the key (seed, a, b) (splitmix64 finaliser over the key). */
HK_API uint64_t hk_rng_bits(uint64_t seed, uint64_t a, uint64_t b);

/* Uniform double in [0, 1) for the key (seed, a, b), 53 random bits. */
HK_API double hk_rng_uniform(uint64_t seed, uint64_t a, uint64_t b);

#ifdef __cplusplus
}
#endif

#endif
