/* Statics energy of a Super-Helix (Lansink 2010 §4.1.1.3 elastic and gravity, §4.1.2
 * collision penalty with envelopes) with its exact gradient and Hessian.
 *
 * Derivatives flow backwards along the strand. Changing the coordinates k_P of element
 * P moves everything beyond its end rigidly: a world rotation rate omega_b = R_P
 * Lambda_P e_b and a displacement t_b = R_P dd_P e_b of the node r_{P+1}, i.e. the
 * twist xi_b = (omega_b, v_b = t_b + r_{P+1} x omega_b) acting as dp = omega x p + v.
 * Its first-order effect on the energy beyond is xi_b . (M, F) with F the summed force
 * (energy gradient in p) and M its moment about the origin, accumulated from the tip.
 * Second derivatives add the second moment S0 = sum p f^T (rotations of lever arms),
 * the 6x6 contact stiffness C = sum B^T A B, and per element the second derivatives
 * of the element's closed form. Derivation: docs/physics.md.
 *
 * GCC 12's -O2 keeps most of the small loops here rolled (a counter, and tests such as
 * i == j made at run time); `#pragma GCC unroll` writes them out, the same operations
 * in the same order, so the same bits (docs/dynamics.md, "Speed", 6 December 2026,
 * night). */
#include "collide/collide_internal.h"
#include "hairkit/rod.h"

#include <string.h>

#include "core/linalg.h"
#include "helix_local.h"
#include "rod/rod_internal.h"

struct hk_StrandWorkspace {
    int n;                 /* elements of the strand this workspace was made for */
    double length;         /* its length */
    double collision_step; /* env->collision_step it was made for */
    int sample_count;
    double sample_weight;   /* arc length represented by one collision sample */
    int *elem_first_sample; /* n + 1 entries: samples of element P are [first[P], first[P+1]) */
    double *sample_u;       /* offset of each sample in its element */
    hk_Vec3 *pos;           /* node positions, n + 1 */
    hk_Mat3 *frame;         /* node frames, n + 1 */
    hk_ElementLocal *local; /* per element closed forms */
    /* per collision sample, valid where active[i] */
    unsigned char *active;
    /* the active samples in order (element P's from touch[first_touch[P]] to before
     * touch[first_touch[P + 1]]): the backward pass visits these alone */
    int *touch, *first_touch;
    hk_Vec3 *sp, *sf;     /* position, weighted gradient of the penalty density */
    hk_Mat3 *sa, *sd;     /* weighted Hessian of the density, world dp/dk of own element */
    hk_Vec3 (*sd2)[3][3]; /* d2p/dk2 of own element, in the element's start frame */
    hk_Vec3 *sfl;         /* sf in the element's start frame */
    double *xi;           /* Hessian: the screws xi_a, stored transposed (6 rows of 3N) */
    double *y;            /* Hessian: the 6-vectors Y_b, per coordinate */
    /* the walk (walk(): the node poses, the elements' closed forms and the positions sp of
     * the samples of the elements within reach of a shape, near[P]) for the coordinates
     * key_q, the root pose key_root, key_frame, the order key_order and the shapes of
     * key_env, kept by hk_strand_workspace_prepare for the next hk_strand_energy call
     * alone (prepared) */
    unsigned char *near;
    double *key_q;
    hk_Vec3 key_root;
    hk_Mat3 key_frame;
    int key_order, prepared;
    hk_StrandEnvDef key_env;
};

/* The default environment: no shapes, no collisions (what a NULL env means). */
static const hk_StrandEnvDef no_env = {NULL, 0, 0.0, 0.0};

hk_StrandEnvDef hk_default_strand_env_def(void) { return no_env; }

int hk_strand_collision_sample_count(const hk_SuperHelix *sh, const hk_StrandEnvDef *env)
{
    if (!env) env = &no_env;
    if (env->shape_count <= 0 || !(env->collision_step > 0.0)) return 0;
    double m = ceil(sh->total_length / env->collision_step - 1e-9);
    if (m < 1.0) m = 1.0;
    if (m > (double)HK_MAX_SAMPLES_PER_STRAND) m = (double)HK_MAX_SAMPLES_PER_STRAND;
    return (int)m;
}

