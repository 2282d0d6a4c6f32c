/* Time stepping of one Super-Helix (paper 000 §3.3-3.4, §4.2; docs/dynamics.md).
 *
 * Every step sweeps the strand once from the root: the node states (pose, velocities,
 * bias accelerations) advance element by element, and each element gathers its own
 * points — Gauss points for the inertia, the air drag and the inertial forces, the
 * collision samples for the body contacts, and the caller's point forces — into the
 * per-element terms of strand_kinematics.c. The elastic and gravity forces are the exact
 * gradient of the statics energy (hk_strand_energy). The linear system is then solved
 * by strand_solve.c. */
#include <math.h>
#include <string.h>

#include "dynamics_internal.h"
#include "core/avx_twins.h"
#include "core/linalg.h"
#include "rod/helix_local.h"
#include "rod/rod_internal.h"

hk_DynamicsDef hk_default_dynamics_def(void)
{
    hk_DynamicsDef p;
    /* Paper 000 §4.2: gamma = 1e-10 fitted its curly clump (Fig. 6), nu between 5e-6
     * (disciplined) and 5e-5 (fuzzy); we take disciplined-to-average hair. */
    p.internal_friction = 1e-10;
    p.air_drag = 1e-5;
    /* Hair on skin or fabric: about 0.2 along the scales, 0.4 against them. */
    p.friction_with = 0.2;
    p.friction_against = 0.4;
    p.friction_velocity = 0.05;
    p.quadrature = 0;
    /* 0.3 rad per step keeps the linearised step within a few percent of the exact
     * rotation (1 - sin(x)/x ~ x^2 / 6 = 1.5 %); 2^8 = 256 substeps at most. */
    p.max_turn = 0.3;
    /* and no node near the body travels more than 1 cm relative to the head (two of the
     * default CollisionStep) in one step: with 5 mm a shaken head took 1.55 steps per
     * guide and frame instead of 1.26, for no measurable change in how deep tips enter
     * the head (the penalty's own reach dominates, tests/test_hair_sim.c) */
    p.max_travel = 0.01;
    /* The linearly implicit Euler step sees the contacts of its start: a sample that
     * meets the body during the step goes in unopposed by its whole travel (under nod,
     * guides of examples/guides200 reached 4.5 mm into the neck at 0.16 m/s, where
     * the penalty's own reach v sqrt(rho S / k) is 0.1 mm). 1 mm leaves room below the
     * 2 mm that guides may enter (docs/dynamics.md, "Limitations"). */
    p.max_entry = 0.001;
    p.max_depth = 8;
    p.hessian_interval = 4;
    /* The O(N) solver by default: with every force implicit in the stage equations,
     * the iteration matrix only steers Newton's iteration (docs/dynamics.md). */
    p.solver = HK_DYNAMICS_LINEAR;
    p.stiffness = HK_STIFFNESS_GAUSS_NEWTON;
    p.newton_tolerance = 1e-5;
    p.newton_iterations = 12;
    p.integrator = HK_INTEGRATOR_TRBDF2;
    return p;
}

void hk_strand_dynamics_destroy(hk_StrandDynamics *d)
{
    if (!d) return;
    hk_strand_workspace_destroy(d->ws);
    hk_free(d->shapes);
    hk_free(d->v);
    hk_free(d->terms);
    hk_free(d->ends);
    hk_free(d->work);
    hk_free(d->anchor_pos);
    hk_free(d->anchor_vel);
    hk_strand_workspace_destroy(d->ws_body);
    hk_free(d->hess);
    hk_free(d->dense_work);
    hk_free(d->entry_s);
    hk_free(d->entry_pos[0]);
    hk_free(d->entry_known[0]);
    hk_free(d->tip_shapes);
    hk_free(d);
}

static int params_valid(const hk_DynamicsDef *p)
{
    return p->internal_friction >= 0.0 && isfinite(p->internal_friction) && p->air_drag >= 0.0 &&
           isfinite(p->air_drag) && p->friction_with >= 0.0 && isfinite(p->friction_with) &&
           p->friction_against >= 0.0 && isfinite(p->friction_against) && p->friction_velocity > 0.0 &&
           isfinite(p->friction_velocity) && p->quadrature >= 0 && p->quadrature <= HK_GAUSS_MAX && p->max_turn > 0.0 &&
           p->max_travel > 0.0 && p->max_entry > 0.0 && p->max_depth >= 0 && p->max_depth <= 30 &&
           p->hessian_interval >= 1 && p->hessian_interval <= 1000 && p->newton_tolerance > 0.0 &&
           isfinite(p->newton_tolerance) && p->newton_iterations >= 1 && p->newton_iterations <= 1000 &&
           (p->integrator == HK_INTEGRATOR_TRBDF2 || p->integrator == HK_INTEGRATOR_LINEAR_EULER) &&
           (p->solver == HK_DYNAMICS_LINEAR || p->solver == HK_DYNAMICS_DENSE) &&
           (p->stiffness == HK_STIFFNESS_GAUSS_NEWTON ||
            (p->stiffness == HK_STIFFNESS_FULL && p->solver == HK_DYNAMICS_DENSE));
}

/* HK_STIFFNESS_FULL's matrices: the Hessian, G+ and the work of G+'s computation (the
 * Cholesky test's factor, then hk_symmetric_positive_part's), in one block. */
static int alloc_hessians(hk_StrandDynamics *d, hk_Error *err)
{
    const size_t dim = (size_t)(3 * d->sh->n);
    d->hess = hk_alloc_array(2 * dim * dim + HK_POSITIVE_PART_WORK(dim), sizeof(double), err);
    if (!d->hess) return 0;
    d->hess_pos = d->hess + dim * dim;
    d->geo_work = d->hess_pos + dim * dim;
    return 1;
}

