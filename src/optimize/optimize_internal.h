/* Internal to hairkit (not installed, not exported): parts of the minimisers the tests
 * check on their own. Included as "optimize/optimize_internal.h". */
#ifndef HK_OPTIMIZE_INTERNAL_H
#define HK_OPTIMIZE_INTERNAL_H

#include "hairkit/statics.h"

/* Palmer's orthonormalisation step on its own, for tests: given the n orthonormal directions xi (row-major
 * n x n, row i = direction i) and the stage advances d[0..n), writes the new orthonormal
 * directions into xi_new. */
void hk_rosenbrock_palmer_directions(int n, const double *xi, const double *d, double *xi_new);

#endif /* HK_OPTIMIZE_INTERNAL_H */
