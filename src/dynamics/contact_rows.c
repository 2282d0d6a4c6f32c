/* The contacts' solve's kernels on a point's rows (contact_rows.h): an AVX twin
 * (CMakeLists.txt, HK_AVX_TWIN_SOURCES), each entry point handing its call to its twin
 * on the AVX path. No loop here sums along a row (no `omp simd reduction`), so the
 * twin's four lanes do each element's operations as the baseline's two do: the same
 * bits. The head driver's 8 frames on examples/guides200 shaking (callgrind): see
 * docs/dynamics.md, "Speed", 7 December 2026, afternoon. */
#include "contact_rows.h"

#include "core/avx_twins.h"

/* (contact_rows.h) The columns side by side (vectorised). */
void hk_contact_rows_in_basis(double *jac, size_t stride, size_t m, const hk_Vec3 basis[3])
{
    HK_AVX_TWIN_CALL(hk_contact_rows_in_basis, jac, stride, m, basis);
    double *j1 = jac + stride, *j2 = jac + 2 * stride;
    const double n0 = basis[0].x, n1 = basis[0].y, n2 = basis[0].z;
    const double s0 = basis[1].x, s1 = basis[1].y, s2 = basis[1].z;
    const double t0 = basis[2].x, t1 = basis[2].y, t2 = basis[2].z;
#pragma omp simd
    for (size_t k = 0; k < m; k++) {
        const double c0 = jac[k], c1 = j1[k], c2 = j2[k];
        jac[k] = n0 * c0 + n1 * c1 + n2 * c2;
        j1[k] = s0 * c0 + s1 * c1 + s2 * c2;
        j2[k] = t0 * c0 + t1 * c1 + t2 * c2;
    }
}

/* Unknowns i and j = i - 1 of one right-hand side z: *a = z_i, then z_j less column
 * i's share, *b = z_j (hk_contact_back_substitute). */
static inline void two_pivots(double *z, const double *ci, const double *inverse, int i, double *a, double *b)
{
    const int j = i - 1;
    *a = z[i] * inverse[i];
    z[i] = *a;
    z[j] -= ci[j] * *a;
    *b = z[j] * inverse[j];
    z[j] = *b;
}

/* Back substitution U z = j for up to three right-hand sides side by side (rows: 3
 * for z0, z1, z2; 2 for z0, z1; 1 for z0), each solved by the same operations in the
 * same order whatever the others: a row solved alone has the bits it has solved with
 * the others (reversed_rows). Columns i and i - 1 are taken in one pass over the
 * entries above them, z_k = (z_k - U_ki z_i) - U_k,i-1 z_i-1: the two subtractions one
 * column at a time makes, in their order (the same bits), with z loaded and stored
 * once for both and half the loops' overhead (callgrind, head driver on
 * examples/guides200 shaking, 8 frames: back_substitute 106.7 -> 78.8 million
 * instructions). */
void hk_contact_back_substitute(const double *u, const double *inverse, size_t dim, int m, double *z0, double *z1,
                                double *z2, int rows)
{
    HK_AVX_TWIN_CALL(hk_contact_back_substitute, u, inverse, dim, m, z0, z1, z2, rows);
    int i = m - 1;
    for (; i >= 1; i -= 2) {
        const int j = i - 1;
        const double *ci = u + (size_t)i * dim, *cj = u + (size_t)j * dim; /* ci[k] = U[k][i] for k < i */
        double a0, b0, a1, b1, a2, b2;
        two_pivots(z0, ci, inverse, i, &a0, &b0);
        if (rows == 1) {
#pragma omp simd
            for (int k = 0; k < j; k++) z0[k] = (z0[k] - ci[k] * a0) - cj[k] * b0;
            continue;
        }
        two_pivots(z1, ci, inverse, i, &a1, &b1);
        if (rows == 2) {
#pragma omp simd
            for (int k = 0; k < j; k++) {
                z0[k] = (z0[k] - ci[k] * a0) - cj[k] * b0;
                z1[k] = (z1[k] - ci[k] * a1) - cj[k] * b1;
            }
            continue;
        }
        two_pivots(z2, ci, inverse, i, &a2, &b2);
#pragma omp simd
        for (int k = 0; k < j; k++) {
            z0[k] = (z0[k] - ci[k] * a0) - cj[k] * b0;
            z1[k] = (z1[k] - ci[k] * a1) - cj[k] * b1;
            z2[k] = (z2[k] - ci[k] * a2) - cj[k] * b2;
        }
    }
    if (i == 0) { /* the first unknown, when m is odd */
        z0[0] *= inverse[0];
        if (rows > 1) z1[0] *= inverse[0];
        if (rows > 2) z2[0] *= inverse[0];
    }
}