hk_Status hk_strand_dynamics_create(hk_SuperHelix *sh, const hk_DynamicsDef *params, const hk_StrandEnvDef *body,
                                    hk_StrandDynamics **out, hk_Error *err)
{
    *out = NULL;
    const hk_DynamicsDef defaults = hk_default_dynamics_def();
    if (!params) params = &defaults;
    if (!params_valid(params))
        return hk_error_set(err, HK_ERR_INVALID,
                            "dynamics parameters out of range (friction and drag must be >= 0, "
                            "quadrature 0..%d; the full stiffness needs the dense solver)",
                            HK_GAUSS_MAX);
    hk_StrandDynamics *d = hk_calloc_array(1, sizeof *d, err);
    if (!d) return HK_ERR_NOMEM;
    const int n = sh->n;
    const size_t dim = (size_t)3 * (size_t)n;
    d->sh = sh;
    d->params = *params;
    d->root_head = sh->root;
    d->frame_head = sh->root_frame;
    d->potential_env = hk_default_strand_env_def();
    hk_gauss_table_init(&d->gauss);
    /* One block for the 3N vectors (struct hk_StrandDynamics). */
    d->v = hk_calloc_array((23 + 2 * HK_ANDERSON_DEPTH + 2) * dim, sizeof(double), err);
    d->terms = hk_alloc_array((size_t)n, sizeof(hk_ElementTerms), err);
    d->ends = hk_alloc_array((size_t)n, sizeof(hk_EndPose), err);
    const int dense = params->solver == HK_DYNAMICS_DENSE;
    d->work = hk_alloc_array(dense ? HK_DENSE_WORK(n) : HK_LINEAR_WORK(n), sizeof(double), err);
    if (!d->v || !d->terms || !d->ends || !d->work ||
        hk_strand_workspace_create(sh, &d->potential_env, &d->ws, err) != HK_OK) {
        hk_strand_dynamics_destroy(d);
        return err ? err->code : HK_ERR_NOMEM;
    }
    double *next = d->v + dim;
    double **vectors[] = {&d->delta, &d->rhs, &d->extra, &d->grad, &d->acc, &d->q0,
                          &d->v0,    &d->aq,  &d->av,    &d->x,    &d->vg,  &d->qg};
    for (size_t i = 0; i < sizeof vectors / sizeof vectors[0]; i++, next += dim) *vectors[i] = next;
    d->saved = next;            /* 2 x 3N */
    d->acc_at = next + 2 * dim; /* 2 x 3N */
    d->start = next + 4 * dim;  /* 2 x 3N */
    d->prev_v0 = next + 6 * dim;
    d->prev_vg = next + 7 * dim;
    d->start_guess = next + 8 * dim;
    d->mixing = next + 9 * dim; /* (2 HK_ANDERSON_DEPTH + 2) x 3N */
    d->ends_q = d->mixing + (2 * HK_ANDERSON_DEPTH + 2) * dim;
    if (body && body->shape_count > 0 && body->collision_step > 0.0) {
        d->shapes = hk_alloc_array((size_t)body->shape_count, sizeof(hk_Shape), err);
        if (!d->shapes) {
            hk_strand_dynamics_destroy(d);
            return HK_ERR_NOMEM;
        }
        memcpy(d->shapes, body->shapes, (size_t)body->shape_count * sizeof(hk_Shape));
        /* The statics' collision samples, so that a strand at rest stays where the
         * statics put it. */
        d->contact_samples = hk_strand_collision_sample_count(sh, body);
        const double m = d->contact_samples;
        d->contact.shapes = d->shapes;
        d->contact.shape_count = body->shape_count;
        d->contact.envelope_alpha = body->envelope_alpha;
        d->contact.weight = sh->total_length / m;
        d->contact.friction_with = params->friction_with;
        d->contact.friction_against = params->friction_against;
        d->contact.friction_velocity = params->friction_velocity;
        d->body_env = *body;
        d->body_env.shapes = d->shapes;
        /* the samples and the tip, before and after a step (contact_entry.c) */
        d->entry_count = d->contact_samples + 1;
        const size_t ec = (size_t)d->entry_count;
        d->entry_s = hk_alloc_array(ec + 2 * dim, sizeof(double), err);
        d->entry_pos[0] = hk_alloc_array(2 * ec + 2 * ((size_t)n + 1), sizeof(hk_Vec3), err);
        d->entry_known[0] = hk_alloc_array(2 * ec, 1, err);
        /* the tip's penalty: the body shapes only (tip_contact.c) */
        d->tip_shapes = hk_alloc_array((size_t)body->shape_count, sizeof(hk_Shape), err);
        if (!d->entry_s || !d->entry_pos[0] || !d->entry_known[0] || !d->tip_shapes) {
            hk_strand_dynamics_destroy(d);
            return HK_ERR_NOMEM;
        }
        for (int i = 0; i < d->contact_samples; i++) d->entry_s[i] = (i + 0.5) * d->contact.weight;
        d->entry_s[d->contact_samples] = sh->total_length;
        d->entry_q[0] = d->entry_s + ec;
        d->entry_q[1] = d->entry_q[0] + dim;
        d->entry_pos[1] = d->entry_pos[0] + ec;
        d->entry_known[1] = d->entry_known[0] + ec;
        d->entry_nodes[0] = d->entry_pos[1] + ec;
        d->entry_nodes[1] = d->entry_nodes[0] + n + 1;
        d->tip = d->contact;
        d->tip.shapes = d->tip_shapes;
        d->tip.shape_count = 0;
        d->tip.envelope_alpha = 0.0;
        d->tip.weight = 0.5 * d->contact.weight;
        for (int i = 0; i < body->shape_count; i++)
            if (!body->shapes[i].styling) d->tip_shapes[d->tip.shape_count++] = body->shapes[i];
    } else {
        d->body_env = hk_default_strand_env_def();
    }
    if (params->stiffness == HK_STIFFNESS_FULL) {
        if (!alloc_hessians(d, err) || hk_strand_workspace_create(sh, &d->body_env, &d->ws_body, err) != HK_OK) {
            hk_strand_dynamics_destroy(d);
            return err ? err->code : HK_ERR_NOMEM;
        }
    } else if (d->contact_samples > 0 && hk_strand_workspace_create(sh, &d->body_env, &d->ws_body, err) != HK_OK) {
        /* the body's penalty energy, for the energy guard of the integrator */
        hk_strand_dynamics_destroy(d);
        return err ? err->code : HK_ERR_NOMEM;
    }
    *out = d;
    return HK_OK;
}

