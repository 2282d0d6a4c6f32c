/* The contacts' solve's work on a point's rows (hair_contact_solve.c): its rows of J
 * turned into its pair's basis, and its rows of Z^T = (U^-1 J^T)^T solved for by back
 * substitution. Apart from the solve so that they are AVX twins (core/avx_twins.h):
 * their loops run four doubles a vector where the CPU has AVX, by the same operations
 * in the same order (the same bits). */
#ifndef HK_CONTACT_ROWS_H
#define HK_CONTACT_ROWS_H

#include <stddef.h>

#include "hairkit/vecmath.h"

/* Rows of a point's J (3 rows of stride `stride`, zero from column m on) turned into
 * the basis: row r becomes basis[r] . J, each sum in hk_v3_dot's order (the same bits
 * as it), the columns side by side. */
void hk_contact_rows_in_basis(double *jac, size_t stride, size_t m, const hk_Vec3 basis[3]);

/* Back substitution U z = j over the first m unknowns (U upper triangular, column i
 * at u + i dim; inverse[i] = 1 / U_ii) for up to three right-hand sides side by side
 * (rows: 3 for z0, z1, z2; 2 for z0, z1; 1 for z0), each solved by the same operations
 * in the same order whatever the others. */
void hk_contact_back_substitute(const double *u, const double *inverse, size_t dim, int m, double *z0, double *z1,
                                double *z2, int rows);

#endif /* HK_CONTACT_ROWS_H */
