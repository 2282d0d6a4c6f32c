/* Inverse statics: the natural shape that makes a given shape a rest shape (hairkit/capture.h;
 * docs/capture.md, "Inverse statics").
 *
 * The statics energy of a Super-Helix (Lansink 2010 §4.1.1.3, hk_strand_energy) is
 *     E(q) = sum_Q l_Q sum_i K_i / 2 (q_iQ - q_rest_iQ)^2 + E_ext(q),
 * E_ext the gravity and the shapes' penalties, which do not depend on q_rest. Its
 * gradient vanishes at q when
 *     q_rest_iQ = q_iQ + (dE_ext/dq_iQ) / (l_Q K_i),
 * one division per coordinate: the elastic force is diagonal in the Super-Helix's
 * coordinates, which is what makes the inverse problem of Derouet-Jourdan et al. 2013
 * (§4) direct for Super-Helices. dE_ext/dq is hk_strand_energy's gradient with q_rest = q
 * (the elastic part then vanishes). The equilibrium is stable when the Hessian of E at q
 * is positive definite: elastic (diagonal, l_Q K_i) plus that of E_ext, both exact in
 * hk_strand_energy; Cholesky tells. */
#include <math.h>
#include <string.h>

#include "core/linalg.h"
#include "hairkit/capture.h"

hk_InverseStaticsDef hk_default_inverse_statics_def(void)
{
    hk_InverseStaticsDef d;
    d.settle_unstable = 1;
    d.statics = hk_default_statics_def();
    return d;
}

/* Largest distance between the nodes of two shapes of the strand. */
static double node_distance(const hk_SuperHelix *sh, const double *qa, const double *qb, hk_Vec3 *work)
{
    const int n = sh->n;
    hk_superhelix_nodes(sh, qa, work, NULL);
    hk_superhelix_nodes(sh, qb, work + n + 1, NULL);
    double d = 0.0;
    for (int i = 0; i <= n; i++) d = fmax(d, hk_v3_norm(hk_v3_sub(work[i], work[n + 1 + i])));
    return d;
}

/* At an unstable equilibrium the gradient vanishes and a descent method would not move:
 * step along the eigenvector of the Hessian's lowest eigenvalue (negative there), far
 * enough to move the tip by about a millimetre (a curvature change dk bends a strand
 * of length L by about dk L^2 / 2), to the side where the energy is lower. hess and
 * work are 3N x 3N and 3N doubles of scratch (hess is overwritten). */
static hk_Status leave_saddle(hk_SuperHelix *sh, const hk_StrandEnvDef *env, hk_StrandWorkspace *ws, double *hess,
                              double *work, hk_Error *err)
{
    const int dim = 3 * sh->n;
    const size_t size = (size_t)dim * (size_t)dim;
    double *vectors = hk_alloc_array(size + 2 * (size_t)dim, sizeof(double), err);
    if (!vectors) return err ? err->code : HK_ERR_NOMEM;
    double *values = vectors + size, *scratch = values + dim;
    hk_strand_energy(sh, env, sh->q, ws, work, hess, NULL);
    hk_Status st = HK_OK;
    if (!hk_symmetric_eigen(dim, hess, values, vectors, scratch)) {
        st = hk_error_set(err, HK_ERR_NUMERIC, "inverse statics: the Hessian's eigenvalues did not converge");
    } else {
        int low = 0;
        for (int i = 1; i < dim; i++)
            if (values[i] < values[low]) low = i;
        const double step = 2e-3 / (sh->total_length * sh->total_length);
        double best = 0.0;
        int sign = 0;
        for (int side = 1; side >= -1; side -= 2) {
            for (int i = 0; i < dim; i++)
                work[i] = sh->q[i] + side * step * vectors[(size_t)i * (size_t)dim + (size_t)low];
            const double e = hk_strand_energy(sh, env, work, ws, NULL, NULL, NULL);
            if (!sign || e < best) best = e, sign = side;
        }
        for (int i = 0; i < dim; i++) sh->q[i] += sign * step * vectors[(size_t)i * (size_t)dim + (size_t)low];
    }
    hk_free(vectors);
    return st;
}

hk_Status hk_statics_invert(hk_SuperHelix *sh, const hk_StrandEnvDef *env, const hk_InverseStaticsDef *def,
                            hk_InverseStaticsReport *report, hk_Error *err)
{
    const hk_InverseStaticsDef d = def ? *def : hk_default_inverse_statics_def();
    const int n = sh->n;
    const size_t dim = 3 * (size_t)n;
    for (int i = 0; i < 3; i++)
        if (!(sh->material.stiffness[i] > 0.0))
            return hk_error_set(err, HK_ERR_INVALID, "inverse statics: stiffness %d of the strand is %g, must be > 0",
                                i, sh->material.stiffness[i]);
    hk_StrandWorkspace *ws = NULL;
    hk_Status st = hk_strand_workspace_create(sh, env, &ws, err);
    if (st != HK_OK) return st;
    /* grad, hess, the shape given, then nodes for the drift */
    double *grad = hk_alloc_array(dim * dim + 3 * dim, sizeof(double), err);
    hk_Vec3 *nodes = hk_alloc_array(2 * (size_t)n + 2, sizeof(hk_Vec3), err);
    if (!grad || !nodes) {
        hk_free(grad);
        hk_free(nodes);
        hk_strand_workspace_destroy(ws);
        return err ? err->code : HK_ERR_NOMEM;
    }
    double *hess = grad + dim, *given = hess + dim * dim, *check = given + dim;

    /* The external generalized forces at q: the gradient with no elastic part. */
    memcpy(sh->q_rest, sh->q, dim * sizeof(double));
    hk_strand_energy(sh, env, sh->q, ws, grad, NULL, NULL);
    double largest = 0.0, change = 0.0;
    for (int e = 0; e < n; e++)
        for (int i = 0; i < 3; i++) {
            const size_t c = 3 * (size_t)e + (size_t)i;
            largest = fmax(largest, fabs(grad[c]));
            sh->q_rest[c] = sh->q[c] + grad[c] / (sh->length[e] * sh->material.stiffness[i]);
            change = fmax(change, fabs(sh->q_rest[c] - sh->q[c]));
        }

    /* What is left of the gradient (rounding only), and the Hessian for the stability. */
    hk_strand_energy(sh, env, sh->q, ws, check, hess, NULL);
    double left = 0.0;
    for (size_t c = 0; c < dim; c++) left = fmax(left, fabs(check[c]));
    const int stable = hk_cholesky_factor((int)dim, hess, 0.0, NULL, hess);

    hk_InverseStaticsReport r = {0};
    r.stable = stable;
    r.rest_change = change;
    r.residual = largest > 0.0 ? left / largest : left;
    if (!stable && d.settle_unstable) {
        memcpy(given, sh->q, dim * sizeof(double));
        st = leave_saddle(sh, env, ws, hess, check, err);
        hk_MinimizeResult result;
        if (st == HK_OK) st = hk_statics_solve(sh, env, &d.statics, &result, err);
        if (st == HK_OK) {
            r.settled = 1;
            r.drift = node_distance(sh, given, sh->q, nodes);
        } else {
            memcpy(sh->q, given, dim * sizeof(double));
        }
    }
    if (report) *report = r;
    hk_free(grad);
    hk_free(nodes);
    hk_strand_workspace_destroy(ws);
    return st;
}