double *hk_strand_dynamics_velocity(hk_StrandDynamics *d) { return d->v; }

int hk_strand_dynamics_contact_count(const hk_StrandDynamics *d) { return d->contact_count; }

hk_DynamicsStats hk_strand_dynamics_stats(const hk_StrandDynamics *d) { return d->stats; }

void hk_strand_dynamics_place(hk_StrandDynamics *d, const hk_RigidState *head)
{
    const hk_RigidState still = hk_rigid_identity();
    if (!head) head = &still;
    d->sh->root = hk_v3_add(hk_m3_mul_v3(&head->rot, d->root_head), head->trans);
    d->sh->root_frame = hk_m3_mul(&head->rot, &d->frame_head);
}

/* Root state: the root is a point of the head, its frame turns with the head. */
hk_FrameKinematics hk_dynamics_root_kinematics(const hk_StrandDynamics *d, const hk_RigidState *head)
{
    hk_FrameKinematics k;
    const hk_Vec3 rel = hk_v3_sub(d->sh->root, head->trans);
    k.frame = d->sh->root_frame;
    k.pos = d->sh->root;
    k.omega = head->omega;
    k.vel = hk_v3_add(head->vel, hk_v3_cross(head->omega, rel));
    k.alpha = head->alpha;
    k.acc = hk_v3_add(head->acc, hk_v3_cross(head->alpha, rel));
    k.acc = hk_v3_add(k.acc, hk_v3_cross(head->omega, hk_v3_cross(head->omega, rel)));
    return k;
}

static hk_Vec3 k_of(const double *q, int p) { return hk_v3(q[3 * p], q[3 * p + 1], q[3 * p + 2]); }

/* Gauss points for element p: 3 integrate a straight element's products of Jacobians
 * (polynomials of degree 4 in u) exactly; more for the helix phase |k| l of the element
 * (and of its rest shape), whose trigonometric integrands a rule of n points
 * integrates to about (phase)^(2n) / (2n)!. */
static int gauss_count(const hk_StrandDynamics *d, int p)
{
    if (d->params.quadrature > 0) return d->params.quadrature;
    const hk_SuperHelix *sh = d->sh;
    const double phase = sh->length[p] * fmax(hk_v3_norm(k_of(sh->q, p)), hk_v3_norm(k_of(sh->q_rest, p)));
    const double g = 3.0 + ceil(1.5 * phase);
    return g < HK_GAUSS_MAX ? (int)g : HK_GAUSS_MAX;
}

/* Rotary inertia of the section in world axes: sum_i I_i n_i n_i^T, written as
 * I_1 (the identity) + (I_0 - I_1) n0 n0^T + (I_2 - I_1) n2 n2^T since the n_i are
 * orthonormal. (Unrolled: -O2 kept the loops, and their i == j test, rolled.) */
static hk_Mat3 rotary_inertia(const hk_RodMaterial *m, const hk_Mat3 *frame, double weight)
{
    const double i1 = weight * m->rotary_inertia[1], d0 = weight * m->rotary_inertia[0] - i1,
                 d2 = weight * m->rotary_inertia[2] - i1;
    const hk_Vec3 n0 = hk_m3_col(frame, 0), n2 = hk_m3_col(frame, 2);
    const double a[3] = {n0.x, n0.y, n0.z}, c[3] = {n2.x, n2.y, n2.z};
    hk_Mat3 out;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) out.m[i][j] = (i == j ? i1 : 0.0) + d0 * a[i] * a[j] + d2 * c[i] * c[j];
    return out;
}

/* A point force at a point of element p: its value where the point is now, following
 * the force's linearisation from where it was given (the anchor, at the start of the
 * step: F0 - K (x - x0) - D (v - v0)), and ch^2 K + ch D as the iteration matrix's
 * effective mass. */
