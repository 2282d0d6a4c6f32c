/* The AVX twins of the guides' evaluation and of the contacts' detection (issue 12). The
 * files listed in HK_AVX_TWIN_SOURCES (CMakeLists.txt) are compiled a second time with
 * -mavx, and every external symbol that compilation defines is renamed NAME_avx, its
 * calls among those files with it (cmake/avx_twins.cmake): a second copy of the
 * kinematics, the energy, the collisions, the broad phase... whose code GCC writes with
 * VEX's three-operand instructions, four doubles a vector where it vectorises. Each
 * element's operations are the same and in the same order (no FMA: -mavx only), so the
 * twins give the same bits as the baseline (core/linalg.h, hk_avx_path).
 *
 * The entry points the programs call (a guide's free step, its contact points, its
 * commit, its samples, a strand's step, the contacts' update) start with
 * HK_AVX_TWIN_RETURN or HK_AVX_TWIN_CALL: on the AVX path (hk_avx_path(), the switch of
 * every AVX path, which the tests toggle) they hand the call to their twin. Inside the
 * twin (HK_COMPILING_AVX_TWIN) and in builds without the twins (HK_AVX_TWINS off: the
 * sanitizers', the fuzzers', other compilers') they are nothing. */
#ifndef HK_CORE_AVX_TWINS_H
#define HK_CORE_AVX_TWINS_H

#include "core/linalg.h"

#if defined(HK_HAS_AVX_TWINS) && !defined(HK_COMPILING_AVX_TWIN)
/* In a function `name`: returns name_avx(...) on the AVX path. */
#define HK_AVX_TWIN_RETURN(name, ...)                                                                                  \
    do {                                                                                                               \
        __typeof__(name) name##_avx;                                                                                   \
        if (hk_avx_path()) return name##_avx(__VA_ARGS__);                                                             \
    } while (0)
/* The same in a function returning void. */
#define HK_AVX_TWIN_CALL(name, ...)                                                                                    \
    do {                                                                                                               \
        __typeof__(name) name##_avx;                                                                                   \
        if (hk_avx_path()) {                                                                                           \
            name##_avx(__VA_ARGS__);                                                                                   \
            return;                                                                                                    \
        }                                                                                                              \
    } while (0)
#else
#define HK_AVX_TWIN_RETURN(name, ...) ((void)0)
#define HK_AVX_TWIN_CALL(name, ...)   ((void)0)
#endif

#endif /* HK_CORE_AVX_TWINS_H */