hk_Status hk_strand_workspace_create(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, hk_StrandWorkspace **out,
                                     hk_Error *err)
{
    *out = NULL;
    if (!env) env = &no_env;
    hk_StrandWorkspace *ws = hk_calloc_array(1, sizeof *ws, err);
    if (!ws) return HK_ERR_NOMEM;
    const int n = sh->n, ns = hk_strand_collision_sample_count(sh, env);
    const size_t sn = (size_t)(ns > 0 ? ns : 1);
    ws->n = n;
    ws->length = sh->total_length;
    ws->collision_step = env->collision_step;
    ws->sample_count = ns;
    ws->sample_weight = ns > 0 ? sh->total_length / ns : 0.0;
    ws->elem_first_sample = hk_alloc_array((size_t)n + 1, sizeof(int), err);
    ws->sample_u = hk_alloc_array(sn, sizeof(double), err);
    ws->pos = hk_alloc_array((size_t)n + 1, sizeof(hk_Vec3), err);
    ws->frame = hk_alloc_array((size_t)n + 1, sizeof(hk_Mat3), err);
    ws->local = hk_alloc_array((size_t)n, sizeof(hk_ElementLocal), err);
    ws->active = hk_calloc_array(sn, 1, err); /* no contact before the first call */
    ws->touch = hk_alloc_array(sn, sizeof(int), err);
    ws->first_touch = hk_calloc_array((size_t)n + 1, sizeof(int), err);
    ws->sp = hk_alloc_array(sn, sizeof(hk_Vec3), err);
    ws->sf = hk_alloc_array(sn, sizeof(hk_Vec3), err);
    ws->sa = hk_alloc_array(sn, sizeof(hk_Mat3), err);
    ws->sd = hk_alloc_array(sn, sizeof(hk_Mat3), err);
    ws->sd2 = hk_alloc_array(sn, sizeof *ws->sd2, err);
    ws->sfl = hk_alloc_array(sn, sizeof(hk_Vec3), err);
    ws->xi = hk_alloc_array((size_t)n * 3 * 6, sizeof(double), err);
    ws->y = hk_alloc_array((size_t)n * 3 * 6, sizeof(double), err);
    ws->near = hk_calloc_array((size_t)n, 1, err);
    ws->key_q = hk_alloc_array((size_t)n * 3, sizeof(double), err);
    if (!ws->elem_first_sample || !ws->sample_u || !ws->pos || !ws->frame || !ws->local || !ws->active || !ws->touch ||
        !ws->first_touch || !ws->sp || !ws->sf || !ws->sa || !ws->sd || !ws->sd2 || !ws->sfl || !ws->xi || !ws->y ||
        !ws->near || !ws->key_q) {
        hk_strand_workspace_destroy(ws);
        return HK_ERR_NOMEM;
    }
    /* Midpoints of ns equal pieces: a midpoint-rule quadrature of the penalty line
     * integral that also covers the tip region (thesis §4.1.2 samples every Delta s). */
    int elem = 0;
    ws->elem_first_sample[0] = 0;
    for (int i = 0; i < ns; i++) {
        double s = (i + 0.5) * ws->sample_weight;
        while (elem < n - 1 && s >= sh->s_start[elem + 1]) ws->elem_first_sample[++elem] = i;
        ws->sample_u[i] = s - sh->s_start[elem];
    }
    while (elem < n) ws->elem_first_sample[++elem] = ns;
    *out = ws;
    return HK_OK;
}

void hk_strand_workspace_destroy(hk_StrandWorkspace *ws)
{
    if (!ws) return;
    hk_free(ws->elem_first_sample);
    hk_free(ws->sample_u);
    hk_free(ws->pos);
    hk_free(ws->frame);
    hk_free(ws->local);
    hk_free(ws->active);
    hk_free(ws->touch);
    hk_free(ws->first_touch);
    hk_free(ws->sp);
    hk_free(ws->sf);
    hk_free(ws->sa);
    hk_free(ws->sd);
    hk_free(ws->sd2);
    hk_free(ws->sfl);
    hk_free(ws->xi);
    hk_free(ws->y);
    hk_free(ws->near);
    hk_free(ws->key_q);
    hk_free(ws);
}

static hk_Vec3 k_of(const double *q, int p) { return hk_v3(q[3 * p], q[3 * p + 1], q[3 * p + 2]); }