static void add_point_force(hk_ElementTerms *t, const hk_PointKinematics *pk, const hk_PointForce *pf, double ch,
                            const hk_Vec3 *anchor_pos, const hk_Vec3 *anchor_vel, const hk_RigidState *euler_head)
{
    hk_Vec3 force = pf->force;
    if (anchor_pos) {
        force = hk_v3_sub(force, hk_m3_mul_v3(&pf->stiffness, hk_v3_sub(pk->k.pos, *anchor_pos)));
        force = hk_v3_sub(force, hk_m3_mul_v3(&pf->damping, hk_v3_sub(pk->k.vel, *anchor_vel)));
    }
    if (euler_head) { /* linearly implicit Euler: minus dt K (J q'), the stiffness acting
                         on the velocity relative to the head */
        const hk_Vec3 rigid =
            hk_v3_add(euler_head->vel, hk_v3_cross(euler_head->omega, hk_v3_sub(pk->k.pos, euler_head->trans)));
        force = hk_v3_sub(force, hk_v3_scale(hk_m3_mul_v3(&pf->stiffness, hk_v3_sub(pk->k.vel, rigid)), ch));
    }
    const hk_Mat3 ks = hk_m3_scale(&pf->stiffness, ch * ch), ds = hk_m3_scale(&pf->damping, ch);
    const hk_Mat3 a = hk_m3_add(&ks, &ds);
    hk_element_terms_add(t, pk->k.pos, &a, NULL, &pk->jac, NULL, force, hk_v3_zero());
}

/* Body contact of collision sample `sample`, at offset u into the element that starts
 * at node (coordinates k, rates kd), with the Gauss-Newton stiffness: fills pk and pf
 * and returns 1 when the sample touches a shape (the penalty's normal force and its
 * friction). With the full stiffness the potential's evaluation (full_potential, just
 * before) tells which samples touch and their penalty gradients, and the sweep adds
 * their friction alone (add_friction). */
static int body_contact(const hk_StrandDynamics *d, const hk_RigidState *head, const hk_FrameKinematics *node,
                        hk_Vec3 k, hk_Vec3 kd, double u, hk_PointKinematics *pk, hk_PointForce *pf)
{
    double c[HK_CN_COUNT];
    const hk_Vec3 pos = hk_v3_add(node->pos, hk_m3_mul_v3(&node->frame, hk_element_offset_begin(k, u, c)));
    const hk_Vec3 x = hk_m3_tmul_v3(&head->rot, hk_v3_sub(pos, head->trans));
    if (!(hk_collision_depth(d->contact.shapes, d->contact.shape_count, d->contact.envelope_alpha, x) > 0.0)) return 0;
    hk_point_kinematics(node, k, kd, u, 1, pk);
    return hk_body_contact_force(&d->contact, head, pk->k.pos, pk->k.vel, hk_m3_col(&pk->k.frame, 0), pf);
}

/* HK_STIFFNESS_FULL: the friction of the touching sample whose kinematics pk has (pos,
 * vel, jac, the tangent) and whose penalty gradient in head space is g, added to t. */
static void add_friction(hk_StrandDynamics *d, const hk_RigidState *head, hk_ElementTerms *t,
                         const hk_PointKinematics *pk, hk_Vec3 g, double ch)
{
    hk_PointForce pf;
    if (!hk_body_contact_friction(&d->contact, head, pk->k.pos, pk->k.vel, hk_m3_col(&pk->k.frame, 0),
                                  hk_m3_mul_v3(&head->rot, g), &pf))
        return;
    d->contact_count++;
    add_point_force(t, pk, &pf, ch, NULL, NULL, d->params.integrator == HK_INTEGRATOR_LINEAR_EULER ? head : NULL);
}

/* Velocity of a point and of its frame when the coordinates move at rates x and the
 * root is still: the same chain as the kinematics, with the Jacobians it computed. */
typedef struct RateChain {
    hk_Vec3 omega, vel;
} RateChain;

static RateChain rate_at(const RateChain *node, const hk_Vec3 node_pos, const hk_PointKinematics *pk, hk_Vec3 xp)
{
    RateChain out;
    out.omega = hk_v3_add(node->omega, hk_m3_mul_v3(&pk->jac_rot, xp));
    out.vel = hk_v3_add(hk_v3_add(node->vel, hk_v3_cross(node->omega, hk_v3_sub(pk->k.pos, node_pos))),
                        hk_m3_mul_v3(&pk->jac, xp));
    return out;
}

typedef enum SweepMode { SWEEP_STEP, SWEEP_MASS } SweepMode;

/* One sweep from root to tip filling d->terms. STEP: the iteration matrix's mass part
 * for the coefficient ch and every load at (q, v), minus M x / ch when x is given;
 * MASS: the plain mass matrix, no loads. */
