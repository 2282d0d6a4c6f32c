/* How a strand's linearly implicit step answers point impulses: the Jacobians of
 * points along the strand and solves with the step's matrix, for the solve of the
 * guide-guide contacts coupled over all guides (hair_contact_solve.c).
 *
 * A point at arc length s of element p moves with the generalized velocities as
 *     x' = (root motion) + sum over P < p, b of (w_Pb x x + t_Pb) q'_Pb + J_p q'_p,
 * where (w_Pb; t_Pb) is the screw that coordinate b of element P gives everything
 * beyond the element's end (strand_kinematics.c, hk_element_terms_set_screw) and J_p
 * the point's own element's Jacobian (hk_point_kinematics): the rows of d x / d q'. */
#include <math.h>
#include <string.h>

#include "core/avx_twins.h"
#include "core/linalg.h"
#include "dynamics_internal.h"

static hk_Vec3 k_at(const double *q, int p) { return hk_v3(q[3 * p], q[3 * p + 1], q[3 * p + 2]); }

/* A point's rows of d x / d q' over the columns c < count of the elements before its
 * own: column c is w_c x x + t_c (hk_v3_cross's products, the same bits), with the
 * screws' components in rows of their own (6 rows of dim) so that the loop vectorises. */
static inline __attribute__((always_inline)) void screw_rows(const double *screws, int dim, int count, hk_Vec3 x,
                                                             double *const row[3])
{
    const double *restrict wx = screws, *restrict wy = wx + dim, *restrict wz = wy + dim;
    const double *restrict tx = wz + dim, *restrict ty = tx + dim, *restrict tz = ty + dim;
    double *restrict r0 = row[0], *restrict r1 = row[1], *restrict r2 = row[2];
    const double px = x.x, py = x.y, pz = x.z;
#pragma omp simd
    for (int c = 0; c < count; c++) {
        r0[c] = (wy[c] * pz - wz[c] * py) + tx[c];
        r1[c] = (wz[c] * px - wx[c] * pz) + ty[c];
        r2[c] = (wx[c] * py - wy[c] * px) + tz[c];
    }
}

/* Four columns a vector on AVX, two in the baseline: the same bits (core/linalg.h,
 * hk_avx_path). */
__attribute__((target("avx"))) static void screw_rows_avx(const double *screws, int dim, int count, hk_Vec3 x,
                                                          double *const row[3])
{
    screw_rows(screws, dim, count, x, row);
}

static void screw_rows_sse2(const double *screws, int dim, int count, hk_Vec3 x, double *const row[3])
{
    screw_rows(screws, dim, count, x, row);
}