/* Forward reconstruction of node poses and element closed forms. */
static void forward(const hk_SuperHelix *sh, const double *q, int order, hk_StrandWorkspace *ws)
{
    ws->frame[0] = sh->root_frame;
    ws->pos[0] = sh->root;
    for (int p = 0; p < sh->n; p++) {
        if (order == 2 && p + 1 < sh->n) { /* two elements at a time, the same bits */
            const hk_Vec3 k[2] = {k_of(q, p), k_of(q, p + 1)};
            hk_element_local_order2(k, &sh->length[p], &ws->local[p]);
            p++;
        } else {
            hk_element_local(k_of(q, p), sh->length[p], order, 1, &ws->local[p]);
        }
    }
    for (int p = 0; p < sh->n; p++) {
        const hk_ElementLocal *el = &ws->local[p];
        ws->pos[p + 1] = hk_v3_add(ws->pos[p], hk_m3_mul_v3(&ws->frame[p], hk_m3_col(&el->lam, 0)));
        ws->frame[p + 1] = hk_m3_mul(&ws->frame[p], &el->rot);
    }
}

/* Collision samples: energy, and for active samples the data the derivatives need. */
/* Whether any point within `radius` of `centre` can touch a shape's envelope. */
static int near_shapes(const hk_StrandEnvDef *env, hk_Vec3 centre, double radius)
{
    for (int j = 0; j < env->shape_count; j++) {
        const hk_Shape *sh = &env->shapes[j];
        const double reach = hk_shape_bound(sh) + 1.7320508075688772 * fabs(env->envelope_alpha * sh->volume) + radius;
        if (hk_v3_norm2(hk_v3_sub(centre, sh->centre)) <= reach * reach) return 1;
    }
    return 0;
}

/* The offset's Jacobian in world axes (sd) and, for order 2, its second derivatives in
 * the element's frame (sd2) of the touching samples i and j of the element with
 * coordinates k and start frame r; j < 0: i alone. Two at once in two lanes, the same
 * bits. */
static void sample_derivatives(hk_StrandWorkspace *ws, hk_Vec3 k, const hk_Mat3 *r, int order, int i, int j)
{
    if (j < 0) {
        double c[HK_CN_COUNT];
        hk_element_offset_begin(k, ws->sample_u[i], c);
        hk_Mat3 dd;
        hk_element_offset_derivs(k, ws->sample_u[i], c, &dd, order >= 2 ? ws->sd2[i] : NULL);
        ws->sd[i] = hk_m3_mul(r, &dd);
        return;
    }
    const double u[2] = {ws->sample_u[i], ws->sample_u[j]};
    hk_Mat3 dd[2];
    hk_element_offset_derivs2(k, u, dd, order >= 2 ? ws->sd2[i] : NULL, order >= 2 ? ws->sd2[j] : NULL);
    ws->sd[i] = hk_m3_mul(r, &dd[0]);
    ws->sd[j] = hk_m3_mul(r, &dd[1]);
}

/* The collision samples' positions (sp) of the elements within reach of a shape
 * (near): an inextensible element stays within its length of its start. Samples are
 * evenly spaced by w: walk from one to the next with the element's own helix map,
 * d(u + w) = d(u) + E(u) d(w), E(u + w) = E(u) E(w), instead of a closed form per
 * sample. */
static void sample_points(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, hk_StrandWorkspace *ws)
{
    const double w = ws->sample_weight;
    for (int p = 0; p < sh->n; p++) {
        const int s0 = ws->elem_first_sample[p], s1 = ws->elem_first_sample[p + 1];
        ws->near[p] = s0 != s1 && near_shapes(env, ws->pos[p], sh->length[p]);
        if (!ws->near[p]) continue;
        const hk_Mat3 *r = &ws->frame[p];
        const hk_Vec3 k = k_of(q, p);
        hk_ElementLocal at, step;
        hk_element_local(k, ws->sample_u[s0], 0, 0, &at);
        if (s1 - s0 > 1) hk_element_local(k, w, 0, 0, &step);
        hk_Mat3 rot = at.rot;
        hk_Vec3 d = hk_m3_col(&at.lam, 0);
        for (int i = s0; i < s1; i++) {
            if (i > s0) {
                d = hk_v3_add(d, hk_m3_mul_v3(&rot, hk_m3_col(&step.lam, 0)));
                rot = hk_m3_mul(&rot, &step.rot);
            }
            ws->sp[i] = hk_v3_add(ws->pos[p], hk_m3_mul_v3(r, d));
        }
    }
}