static void sweep(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                  double ch, const double *x, SweepMode mode)
{
    const hk_SuperHelix *sh = d->sh;
    const hk_RodMaterial *mat = &sh->material;
    const int n = sh->n;
    const double rho_s = mat->mass_per_length;
    const double nu = mode == SWEEP_STEP ? d->params.air_drag : 0.0;
    const double cw = d->contact.weight;
    const double inv_ch = x && ch > 0.0 ? 1.0 / ch : 0.0;
    const int euler = d->params.integrator == HK_INTEGRATOR_LINEAR_EULER;
    const int full = d->params.stiffness == HK_STIFFNESS_FULL;
    memset(d->terms, 0, (size_t)n * sizeof(hk_ElementTerms));
    hk_FrameKinematics node = hk_dynamics_root_kinematics(d, head);
    RateChain rate = {hk_v3_zero(), hk_v3_zero()};
    int sample = 0, fi = 0;
    d->contact_count = 0;
    for (int p = 0; p < n; p++) {
        hk_ElementTerms *t = &d->terms[p];
        const hk_Vec3 k = k_of(sh->q, p), kd = k_of(d->v, p), xp = x ? k_of(x, p) : hk_v3_zero();
        const double len = sh->length[p];
        const int g = gauss_count(d, p);
        hk_PointKinematics pair[2], end;
        int end_known = 0;
        /* a pair's first point's a, b, f and tau, added with the second's */
        double aq[2];
        hk_Mat3 bq[2];
        hk_Vec3 fq[2], tauq[2];
        for (int i = 0; i < g; i++) {
            const double u = len * d->gauss.node[g - 1][i], w = len * d->gauss.weight[g - 1][i];
            /* A step's points two at a time; an odd last one with the element's end, which
             * starts the next element (the same bits as on its own). */
            if (mode == SWEEP_STEP && i % 2 == 0) {
                end_known = i + 1 == g;
                const double uu[2] = {u, end_known ? len : len * d->gauss.node[g - 1][i + 1]};
                hk_point_kinematics2(&node, k, kd, uu, pair);
                if (end_known) end = pair[1];
            } else if (mode != SWEEP_STEP) {
                hk_point_kinematics(&node, k, kd, u, 1, &pair[0]);
            }
            const hk_PointKinematics *pk = &pair[mode == SWEEP_STEP ? i % 2 : 0];
            const hk_Mat3 b = rotary_inertia(mat, &pk->k.frame, w);
            hk_Vec3 f = hk_v3_zero(), tau = hk_v3_zero();
            if (mode == SWEEP_STEP) {
                /* Inertial forces of the bias acceleration and the air drag (eq. 5a). */
                f = hk_v3_scale(hk_v3_add(hk_v3_scale(pk->k.acc, rho_s), hk_v3_scale(pk->k.vel, nu)), -w);
                /* Euler's equations of the section: I w' + w x I w. */
                const hk_Vec3 iw = hk_m3_mul_v3(&b, pk->k.omega);
                tau = hk_v3_neg(hk_v3_add(hk_m3_mul_v3(&b, pk->k.alpha), hk_v3_cross(pk->k.omega, iw)));
                if (x) { /* the stage's inertia, M x / ch, as loads of this point */
                    const RateChain r = rate_at(&rate, node.pos, pk, xp);
                    f = hk_v3_madd(f, r.vel, -rho_s * w * inv_ch);
                    tau = hk_v3_sub(tau, hk_v3_scale(hk_m3_mul_v3(&b, r.omega), inv_ch));
                }
            }
            const double a = (rho_s + ch * nu) * w;
            if (mode == SWEEP_STEP && !end_known) { /* two Gauss points, in two lanes */
                const int l = i % 2;
                aq[l] = a, bq[l] = b, fq[l] = f, tauq[l] = tau;
                if (l == 1) hk_element_terms_add_quadrature2(t, pair, aq, bq, fq, tauq);
                continue;
            }
            hk_element_terms_add_quadrature(t, pk->k.pos, a, &b, &pk->jac, &pk->jac_rot, f, tau);
        }
        const double s_end = sh->s_start[p + 1];
        const int last = p == n - 1;
        /* Body contacts at the collision samples of this element. With the full
         * stiffness the potential told which touch: their kinematics two at a time,
         * their forces added in the order of the samples. */
        if (mode == SWEEP_STEP && full) {
            /* the element's touching samples as the potential listed them: its elements
             * hold the samples the sweep's would (s = (i + 1/2) w against s_start, w the
             * same quotient), in the same order */
            const int *touch;
            const int touches = hk_strand_workspace_touching(d->ws_body, p, &touch);
            int m = 0;
            for (; m + 1 < touches; m += 2) {
                hk_Vec3 grad[2];
                hk_strand_workspace_contact(d->ws_body, touch[m], &grad[0]);
                hk_strand_workspace_contact(d->ws_body, touch[m + 1], &grad[1]);
                hk_PointKinematics pk[2];
                const double uu[2] = {(touch[m] + 0.5) * cw - sh->s_start[p],
                                      (touch[m + 1] + 0.5) * cw - sh->s_start[p]};
                hk_point_contact2(&node, k, kd, uu, pk);
                add_friction(d, head, t, &pk[0], grad[0], ch);
                add_friction(d, head, t, &pk[1], grad[1], ch);
            }
            if (m < touches) { /* the element's last one, alone */
                hk_Vec3 grad;
                hk_strand_workspace_contact(d->ws_body, touch[m], &grad);
                hk_PointKinematics pk;
                hk_point_kinematics(&node, k, kd, (touch[m] + 0.5) * cw - sh->s_start[p], 1, &pk);
                add_friction(d, head, t, &pk, grad, ch);
            }
        }
        for (; mode == SWEEP_STEP && !full && sample < d->contact_samples; sample++) {
            const double s = (sample + 0.5) * cw;
            if (!last && s >= s_end) break;
            hk_PointKinematics pk;
            hk_PointForce pf;
            if (!body_contact(d, head, &node, k, kd, s - sh->s_start[p], &pk, &pf)) continue;
            d->contact_count++;
            add_point_force(t, &pk, &pf, ch, NULL, NULL, euler ? head : NULL);
        }
        /* The caller's point forces (sorted by s). */
        for (; mode == SWEEP_STEP && fi < force_count; fi++) {
            const double s = forces[fi].s;
            if (!last && s >= s_end) break;
            double u = s - sh->s_start[p];
            if (!(u >= 0.0)) u = 0.0;
            if (u > len) u = len;
            hk_PointKinematics pk;
            hk_point_kinematics(&node, k, kd, u, 1, &pk);
            add_point_force(t, &pk, &forces[fi], ch, &d->anchor_pos[fi], &d->anchor_vel[fi], euler ? head : NULL);
        }
        if (!end_known) hk_point_kinematics(&node, k, kd, len, mode == SWEEP_STEP ? 2 : 1, &end);
        hk_PointForce tip;
        if (last && mode == SWEEP_STEP && hk_dynamics_tip_contact(d, head, &end, &tip)) {
            d->contact_count++;
            add_point_force(t, &end, &tip, ch, NULL, NULL, euler ? head : NULL);
        }
        hk_element_terms_set_screw(t, &end);
        d->ends[p] = (hk_EndPose){end.k.frame, end.jac, end.jac_rot, end.k.pos};
        if (x) rate = rate_at(&rate, node.pos, &end, xp);
        node = end.k;
    }
    /* the ends' poses hold for this state (hk_dynamics_end_poses) */
    memcpy(d->ends_q, sh->q, (size_t)(3 * n) * sizeof(double));
    d->ends_root = sh->root;
    d->ends_frame = sh->root_frame;
    d->ends_valid = 1;
}

