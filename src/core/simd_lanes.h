/* Doubles side by side in vector registers (GCC's vector extension), for the
 * kernels of src/core/positive_part.c, the tridiagonal eigenvalues it calls
 * (tridiagonal_eigenvalues.h), src/dynamics/strand_solve.c and the contacts' rows'
 * sums (src/dynamics/hair_contact_solve.c). Internal: included by those files only. */
#ifndef HK_CORE_SIMD_LANES_H
#define HK_CORE_SIMD_LANES_H

#include <string.h>

/* Two doubles in one SSE2 register (GCC's vector extension, as in
 * src/helicoid/piece_rk4_tangent.c): the kernels below pair a row's elements by hand,
 * which -O2 does not do by itself for loops of unknown length and alignment (and
 * hk_dot's out-of-line call per row cost as much as the row's arithmetic). Loads and
 * stores through memcpy: unaligned, as the rows of a triangle start anywhere. */
typedef double Pair __attribute__((vector_size(16)));
typedef long long Bits __attribute__((vector_size(16))); /* a Pair's bits, for masks */

static inline Pair load_pair(const double *p)
{
    Pair r;
    memcpy(&r, p, sizeof r);
    return r;
}

static inline void store_pair(double *p, Pair v) { memcpy(p, &v, sizeof v); }

static inline Pair splat(double a) { return (Pair){a, a}; }

/* Four doubles (GCC's vector extension again): one AVX register where the caller is
 * compiled for AVX (hk_symmetric_positive_part's AVX path, below), two SSE2 registers
 * otherwise, the same operations element by element either way (no FMA: a product and
 * a sum round as two), so that both paths give the same bits. No Quad crosses a call:
 * the helpers are always inlined (hence -Wpsabi's note on the ABI is moot and
 * silenced), and those that take one are macros (GCC notes a Quad parameter whatever
 * the pragma says). */
#if defined(__clang__)
#if __has_warning("-Wpsabi")
#pragma clang diagnostic ignored "-Wpsabi"
#endif
#elif defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif
typedef double Quad __attribute__((vector_size(32)));

static inline __attribute__((always_inline)) Quad load_quad(const double *p)
{
    Quad r;
    memcpy(&r, p, sizeof r);
    return r;
}

static inline __attribute__((always_inline)) Quad splat4(double a) { return (Quad){a, a, a, a}; }

#define STORE_QUAD(p, v)                                                                                               \
    do {                                                                                                               \
        const Quad stored_ = (v);                                                                                      \
        memcpy((p), &stored_, sizeof stored_);                                                                         \
    } while (0)

/* The Quad variable q's first and last two elements. */
#define LOW_PAIR(q)  __builtin_shufflevector((q), (q), 0, 1)
#define HIGH_PAIR(q) __builtin_shufflevector((q), (q), 2, 3)

/* x[i] -= c */
static inline __attribute__((always_inline)) void sub_constant(double *x, double c, int n, int wide)
{
    int i = 0;
    if (wide)
        for (const Quad cq = splat4(c); i + 4 <= n; i += 4) STORE_QUAD(x + i, load_quad(x + i) - cq);
    for (const Pair cp = splat(c); i + 2 <= n; i += 2) store_pair(x + i, load_pair(x + i) - cp);
    if (i < n) x[i] -= c;
}

/* y[i] += f x[i] for i < n: four (wide, the AVX path), two, one at a time by hand, each
 * entry's product and sum as the scalar's (positive_part.c; strand_solve.c's factor rows).
 * An `omp simd` loop's peeling and checks cost more than the arithmetic on rows of 3N = 30
 * and less. */
static inline __attribute__((always_inline)) void add_multiple(double *y, double f, const double *x, int n, int wide)
{
    int i = 0;
    if (wide)
        for (const Quad fq = splat4(f); i + 4 <= n; i += 4) STORE_QUAD(y + i, load_quad(y + i) + fq * load_quad(x + i));
    for (const Pair fp = splat(f); i + 2 <= n; i += 2) store_pair(y + i, load_pair(y + i) + fp * load_pair(x + i));
    if (i < n) y[i] += f * x[i];
}

/* y[i] = (y[i] + f x[i]) + g z[i] for i < n: add_multiple by f and x, then by g and z,
 * in one pass (each entry's operations and their order as the two calls': the same
 * bits), y loaded and stored once for both. */
static inline __attribute__((always_inline)) void add_multiple2(double *y, double f, const double *x, double g,
                                                                const double *z, int n, int wide)
{
    int i = 0;
    if (wide)
        for (const Quad fq = splat4(f), gq = splat4(g); i + 4 <= n; i += 4)
            STORE_QUAD(y + i, (load_quad(y + i) + fq * load_quad(x + i)) + gq * load_quad(z + i));
    for (const Pair fp = splat(f), gp = splat(g); i + 2 <= n; i += 2)
        store_pair(y + i, (load_pair(y + i) + fp * load_pair(x + i)) + gp * load_pair(z + i));
    if (i < n) y[i] = (y[i] + f * x[i]) + g * z[i];
}

#endif