/* The walk of hk_strand_energy: node poses and closed forms, and the samples' positions,
 * unless hk_strand_workspace_prepare left them for these very inputs. */
static int prepared_for(const hk_StrandWorkspace *ws, const hk_SuperHelix *sh, const hk_StrandEnvDef *env,
                        const double *q, int order)
{
    return ws->prepared && ws->key_order == order && ws->key_env.shapes == env->shapes &&
           ws->key_env.shape_count == env->shape_count &&
           memcmp(&ws->key_env.envelope_alpha, &env->envelope_alpha, sizeof(double)) == 0 &&
           memcmp(&ws->key_root, &sh->root, sizeof sh->root) == 0 &&
           memcmp(&ws->key_frame, &sh->root_frame, sizeof sh->root_frame) == 0 &&
           memcmp(ws->key_q, q, (size_t)(3 * sh->n) * sizeof(double)) == 0;
}

static void walk(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, int order,
                 hk_StrandWorkspace *ws)
{
    if (!prepared_for(ws, sh, env, q, order)) {
        forward(sh, q, order, ws);
        if (ws->sample_count > 0) sample_points(sh, env, q, ws);
    }
    ws->prepared = 0;
}

/* Collision samples (the positions from sample_points): energy, and for active samples
 * the data the derivatives need. */
static double collisions(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, int order,
                         hk_StrandWorkspace *ws, double *max_depth)
{
    double energy = 0.0;
    const double w = ws->sample_weight;
    int touching = 0;
    for (int p = 0; p < sh->n; p++) {
        const int s0 = ws->elem_first_sample[p], s1 = ws->elem_first_sample[p + 1];
        ws->first_touch[p] = touching;
        for (int i = s0; i < s1; i++) ws->active[i] = 0;
        if (!ws->near[p]) continue;
        const hk_Mat3 *r = &ws->frame[p];
        const hk_Vec3 k = k_of(q, p);
        int held = -1; /* a touching sample whose derivatives wait for the next one's */
        for (int i = s0; i < s1; i++) {
            const hk_Vec3 pt = ws->sp[i];
            if (max_depth) {
                double depth = hk_collision_depth(env->shapes, env->shape_count, env->envelope_alpha, pt);
                if (depth > *max_depth) *max_depth = depth;
                continue;
            }
            hk_Vec3 g;
            hk_Mat3 h;
            double e = hk_collision_penalty(env->shapes, env->shape_count, env->envelope_alpha, pt,
                                            order >= 1 ? &g : NULL, order >= 2 ? &h : NULL);
            if (!(e > 0.0)) continue;
            energy += w * e;
            if (order < 1) continue;
            ws->active[i] = 1;
            ws->touch[touching++] = i;
            ws->sf[i] = hk_v3_scale(g, w);
            if (order >= 2) {
                ws->sa[i] = hk_m3_scale(&h, w);
                ws->sfl[i] = hk_m3_tmul_v3(r, ws->sf[i]);
            }
            /* the offset's derivatives two samples at a time */
            if (held < 0) {
                held = i;
                continue;
            }
            sample_derivatives(ws, k, r, order, held, i);
            held = -1;
        }
        if (held >= 0) sample_derivatives(ws, k, r, order, held, -1);
    }
    ws->first_touch[sh->n] = touching;
    return energy;
}

/* 6x6 contact stiffness C = sum B^T A B with B = [-[p]x, I] (dp = omega x p + v). */
static void add_contact_stiffness(double c[6][6], hk_Vec3 p, const hk_Mat3 *a)
{
    const hk_Mat3 px = hk_m3_skew(p);
    const hk_Mat3 pa = hk_m3_mul(&px, a);    /* [p]x A */
    const hk_Mat3 pap = hk_m3_mul(&pa, &px); /* [p]x A [p]x */
    const hk_Mat3 ap = hk_m3_mul(a, &px);    /* A [p]x */
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) {
            c[i][j] -= pap.m[i][j];
            c[i][j + 3] += pa.m[i][j];
            c[i + 3][j] -= ap.m[i][j];
            c[i + 3][j + 3] += a->m[i][j];
        }
}

static void mat6_mul_vec(double c[6][6], const double *x, double *out)
{
#pragma GCC unroll 6
    for (int i = 0; i < 6; i++) {
        double s = 0.0;
#pragma GCC unroll 6
        for (int j = 0; j < 6; j++) s += c[i][j] * x[j];
        out[i] = s;
    }
}