const hk_EndPose *hk_dynamics_end_poses(const hk_StrandDynamics *d)
{
    const hk_SuperHelix *sh = d->sh;
    const int same = d->ends_valid && memcmp(d->ends_q, sh->q, (size_t)(3 * sh->n) * sizeof(double)) == 0 &&
                     memcmp(&d->ends_root, &sh->root, sizeof sh->root) == 0 &&
                     memcmp(&d->ends_frame, &sh->root_frame, sizeof sh->root_frame) == 0;
    return same ? d->ends : NULL;
}

/* The strand's root pose moved to head space (where the body's shapes are) for a
 * computation; returns the world pose, for restore_world_pose. */
typedef struct RootPose {
    hk_Vec3 root;
    hk_Mat3 frame;
} RootPose;

static RootPose use_head_space(hk_StrandDynamics *d)
{
    const RootPose world = {d->sh->root, d->sh->root_frame};
    d->sh->root = d->root_head;
    d->sh->root_frame = d->frame_head;
    return world;
}

static void restore_world_pose(hk_StrandDynamics *d, RootPose world)
{
    d->sh->root = world.root;
    d->sh->root_frame = world.frame;
}

void hk_dynamics_head_space_nodes(hk_StrandDynamics *d, const double *q, hk_Vec3 *nodes)
{
    const RootPose world = use_head_space(d);
    hk_superhelix_nodes(d->sh, q, nodes, NULL);
    restore_world_pose(d, world);
}

void hk_dynamics_head_space_walk(hk_StrandDynamics *d, const double *q, const double *s, int count, hk_Vec3 *points,
                                 hk_Vec3 *nodes)
{
    const RootPose world = use_head_space(d);
    hk_superhelix_points_nodes(d->sh, q, s, count, points, nodes);
    restore_world_pose(d, world);
}

void hk_dynamics_potential_walk(hk_StrandDynamics *d, const double *q, hk_Vec3 *points, unsigned char *known,
                                hk_Vec3 *nodes)
{
    hk_SuperHelix *sh = d->sh;
    /* the order of the next evaluation's potential (hk_dynamics_evaluate's refresh) */
    const int order = d->evaluations % d->params.hessian_interval == 0 ? 2 : 1;
    const RootPose world = use_head_space(d);
    hk_strand_workspace_prepare(sh, &d->body_env, q, order, d->ws_body);
    restore_world_pose(d, world);
    memcpy(nodes, hk_strand_workspace_nodes(d->ws_body), (size_t)(sh->n + 1) * sizeof(hk_Vec3));
    hk_strand_workspace_samples(d->ws_body, points, known);
    points[d->contact_samples] = nodes[sh->n]; /* the tip: the last node */
    known[d->contact_samples] = 1;
}

hk_Vec3 hk_dynamics_head_space_tip(hk_StrandDynamics *d, const double *q)
{
    const RootPose world = use_head_space(d);
    hk_Vec3 tip;
    hk_superhelix_eval(d->sh, q, d->sh->total_length, &tip, NULL);
    restore_world_pose(d, world);
    return tip;
}

/* HK_STIFFNESS_FULL: gradient and Hessian of the whole potential with the body's
 * penalty, evaluated in head space (where the shapes are; the generalized Hessian does
 * not change under a rigid motion of the scene, gravity turned with it). */
static void full_potential(hk_StrandDynamics *d, const hk_RigidState *head, int with_hessian)
{
    hk_SuperHelix *sh = d->sh;
    const hk_Vec3 gravity = sh->material.gravity;
    const RootPose world = use_head_space(d);
    sh->material.gravity = hk_m3_tmul_v3(&head->rot, gravity);
    hk_strand_energy(sh, &d->body_env, sh->q, d->ws_body, d->grad, with_hessian ? d->hess : NULL, NULL);
    sh->material.gravity = gravity;
    restore_world_pose(d, world);
}

/* The geometric stiffness G = Hess - K (the elastic diagonal K is in the matrix
 * already): gravity's and the contacts' second derivatives. For Newton's iteration G
 * is used as it is while M + ch D + ch^2 (K + G) is positive definite - as it is about
 * any stable rest state, where the whole Hessian is. Left out, gravity's coupling of
 * twist and bending in a curly strand (comparable to the twist's own stiffness, which
 * is all the twist has against it: its inertia is the section's) slowed the iteration
 * to a contraction of 0.7 per step. Where the matrix is indefinite - hair held above its
 * root, gravity pulling hair over a crest - G+ = V max(L, 0) V^T from G's
 * eigen-decomposition steers instead (positive_part). */
static void geometric_stiffness(hk_StrandDynamics *d)
{
    const hk_SuperHelix *sh = d->sh;
    const size_t sd = (size_t)(3 * sh->n);
    for (size_t j = 0; j < sd; j++) d->hess[j * sd + j] -= sh->material.stiffness[j % 3] * sh->length[j / 3];
    d->hess_pos_valid = 0;
}