void hk_dynamics_point_jacobians(hk_StrandDynamics *d, const hk_RigidState *head, const double *rates, const double *s,
                                 int count, double *screws, double *jac, int packed, hk_Vec3 *pos, hk_Vec3 *vel,
                                 int *element)
{
    HK_AVX_TWIN_CALL(hk_dynamics_point_jacobians, d, head, rates, s, count, screws, jac, packed, pos, vel, element);
    const hk_RigidState still = hk_rigid_identity();
    if (!head) head = &still;
    hk_SuperHelix *sh = d->sh;
    const int n = sh->n, dim = 3 * n;
    hk_strand_dynamics_place(d, head);
    hk_FrameKinematics node = hk_dynamics_root_kinematics(d, head);
    /* The elements' ends as the step's sweep found them at this state (the contacts'
     * solve takes the points right after the free step, hair_contact_solve.c): their
     * closed forms are not evaluated again. */
    const hk_EndPose *ends = hk_dynamics_end_poses(d);
    int p = 0, ahead = 0; /* ahead: point i was computed with point i - 1 */
    hk_Vec3 pair_pos[2], pair_vel[2];
    hk_Mat3 pair_jac[2];
    for (int i = 0; i < count; i++) {
        while (p < n - 1 && s[i] >= sh->s_start[p + 1]) {
            hk_PointKinematics end;
            if (ends)
                hk_end_kinematics(&node, &ends[p], k_at(rates, p), &end);
            else
                hk_point_kinematics(&node, k_at(sh->q, p), k_at(rates, p), sh->length[p], 1, &end);
#pragma GCC unroll 3
            for (int b = 0; b < 3; b++) { /* as hk_element_terms_set_screw */
                const hk_Vec3 w = hk_m3_col(&end.jac_rot, b);
                const hk_Vec3 t = hk_v3_add(hk_m3_col(&end.jac, b), hk_v3_cross(end.k.pos, w));
                const double z[6] = {w.x, w.y, w.z, t.x, t.y, t.z};
#pragma GCC unroll 6
                for (int r = 0; r < 6; r++) screws[(size_t)r * (size_t)dim + (size_t)(3 * p + b)] = z[r];
            }
            node = end.k;
            p++;
        }
        hk_Vec3 x, xv;
        hk_Mat3 own; /* the point's own element's Jacobian */
        if (ahead) {
            x = pair_pos[1], xv = pair_vel[1], own = pair_jac[1];
            ahead = 0;
        } else {
            /* with the next point when it lies in the same element: two at a time */
            const int pair = i + 1 < count && !(p < n - 1 && s[i + 1] >= sh->s_start[p + 1]);
            double u[2];
            for (int j = 0; j <= pair; j++) {
                u[j] = s[i + j] - sh->s_start[p];
                if (!(u[j] >= 0.0)) u[j] = 0.0;
                if (u[j] > sh->length[p]) u[j] = sh->length[p];
            }
            if (pair) {
                hk_point_jacobian2(&node, k_at(sh->q, p), k_at(rates, p), u, pair_pos, pair_vel, pair_jac);
                x = pair_pos[0], xv = pair_vel[0], own = pair_jac[0];
                ahead = 1;
            } else {
                hk_point_jacobian(&node, k_at(sh->q, p), k_at(rates, p), u[0], &x, &xv, &own);
            }
        }
        if (pos) pos[i] = x;
        if (vel) vel[i] = xv;
        if (element) element[i] = p;
        const int beyond = 3 * p + 3; /* the columns beyond the point's element are zero */
        const size_t stride = (size_t)(packed ? beyond : dim);
        double *row[3] = {jac, jac + stride, jac + 2 * stride};
        jac += 3 * stride;
        if (!packed)
            for (int r = 0; r < 3; r++) memset(row[r] + beyond, 0, (size_t)(dim - beyond) * sizeof(double));
        if (hk_avx_path())
            screw_rows_avx(screws, dim, 3 * p, x, row);
        else
            screw_rows_sse2(screws, dim, 3 * p, x, row);
#pragma GCC unroll 3
        for (int b = 0; b < 3; b++) {
            const hk_Vec3 col = hk_m3_col(&own, b);
            row[0][3 * p + b] = col.x, row[1][3 * p + b] = col.y, row[2][3 * p + b] = col.z;
        }
    }
}

/* The factor U (A = U U^T) the last dense solve left after its assembled matrix
 * (hk_terms_solve_dense), or NULL when the matrix is the O(N) solver's. */
static const double *dense_factor(const hk_StrandDynamics *d)
{
    const size_t sd = (size_t)(3 * d->sh->n);
    if (d->dense_fallback) return d->dense_work + sd * sd;
    return d->params.solver == HK_DYNAMICS_DENSE ? d->work + sd * sd : NULL;
}

const double *hk_dynamics_reversed_factor(const hk_StrandDynamics *d)
{
    if (d->dense_fallback || d->params.solver != HK_DYNAMICS_DENSE) return NULL;
    return dense_factor(d); /* U, U^T below it, then 1 / U_ii (hk_upper_cholesky) */
}

int hk_dynamics_resolve(hk_StrandDynamics *d, const double *rhs, double *out)
{
    const int n = d->sh->n, dim = 3 * n;
    if (out != rhs) memcpy(out, rhs, (size_t)dim * sizeof(double));
    const double *factor = dense_factor(d);
    if (factor) {
        hk_upper_solve(dim, factor, out);
        return 1;
    }
    return hk_terms_solve_linear(n, d->terms, d->extra, out, out, d->work);
}

int hk_dynamics_resolve_rows(hk_StrandDynamics *d, const double *rhs, int count, double *out)
{
    const size_t sd = (size_t)(3 * d->sh->n);
    for (int r = 0; r < count; r++)
        if (!hk_dynamics_resolve(d, rhs + (size_t)r * sd, out + (size_t)r * sd)) return 0;
    return 1;
}