static double dot6(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3] + a[4] * b[4] + a[5] * b[5];
}

/* (S - tr(S) I) w, the second moment of the load acting on a rotation rate w. */
static hk_Vec3 moment_op(const hk_Mat3 *s, double trace, hk_Vec3 w)
{
    return hk_v3_madd(hk_m3_mul_v3(s, w), w, -trace);
}

double hk_strand_energy(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, hk_StrandWorkspace *ws,
                        double *grad, double *hess, hk_StrandEnergy *parts)
{
    if (!env) env = &no_env;
    const int n = sh->n, dim = 3 * n;
    const int order = hess ? 2 : (grad ? 1 : 0);
    walk(sh, env, q, order, ws);

    /* Elastic energy: constant curvature per element integrates exactly (§4.1.1.3.1). */
    double e_elastic = 0.0;
    /* Of the Hessian only the diagonal blocks are cleared: the final loop writes every
     * entry of the others. */
    for (int p = 0; p < n && hess; p++)
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++) memset(hess + (size_t)(3 * p + i) * (size_t)dim + 3 * p, 0, 3 * sizeof(double));
    for (int p = 0; p < n; p++)
#pragma GCC unroll 3
        for (int i = 0; i < 3; i++) {
            const double kl = sh->material.stiffness[i] * sh->length[p];
            const double dq = q[3 * p + i] - sh->q_rest[3 * p + i];
            e_elastic += 0.5 * kl * dq * dq;
            if (grad) grad[3 * p + i] = kl * dq;
            if (hess) hess[(size_t)(3 * p + i) * (size_t)dim + (size_t)(3 * p + i)] = kl;
        }

    /* Gravity: the potential per length is fg . r with fg = -rho S g, and
     * int_element r ds = l r_P + R_P g_P in closed form (§4.1.1.3.2). */
    const hk_Vec3 fg = hk_v3_scale(sh->material.gravity, -sh->material.mass_per_length);
    double e_gravity = 0.0;
    for (int p = 0; p < n; p++) {
        hk_Vec3 integral =
            hk_v3_add(hk_v3_scale(ws->pos[p], sh->length[p]), hk_m3_mul_v3(&ws->frame[p], ws->local[p].g));
        e_gravity += hk_v3_dot(fg, integral);
    }

    const double e_collision = ws->sample_count > 0 ? collisions(sh, env, q, order, ws, NULL) : 0.0;
    const double total = e_elastic + e_gravity + e_collision;
    if (parts) {
        parts->elastic = e_elastic;
        parts->gravity = e_gravity;
        parts->collision = e_collision;
        parts->total = total;
    }
    if (order == 0) return total;

    /* Backward sweep. Accumulators describe the strand beyond the end of element p. */
    hk_Vec3 force = hk_v3_zero(), moment = hk_v3_zero();
    hk_Mat3 second = hk_m3_zero();
    double stiff[6][6];
    memset(stiff, 0, sizeof stiff);
    int stiff_zero = 1; /* no touching sample beyond yet: stiff is all +0 */
    for (int p = n - 1; p >= 0; p--) {
        const hk_ElementLocal *el = &ws->local[p];
        const hk_Mat3 *r = &ws->frame[p];
        const hk_Vec3 r1 = ws->pos[p + 1];
        const int *touch = ws->touch + ws->first_touch[p], touches = ws->first_touch[p + 1] - ws->first_touch[p];
        hk_Vec3 omega[3], t[3], dgw[3];
        double xi[3][6];
#pragma GCC unroll 3
        for (int b = 0; b < 3; b++) {
            omega[b] = hk_m3_mul_v3(r, hk_m3_col(&el->lam, b));
            t[b] = hk_m3_mul_v3(r, hk_m3_col(&el->dd, b));
            dgw[b] = hk_m3_mul_v3(r, hk_m3_col(&el->dg, b));
            const hk_Vec3 v = hk_v3_add(t[b], hk_v3_cross(r1, omega[b]));
            xi[b][0] = omega[b].x, xi[b][1] = omega[b].y, xi[b][2] = omega[b].z;
            xi[b][3] = v.x, xi[b][4] = v.y, xi[b][5] = v.z;
#pragma GCC unroll 6
            for (int e = 0; e < 6; e++) ws->xi[(size_t)e * (size_t)dim + (size_t)(3 * p + b)] = xi[b][e];
            double gb = hk_v3_dot(omega[b], moment) + hk_v3_dot(v, force) + hk_v3_dot(fg, dgw[b]);
            for (int m = 0; m < touches; m++) {
                const int i = touch[m];
                gb += hk_v3_dot(ws->sf[i], hk_m3_col(&ws->sd[i], b));
            }
            grad[3 * p + b] += gb;
        }

        if (hess) {
            /* S = sum (p - r1) f^T beyond; tr S = sum (p - r1) . f. */
            hk_Mat3 s = hk_m3_outer(r1, force);
#pragma GCC unroll 3
            for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
                for (int j = 0; j < 3; j++) s.m[i][j] = second.m[i][j] - s.m[i][j];
            const double trs = hk_m3_trace(&s);
            const hk_Vec3 arm_moment = hk_v3_sub(moment, hk_v3_cross(r1, force));
            double cxi[3][6];
            hk_Vec3 turned[3]; /* (S - tr S I) omega_b, for Y_b and the diagonal block */
#pragma GCC unroll 3
            for (int b = 0; b < 3; b++) turned[b] = moment_op(&s, trs, omega[b]);
#pragma GCC unroll 3
            for (int b = 0; b < 3; b++) {
                /* C xi is +0 to the bit while C is (sums of 0 xi_j from +0), xi finite */
                if (stiff_zero)
                    memset(cxi[b], 0, sizeof cxi[b]);
                else
                    mat6_mul_vec(stiff, xi[b], cxi[b]);
                /* Y_b: coupling of coordinate b with every earlier coordinate a through
                 * H_ab = xi_a . Y_b (rotation of b's displacement field by a, plus the
                 * contact stiffness seen through both). */
                hk_Vec3 z = hk_v3_add(turned[b], hk_v3_cross(t[b], force));
                z = hk_v3_add(z, hk_v3_cross(dgw[b], fg));
                double y[6];
                memcpy(y, cxi[b], sizeof y);
                for (int m = 0; m < touches; m++) {
                    const int i = touch[m];
                    const hk_Vec3 jb = hk_m3_col(&ws->sd[i], b);
                    z = hk_v3_add(z, hk_v3_cross(jb, ws->sf[i]));
                    const hk_Vec3 aj = hk_m3_mul_v3(&ws->sa[i], jb);
                    const hk_Vec3 paj = hk_v3_cross(ws->sp[i], aj);
                    y[0] += paj.x, y[1] += paj.y, y[2] += paj.z;
                    y[3] += aj.x, y[4] += aj.y, y[5] += aj.z;
                }
                double *yb = ws->y + (size_t)(3 * p + b) * 6;
                yb[0] = y[0] + z.x, yb[1] = y[1] + z.y, yb[2] = y[2] + z.z;
                yb[3] = y[3], yb[4] = y[4], yb[5] = y[5];
            }
            /* Diagonal block: both coordinates in element p. Loads are brought into the
             * element's start frame once, instead of rotating every derivative. */
            const hk_Vec3 arm_local = hk_m3_tmul_v3(r, arm_moment);
            const hk_Vec3 force_local = hk_m3_tmul_v3(r, force), fg_local = hk_m3_tmul_v3(r, fg);
#pragma GCC unroll 3
            for (int a = 0; a < 3; a++) {
#pragma GCC unroll 3
                for (int b = a; b < 3; b++) {
                    double h = hk_v3_dot(hk_m3_col(&el->dlam[b], a), arm_local);
                    h += hk_v3_dot(omega[b], turned[a]);
                    h += hk_v3_dot(force_local, el->d2d[a][b]);
                    h += hk_v3_dot(fg_local, el->d2g[a][b]);
                    h += dot6(xi[a], cxi[b]);
                    for (int m = 0; m < touches; m++) {
                        const int i = touch[m];
                        const hk_Vec3 ja = hk_m3_col(&ws->sd[i], a), jb = hk_m3_col(&ws->sd[i], b);
                        h += hk_v3_dot(ws->sfl[i], ws->sd2[i][a][b]);
                        h += hk_v3_dot(ja, hk_m3_mul_v3(&ws->sa[i], jb));
                    }
                    const size_t ia = (size_t)(3 * p + a), ib = (size_t)(3 * p + b);
                    hess[ia * (size_t)dim + ib] += h;
                    if (a != b) hess[ib * (size_t)dim + ia] += h;
                }
            }
        }

        /* Fold element p's own load into the accumulators. */
        const hk_Vec3 integral = hk_v3_add(hk_v3_scale(ws->pos[p], sh->length[p]), hk_m3_mul_v3(r, el->g));
        force = hk_v3_madd(force, fg, sh->length[p]);
        moment = hk_v3_add(moment, hk_v3_cross(integral, fg));
        if (hess) {
            const hk_Mat3 o = hk_m3_outer(integral, fg);
            second = hk_m3_add(&second, &o);
        }
        for (int m = 0; m < touches; m++) {
            const int i = touch[m];
            force = hk_v3_add(force, ws->sf[i]);
            moment = hk_v3_add(moment, hk_v3_cross(ws->sp[i], ws->sf[i]));
            if (hess) {
                const hk_Mat3 o = hk_m3_outer(ws->sp[i], ws->sf[i]);
                second = hk_m3_add(&second, &o);
                add_contact_stiffness(stiff, ws->sp[i], &ws->sa[i]);
                stiff_zero = 0;
            }
        }
    }

    if (hess) {
        /* Off-diagonal blocks: a in an earlier element than b, H_ab = xi_a . Y_b, row b
         * at once over a (the screws stored transposed), then mirrored. 0.0 + h: the
         * bits of a sum into a cleared matrix (-0 turns +0). */
        for (int b = 3; b < dim; b += 3) { /* element b / 3's three rows, mirrored together */
            double *r0 = hess + (size_t)b * (size_t)dim, *r1 = r0 + dim, *r2 = r1 + dim;
            hk_dot6_columns(ws->y + (size_t)b * 6, ws->xi, (size_t)dim, b, r0);
            hk_dot6_columns(ws->y + (size_t)(b + 1) * 6, ws->xi, (size_t)dim, b, r1);
            hk_dot6_columns(ws->y + (size_t)(b + 2) * 6, ws->xi, (size_t)dim, b, r2);
            for (int a = 0; a < b; a++) {
                const double h0 = 0.0 + r0[a], h1 = 0.0 + r1[a], h2 = 0.0 + r2[a];
                r0[a] = h0, r1[a] = h1, r2[a] = h2;
                double *mirror = hess + (size_t)a * (size_t)dim + (size_t)b;
                mirror[0] = h0, mirror[1] = h1, mirror[2] = h2;
            }
        }
    }
    return total;
}