/* G+ into hess_pos (once per refresh of G). The linearly implicit Euler step uses it
 * alone: implicit Euler would amplify the modes of a negative part by
 * 1 / (1 - dt^2 w^2) (the energy of a strand released sideways rose by 70 % in one
 * step). */
static const double *positive_part(hk_StrandDynamics *d)
{
    if (d->hess_pos_valid) return d->hess_pos;
    const int dim = 3 * d->sh->n;
    const size_t sd = (size_t)dim;
    /* A positive definite G is its own positive part: one Cholesky factorisation tells,
     * and saves the decomposition. On a head G is indefinite in nearly every step
     * (examples/guides200: about 10 of its 30 eigenvalues negative), so the test is
     * tried only when the guide's last G was positive (semi)definite. */
    if (!d->geo_indefinite && hk_cholesky_factor(dim, d->hess, 0.0, NULL, d->geo_work)) {
        memcpy(d->hess_pos, d->hess, sd * sd * sizeof(double));
    } else {
        /* G+ = V max(L, 0) V^T, as G minus its negative modes when they are fewer (a
         * third on a head), with the eigenvectors of the fewer side only
         * (hk_symmetric_positive_part; the whole decomposition took twice as long). */
        int negative = 0;
        if (hk_symmetric_positive_part(dim, d->hess, d->hess_pos, d->geo_work, &negative))
            d->geo_indefinite = negative > 0;
        else /* no convergence (not seen): the Gauss-Newton matrix */
            memset(d->hess_pos, 0, sd * sd * sizeof(double));
    }
    d->hess_pos_valid = 1;
    return d->hess_pos;
}

const double *hk_dynamics_geometric_positive(hk_StrandDynamics *d) { return positive_part(d); }

double hk_dynamics_total_energy(hk_StrandDynamics *d, const hk_RigidState *head, double *kinetic)
{
    double k = 0.0, u = 0.0;
    hk_strand_dynamics_energy(d, head, &k, d->ws_body ? NULL : &u);
    if (d->ws_body) { /* with the body's penalty: in head space, gravity turned with it */
        hk_SuperHelix *sh = d->sh;
        const hk_Vec3 gravity = sh->material.gravity;
        const RootPose world = use_head_space(d);
        sh->material.gravity = hk_m3_tmul_v3(&head->rot, gravity);
        u = hk_strand_energy(sh, &d->body_env, sh->q, d->ws_body, NULL, NULL, NULL);
        sh->material.gravity = gravity;
        restore_world_pose(d, world);
        u += hk_dynamics_tip_energy(d, sh->q);
    }
    if (kinetic) *kinetic = k;
    return k + u;
}

void hk_dynamics_evaluate(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces, int force_count,
                          double ch, const double *x)
{
    hk_SuperHelix *sh = d->sh;
    const int n = sh->n;
    hk_strand_dynamics_place(d, head);
    /* Elastic energy and gravity (and with the full stiffness the body's penalty): the
     * exact gradient of the statics energy. */
    const int full = d->params.stiffness == HK_STIFFNESS_FULL;
    /* G+ only steers the iteration: refreshing it every few evaluations, with the
     * gradient exact every time, saves the Hessian and its eigen-decomposition. The
     * dense fallback of the O(N) solver takes the Hessian of elastic energy and gravity
     * every time (the contacts' Gauss-Newton part is in the terms). */
    const int refresh = d->dense_fallback || (full && d->evaluations % d->params.hessian_interval == 0);
    d->evaluations++;
    if (full)
        full_potential(d, head, refresh);
    else
        hk_strand_energy(sh, &d->potential_env, sh->q, d->ws, d->grad, d->dense_fallback ? d->hess : NULL, NULL);
    sweep(d, head, forces, force_count, ch, x, SWEEP_STEP);
    if (refresh) geometric_stiffness(d);
    hk_terms_generalized_force(n, d->terms, d->rhs);
    /* Elastic stiffness and internal friction (eq. 5c-d) are diagonal: gamma and K_i
     * times the element length. */
    for (int p = 0; p < n; p++)
        for (int i = 0; i < 3; i++) {
            const int j = 3 * p + i;
            const double kl = sh->material.stiffness[i] * sh->length[p];
            const double gl = d->params.internal_friction * sh->length[p];
            d->rhs[j] -= d->grad[j] + gl * d->v[j];
            d->extra[j] = ch * gl + ch * ch * kl;
        }
}

int hk_dynamics_solve(hk_StrandDynamics *d, double ch, double *out)
{
    const int n = d->sh->n;
    if (d->dense_fallback) {
        if (hk_terms_solve_dense(n, d->terms, d->extra, d->hess, ch * ch, d->rhs, out, d->dense_work)) return 1;
        return hk_terms_solve_dense(n, d->terms, d->extra, positive_part(d), ch * ch, d->rhs, out, d->dense_work);
    }
    if (d->params.solver == HK_DYNAMICS_DENSE) {
        if (!d->hess) /* the Gauss-Newton stiffness */
            return hk_terms_solve_dense(n, d->terms, d->extra, NULL, 0.0, d->rhs, out, d->work);
        if (d->params.integrator == HK_INTEGRATOR_TRBDF2 &&
            hk_terms_solve_dense(n, d->terms, d->extra, d->hess, ch * ch, d->rhs, out, d->work))
            return 1;
        return hk_terms_solve_dense(n, d->terms, d->extra, positive_part(d), ch * ch, d->rhs, out, d->work);
    }
    return hk_terms_solve_linear(n, d->terms, d->extra, d->rhs, out, d->work);
}

int hk_dynamics_dense_ready(hk_StrandDynamics *d)
{
    if (!d->dense_work) d->dense_work = hk_alloc_array(HK_DENSE_WORK(d->sh->n), sizeof(double), NULL);
    if (!d->hess) alloc_hessians(d, NULL);
    return d->dense_work && d->hess;
}

hk_Status hk_dynamics_anchor_forces(hk_StrandDynamics *d, const hk_RigidState *head, const hk_PointForce *forces,
                                    int force_count, hk_Error *err)
{
    if (force_count < 0 || (force_count > 0 && !forces))
        return hk_error_set(err, HK_ERR_INVALID, "bad point force list");
    if (force_count > d->anchor_capacity) {
        hk_free(d->anchor_pos);
        hk_free(d->anchor_vel);
        d->anchor_capacity = 0;
        d->anchor_pos = hk_alloc_array((size_t)force_count, sizeof(hk_Vec3), err);
        d->anchor_vel = hk_alloc_array((size_t)force_count, sizeof(hk_Vec3), err);
        if (!d->anchor_pos || !d->anchor_vel) return HK_ERR_NOMEM;
        d->anchor_capacity = force_count;
    }
    if (force_count == 0) return HK_OK;
    double s_buf[64], *s = force_count <= 64 ? s_buf : hk_alloc_array((size_t)force_count, sizeof(double), err);
    if (!s) return HK_ERR_NOMEM;
    for (int i = 0; i < force_count; i++) s[i] = forces[i].s;
    hk_strand_dynamics_points(d, head, s, force_count, d->anchor_pos, d->anchor_vel);
    if (s != s_buf) hk_free(s);
    return HK_OK;
}

void hk_strand_dynamics_energy(hk_StrandDynamics *d, const hk_RigidState *head, double *kinetic, double *potential)
{
    const hk_RigidState still = hk_rigid_identity();
    if (!head) head = &still;
    hk_SuperHelix *sh = d->sh;
    hk_strand_dynamics_place(d, head);
    if (potential) *potential = hk_strand_energy(sh, &d->potential_env, sh->q, d->ws, NULL, NULL, NULL);
    if (!kinetic) return;
    /* T = 1/2 int (rho S |r'|^2 + w . I w) ds (eq. 5b plus the section's rotation). */
    double t = 0.0;
    hk_FrameKinematics node = hk_dynamics_root_kinematics(d, head);
    for (int p = 0; p < sh->n; p++) {
        const hk_Vec3 k = k_of(sh->q, p), kd = k_of(d->v, p);
        const int g = gauss_count(d, p);
        for (int i = 0; i < g; i++) {
            const double u = sh->length[p] * d->gauss.node[g - 1][i];
            const double w = sh->length[p] * d->gauss.weight[g - 1][i];
            hk_FrameKinematics pk;
            hk_point_motion(&node, k, kd, u, &pk);
            const hk_Mat3 b = rotary_inertia(&sh->material, &pk.frame, w);
            t += 0.5 * (w * sh->material.mass_per_length * hk_v3_norm2(pk.vel) +
                        hk_v3_dot(pk.omega, hk_m3_mul_v3(&b, pk.omega)));
        }
        hk_FrameKinematics end;
        hk_point_motion(&node, k, kd, sh->length[p], &end);
        node = end;
    }
    *kinetic = t;
}

void hk_strand_dynamics_points(hk_StrandDynamics *d, const hk_RigidState *head, const double *s, int count,
                               hk_Vec3 *pos, hk_Vec3 *vel)
{
    HK_AVX_TWIN_CALL(hk_strand_dynamics_points, d, head, s, count, pos, vel);
    const hk_RigidState still = hk_rigid_identity();
    if (!head) head = &still;
    hk_SuperHelix *sh = d->sh;
    hk_strand_dynamics_place(d, head);
    hk_FrameKinematics node = hk_dynamics_root_kinematics(d, head);
    int p = 0;
    for (int i = 0; i < count; i++) {
        double si = s[i];
        while (p < sh->n - 1 && si >= sh->s_start[p + 1]) {
            hk_FrameKinematics end;
            hk_point_motion(&node, k_of(sh->q, p), k_of(d->v, p), sh->length[p], &end);
            node = end;
            p++;
        }
        /* with the next point when it lies in the same element: two at a time */
        const int pair = i + 1 < count && !(p < sh->n - 1 && s[i + 1] >= sh->s_start[p + 1]);
        double u[2];
        for (int j = 0; j <= pair; j++) {
            u[j] = s[i + j] - sh->s_start[p];
            if (!(u[j] >= 0.0)) u[j] = 0.0;
            if (u[j] > sh->length[p]) u[j] = sh->length[p];
        }
        if (pair)
            hk_point_velocity2(&node, k_of(sh->q, p), k_of(d->v, p), u, &pos[i], vel ? &vel[i] : NULL);
        else
            hk_point_velocity(&node, k_of(sh->q, p), k_of(d->v, p), u[0], &pos[i], vel ? &vel[i] : NULL);
        i += pair;
    }
}

hk_Status hk_strand_dynamics_mass_matrix(hk_StrandDynamics *d, double *mass, hk_Error *err)
{
    double *scratch = hk_alloc_array(HK_ASSEMBLE_WORK(d->sh->n), sizeof(double), err);
    if (!scratch) return HK_ERR_NOMEM;
    const hk_RigidState still = hk_rigid_identity();
    hk_strand_dynamics_place(d, &still);
    sweep(d, &still, NULL, 0, 0.0, NULL, SWEEP_MASS);
    hk_terms_assemble(d->sh->n, d->terms, mass, scratch);
    hk_free(scratch);
    return HK_OK;
}