int hk_strand_workspace_contact(const hk_StrandWorkspace *ws, int i, hk_Vec3 *grad)
{
    if (i < 0 || i >= ws->sample_count || !ws->active[i]) return 0;
    *grad = ws->sf[i];
    return 1;
}

int hk_strand_workspace_touching(const hk_StrandWorkspace *ws, int p, const int **samples)
{
    *samples = ws->touch + ws->first_touch[p];
    return ws->first_touch[p + 1] - ws->first_touch[p];
}

double hk_strand_max_penetration(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q,
                                 hk_StrandWorkspace *ws)
{
    if (ws->sample_count == 0) return 0.0;
    if (!env) env = &no_env;
    walk(sh, env, q, 0, ws);
    double depth = 0.0;
    collisions(sh, env, q, 0, ws, &depth);
    return depth;
}

void hk_strand_workspace_prepare(const hk_SuperHelix *sh, const hk_StrandEnvDef *env, const double *q, int order,
                                 hk_StrandWorkspace *ws)
{
    if (!env) env = &no_env;
    walk(sh, env, q, order, ws);
    memcpy(ws->key_q, q, (size_t)(3 * sh->n) * sizeof(double));
    ws->key_root = sh->root;
    ws->key_frame = sh->root_frame;
    ws->key_order = order;
    ws->key_env = *env;
    ws->prepared = 1;
}

const hk_Vec3 *hk_strand_workspace_nodes(const hk_StrandWorkspace *ws) { return ws->pos; }

void hk_strand_workspace_samples(const hk_StrandWorkspace *ws, hk_Vec3 *pos, unsigned char *known)
{
    for (int p = 0; p < ws->n; p++)
        for (int i = ws->elem_first_sample[p]; i < ws->elem_first_sample[p + 1]; i++) {
            known[i] = ws->near[p];
            if (ws->near[p]) pos[i] = ws->sp[i];
        }
}
