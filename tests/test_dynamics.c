/* Building blocks of the Super-Helix dynamics, each against an independent reference:
 *  - Gauss-Legendre rules integrate polynomials of degree 2n - 1 exactly (analytic);
 *  - velocities and bias accelerations of a point equal finite differences in time of
 *    the closed-form reconstruction under a known motion;
 *  - the mass matrix gives back the kinetic energy computed from point velocities
 *    (1/2 v^T M v = T for any v), is symmetric and positive definite;
 *  - the O(N) recursion and the dense Cholesky solve the same step to rounding;
 *  - body friction follows the cosine blend of paper 000 §4.2 and never pushes;
 *  - the positive part's AVX and SSE2 paths give a strand's steps the same bytes. */
#include "hk_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"
#include "dynamics/dynamics_internal.h"
#include "hairkit/dynamics.h"
#include "hairkit/motion.h"
#include "rod/helix_local.h"

static double rnd(double lo, double hi) { return lo + (hi - lo) * hk_test_uniform(); }

/* A vector of three draws in [lo, hi) made in a fixed order. The order in which a
 * function's arguments are evaluated is unspecified in C (gcc goes right to left, clang
 * left to right), so hk_v3(rnd(), rnd(), rnd()) gave each compiler another scenario:
 * z first, as gcc drew them, so that the scenarios stay those the tests were written
 * on. */
static hk_Vec3 rnd3(double lo, double hi)
{
    const double z = rnd(lo, hi), y = rnd(lo, hi), x = rnd(lo, hi);
    return hk_v3(x, y, z);
}

static void test_gauss_rules_exact(void **state)
{
    (void)state;
    hk_GaussTable t;
    hk_gauss_table_init(&t);
    for (int n = 1; n <= HK_GAUSS_MAX; n++) {
        for (int deg = 0; deg <= 2 * n - 1; deg++) {
            double sum = 0.0;
            for (int i = 0; i < n; i++) sum += t.weight[n - 1][i] * pow(t.node[n - 1][i], deg);
            hk_assert_near(sum, 1.0 / (deg + 1), 1e-14);
        }
        if (n <= 8) { /* not degree 2n: the error (n!)^4 / ((2n+1) ((2n)!)^2) >= 3.6e-10 */
            double sum = 0.0;
            for (int i = 0; i < n; i++) sum += t.weight[n - 1][i] * pow(t.node[n - 1][i], 2 * n);
            assert_true(fabs(sum - 1.0 / (2 * n + 1)) > 1e-10);
        }
    }
}

static hk_Mat3 axis_rotation(hk_Vec3 axis, double angle)
{
    double c[HK_CN_COUNT];
    const hk_Vec3 phi = hk_v3_scale(axis, angle);
    hk_helix_cn(hk_v3_norm2(phi), c);
    return hk_helix_rotation(c, phi);
}

/* A start frame turning about z by a(t) and then about its own x by b(t), with
 * quadratic angles and a quadratic translation: exact pose, angular velocity and
 * angular acceleration at any t. */
typedef struct Motion {
    double a1, a2, b1, b2; /* a(t) = a1 t + a2 t^2 / 2, b likewise */
    hk_Vec3 p0, v0, acc0;
    hk_Mat3 f0;
} Motion;

static hk_FrameKinematics motion_at(const Motion *m, double t)
{
    const hk_Vec3 ez = hk_v3(0, 0, 1), ex = hk_v3(1, 0, 0);
    const double a = m->a1 * t + 0.5 * m->a2 * t * t, ad = m->a1 + m->a2 * t, add = m->a2;
    const double b = m->b1 * t + 0.5 * m->b2 * t * t, bd = m->b1 + m->b2 * t, bdd = m->b2;
    const hk_Mat3 rz = axis_rotation(ez, a), rx = axis_rotation(ex, b);
    const hk_Mat3 rzx = hk_m3_mul(&rz, &rx);
    hk_FrameKinematics k;
    k.frame = hk_m3_mul(&rzx, &m->f0);
    const hk_Vec3 ex_w = hk_m3_mul_v3(&rz, ex);
    k.omega = hk_v3_add(hk_v3_scale(ez, ad), hk_v3_scale(ex_w, bd));
    k.alpha =
        hk_v3_add(hk_v3_add(hk_v3_scale(ez, add), hk_v3_scale(ex_w, bdd)), hk_v3_scale(hk_v3_cross(ez, ex_w), ad * bd));
    k.pos = hk_v3_add(m->p0, hk_v3_add(hk_v3_scale(m->v0, t), hk_v3_scale(m->acc0, 0.5 * t * t)));
    k.vel = hk_v3_add(m->v0, hk_v3_scale(m->acc0, t));
    k.acc = m->acc0;
    return k;
}

static void test_point_kinematics_match_finite_differences(void **state)
{
    (void)state;
    for (int trial = 0; trial < 20; trial++) {
        Motion m; /* drawn one by one: see rnd3 */
        m.a1 = rnd(-3, 3), m.a2 = rnd(-20, 20), m.b1 = rnd(-3, 3), m.b2 = rnd(-20, 20);
        m.p0 = rnd3(-1, 1), m.v0 = rnd3(-1, 1), m.acc0 = rnd3(-5, 5);
        const double angle = rnd(0, 3), ay = rnd(-1, 1), ax = rnd(-1, 1);
        m.f0 = axis_rotation(hk_v3_normalize(hk_v3(ax, ay, 1)), angle);
        /* Curvatures from straight (series branch) to curly; rates of 1..100 / (m s). */
        const double scale = trial < 4 ? 1e-7 : 300.0;
        const hk_Vec3 k0 = hk_v3_scale(rnd3(-1, 1), scale);
        const hk_Vec3 kd = rnd3(-100, 100);
        const double u = rnd(0.001, 0.03), h = 1e-4;
        hk_PointKinematics at[3];
        for (int j = 0; j < 3; j++) {
            const double t = (j - 1) * h;
            const hk_FrameKinematics start = motion_at(&m, t);
            hk_point_kinematics(&start, hk_v3_madd(k0, kd, t), kd, u, 2, &at[j]);
        }
        const hk_PointKinematics *c = &at[1];
        /* velocity = d pos / dt, bias acceleration = d2 pos / dt2 (k'' = 0) */
        const hk_Vec3 vel = hk_v3_scale(hk_v3_sub(at[2].k.pos, at[0].k.pos), 0.5 / h);
        const hk_Vec3 acc =
            hk_v3_scale(hk_v3_add(hk_v3_sub(at[2].k.pos, hk_v3_scale(c->k.pos, 2.0)), at[0].k.pos), 1.0 / (h * h));
        const double vs = hk_v3_norm(c->k.vel) + 1e-3, as = hk_v3_norm(c->k.acc) + 1.0;
        hk_assert_near(hk_v3_dist(vel, c->k.vel) / vs, 0.0, 1e-6);
        hk_assert_near(hk_v3_dist(acc, c->k.acc) / as, 0.0, 1e-4);
        /* also d vel / dt */
        const hk_Vec3 acc2 = hk_v3_scale(hk_v3_sub(at[2].k.vel, at[0].k.vel), 0.5 / h);
        hk_assert_near(hk_v3_dist(acc2, c->k.acc) / as, 0.0, 1e-6);
        /* angular velocity from the frames: (R+ R-^T - R- R+^T) / (4 h) = [w]x */
        const hk_Mat3 rmt = hk_m3_transpose(&at[0].k.frame);
        const hk_Mat3 dr = hk_m3_mul(&at[2].k.frame, &rmt);
        const hk_Vec3 w =
            hk_v3_scale(hk_v3(dr.m[2][1] - dr.m[1][2], dr.m[0][2] - dr.m[2][0], dr.m[1][0] - dr.m[0][1]), 0.25 / h);
        const double ws = hk_v3_norm(c->k.omega) + 1e-3;
        hk_assert_near(hk_v3_dist(w, c->k.omega) / ws, 0.0, 1e-6);
        /* bias angular acceleration = d w / dt */
        const hk_Vec3 al = hk_v3_scale(hk_v3_sub(at[2].k.omega, at[0].k.omega), 0.5 / h);
        hk_assert_near(hk_v3_dist(al, c->k.alpha) / (hk_v3_norm(c->k.alpha) + 1.0), 0.0, 1e-6);
        /* Jacobians: a change of k moves the point by jac dk and turns it by jac_rot dk */
        for (int b = 0; b < 3; b++) {
            /* central differences of the offset (magnitude u): truncation e^2 u^4,
             * rounding u eps / e, both far below 1e-9 u */
            const double e = 1e-4;
            hk_Vec3 kp = k0, km = k0;
            hk_v3_set(&kp, b, hk_v3_get(k0, b) + e);
            hk_v3_set(&km, b, hk_v3_get(k0, b) - e);
            const hk_FrameKinematics start = motion_at(&m, 0.0);
            hk_PointKinematics pp, pm;
            hk_point_kinematics(&start, kp, kd, u, 1, &pp);
            hk_point_kinematics(&start, km, kd, u, 1, &pm);
            const hk_Vec3 op = hk_v3_sub(pp.k.pos, start.pos), om = hk_v3_sub(pm.k.pos, start.pos);
            const hk_Vec3 dp = hk_v3_scale(hk_v3_sub(op, om), 0.5 / e);
            hk_assert_near(hk_v3_dist(dp, hk_m3_col(&c->jac, b)), 0.0, 1e-9 * u);
        }
        /* The point-only paths give the full paths' position, velocity and Jacobian bit
         * for bit (the contacts' points and the detection's samples use them). */
        const hk_FrameKinematics start = motion_at(&m, 0.0);
        hk_PointKinematics full;
        hk_FrameKinematics motion;
        hk_point_kinematics(&start, k0, kd, u, 1, &full);
        hk_point_motion(&start, k0, kd, u, &motion);
        hk_Vec3 pos, pvel, pos2, vel2;
        hk_Mat3 jac;
        hk_point_jacobian(&start, k0, kd, u, &pos, &pvel, &jac);
        hk_point_velocity(&start, k0, kd, u, &pos2, &vel2);
        for (int i = 0; i < 3; i++) {
            hk_assert_near(hk_v3_get(pos, i), hk_v3_get(full.k.pos, i), 0.0);
            hk_assert_near(hk_v3_get(pvel, i), hk_v3_get(full.k.vel, i), 0.0);
            hk_assert_near(hk_v3_get(pos2, i), hk_v3_get(motion.pos, i), 0.0);
            hk_assert_near(hk_v3_get(vel2, i), hk_v3_get(motion.vel, i), 0.0);
            for (int j = 0; j < 3; j++) hk_assert_near(jac.m[i][j], full.jac.m[i][j], 0.0);
        }
    }
}

/* A curly strand of n elements over 12 cm with random coordinates. */
static hk_SuperHelix *curly_strand(int n)
{
    double len[32];
    for (int i = 0; i < n; i++) len[i] = 0.12 / n * (0.7 + 0.6 * hk_test_uniform());
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, len, &sh, &err), HK_OK);
    sh->material = hk_rod_material(5e-5, 4e-5, 1.5e9, 0.48, 1300.0, hk_v3(0, -9.81, 0));
    sh->root = hk_v3(0.01, 0.1, 0.02);
    sh->root_frame = hk_root_frame(hk_v3(0.3, 1.0, 0.2));
    for (int i = 0; i < 3 * n; i++) {
        sh->q_rest[i] = rnd(-1, 1) * 60.0;
        sh->q[i] = sh->q_rest[i] + rnd(-1, 1) * 20.0;
    }
    return sh;
}

static void test_mass_matrix_gives_kinetic_energy(void **state)
{
    (void)state;
    const int n = 6, dim = 3 * n;
    hk_SuperHelix *sh = curly_strand(n);
    hk_DynamicsDef prm = hk_default_dynamics_def();
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &prm, NULL, &d, &err), HK_OK);
    double *mass = malloc(sizeof(double) * dim * dim);
    assert_int_equal(hk_strand_dynamics_mass_matrix(d, mass, &err), HK_OK);
    for (int i = 0; i < dim; i++)
        for (int j = 0; j < dim; j++)
            hk_assert_near(mass[i * dim + j], mass[j * dim + i], 1e-14 * fabs(mass[i * dim + i]));
    double *v = hk_strand_dynamics_velocity(d);
    for (int trial = 0; trial < 10; trial++) {
        for (int i = 0; i < dim; i++) v[i] = rnd(-1, 1) * (trial == 0 ? (i % 3 == 0) : 50.0);
        double t = 0.0, quad = 0.0;
        hk_strand_dynamics_energy(d, NULL, &t, NULL);
        for (int i = 0; i < dim; i++)
            for (int j = 0; j < dim; j++) quad += 0.5 * v[i] * mass[i * dim + j] * v[j];
        assert_true(t > 0.0); /* positive definite, even for pure twist (trial 0) */
        hk_assert_rel(quad, t, 1e-11, 0.0);
    }
    free(mass);
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
}

static void test_linear_and_dense_agree(void **state)
{
    (void)state;
    const int n = 9, dim = 3 * n;
    hk_SuperHelix *a = curly_strand(n);
    hk_SuperHelix *b = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, a->length, &b, &err), HK_OK);
    b->material = a->material;
    b->root = a->root;
    b->root_frame = a->root_frame;
    memcpy(b->q, a->q, sizeof(double) * dim);
    memcpy(b->q_rest, a->q_rest, sizeof(double) * dim);
    /* A sphere the strand dips into, so that body contacts and friction take part. */
    hk_Vec3 mid;
    hk_superhelix_eval(a, NULL, 0.6 * a->total_length, &mid, NULL);
    hk_Shape sphere = hk_shape_sphere(hk_v3_add(mid, hk_v3(0.0, -0.02, 0.0)), 0.025, 0.0, 10.0);
    hk_StrandEnvDef body = {&sphere, 1, 0.0, 0.004};
    /* The same scheme for both: the stiffness the O(N) recursion can carry. */
    hk_DynamicsDef pl = hk_default_dynamics_def(), pd = pl;
    /* one linear solve per step: the solvers' difference is not hidden by Newton's
     * iteration converging to the same stage solution */
    pl.integrator = pd.integrator = HK_INTEGRATOR_LINEAR_EULER;
    pl.solver = HK_DYNAMICS_LINEAR;
    pl.stiffness = pd.stiffness = HK_STIFFNESS_GAUSS_NEWTON;
    pd.solver = HK_DYNAMICS_DENSE;
    hk_StrandDynamics *dl = NULL, *dd = NULL;
    assert_int_equal(hk_strand_dynamics_create(a, &pl, &body, &dl, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_create(b, &pd, &body, &dd, &err), HK_OK);
    for (int i = 0; i < dim; i++)
        hk_strand_dynamics_velocity(dl)[i] = hk_strand_dynamics_velocity(dd)[i] = rnd(-30, 30);
    hk_RigidState head = hk_rigid_identity();
    head.omega = hk_v3(0.5, -1.0, 2.0);
    head.alpha = hk_v3(3.0, 1.0, -2.0);
    head.vel = hk_v3(0.1, 0.2, -0.1);
    head.acc = hk_v3(-1.0, 2.0, 0.5);
    hk_PointForce pf[3];
    for (int i = 0; i < 3; i++) {
        pf[i].s = a->total_length * (0.2 + 0.3 * i);
        pf[i].force = hk_v3_scale(rnd3(-1, 1), 1e-4);
        const hk_Vec3 nrm = hk_v3_normalize(rnd3(-1, 1));
        const hk_Mat3 o = hk_m3_outer(nrm, nrm);
        pf[i].stiffness = hk_m3_scale(&o, 0.5);
        pf[i].damping = hk_m3_scale(&o, 1e-3);
    }
    /* The step's matrix is badly conditioned (the twist's rotary inertia rho J l ~ 1e-16
     * and the bending dt^2 K l ~ 1e-13 against translational terms ~ 1e-9: a condition
     * number near 1e8), so two correct factorisations differ by up to about cond * eps
     * ~ 1e-8 relative; a wrong recursion differs at O(1). The backward error of the
     * recursion alone is checked tightly in test_linear_solve_residual. */
    for (int step = 0; step < 5; step++) {
        assert_int_equal(hk_strand_dynamics_step(dl, &head, pf, 3, 1.0 / 30, &err), HK_OK);
        assert_int_equal(hk_strand_dynamics_step(dd, &head, pf, 3, 1.0 / 30, &err), HK_OK);
        for (int i = 0; i < dim; i++) {
            const double va = hk_strand_dynamics_velocity(dl)[i], vb = hk_strand_dynamics_velocity(dd)[i];
            hk_assert_near(va, vb, 1e-6 * (fabs(vb) + 1.0));
            hk_assert_near(a->q[i], b->q[i], 1e-7 * (fabs(b->q[i]) + 1.0));
        }
    }
    assert_true(hk_strand_dynamics_contact_count(dl) > 0);
    assert_int_equal(hk_strand_dynamics_contact_count(dl), hk_strand_dynamics_contact_count(dd));
    hk_strand_dynamics_destroy(dl);
    hk_strand_dynamics_destroy(dd);
    hk_superhelix_destroy(a);
    hk_superhelix_destroy(b);
}

/* Random element terms built from random points (so that the matrix they describe is
 * a sum of J^T A J, positive semi-definite) with random screws: the O(N) solution
 * satisfies the densely assembled system to a backward error of rounding. */
static void test_linear_solve_residual(void **state)
{
    (void)state;
    enum { N = 12, DIM = 3 * N };
    hk_ElementTerms terms[N];
    memset(terms, 0, sizeof terms);
    for (int p = 0; p < N; p++) {
        for (int i = 0; i < 4; i++) {
            hk_Mat3 a = hk_m3_zero(), b = hk_m3_zero(), jac, jrot;
            for (int r = 0; r < 3; r++) {
                const hk_Vec3 v = rnd3(-1, 1), w = rnd3(-1, 1);
                const hk_Mat3 vv = hk_m3_outer(v, v), ww = hk_m3_outer(w, w);
                a = hk_m3_add(&a, &vv);
                b = hk_m3_add(&b, &ww);
                for (int c = 0; c < 3; c++) {
                    jac.m[r][c] = rnd(-1, 1);
                    jrot.m[r][c] = rnd(-1, 1);
                }
            }
            hk_element_terms_add(&terms[p], rnd3(-1, 1), &a, &b, &jac, &jrot, hk_v3_zero(), hk_v3_zero());
        }
        for (int b = 0; b < 3; b++)
            for (int i = 0; i < 6; i++) terms[p].xi[b][i] = rnd(-1, 1);
    }
    double extra[DIM], rhs[DIM], x[DIM], work[21 * N], mass[DIM * DIM], prod[DIM];
    for (int i = 0; i < DIM; i++) {
        extra[i] = rnd(0.01, 0.1);
        rhs[i] = rnd(-1, 1);
    }
    assert_int_equal(hk_terms_solve_linear(N, terms, extra, rhs, x, work), 1);
    hk_terms_assemble(N, terms, mass, work);
    /* the O(N) product agrees with the assembled matrix */
    hk_terms_multiply(N, terms, extra, rhs, prod, work);
    for (int i = 0; i < DIM; i++) {
        double r = extra[i] * rhs[i], scale = fabs(extra[i] * rhs[i]);
        for (int j = 0; j < DIM; j++) {
            r += mass[i * DIM + j] * rhs[j];
            scale += fabs(mass[i * DIM + j] * rhs[j]);
        }
        hk_assert_near(prod[i], r, 1e-13 * scale);
    }
    double rnorm = 0.0, bnorm = 0.0;
    for (int i = 0; i < DIM; i++) {
        double r = extra[i] * x[i] - rhs[i];
        for (int j = 0; j < DIM; j++) r += mass[i * DIM + j] * x[j];
        rnorm += r * r;
        bnorm += rhs[i] * rhs[i];
    }
    assert_true(sqrt(rnorm) <= 1e-11 * sqrt(bnorm));
}

/* The dense solve's factor A = U U^T (hk_upper_cholesky) is Cholesky's factorisation
 * of the reversed matrix read backwards, to the bit (the contacts' solve relies on its
 * rows stopping at a point's element, the step's own solve on the same factor), with
 * U^T in its strict lower part and the reciprocals of its diagonal after it, and
 * hk_upper_solve solves with it, hk_upper_transpose_solve its U^T to the bit of the
 * column sums times those reciprocals; sizes with every remainder of the four partial
 * sums. */
static void upper_cholesky_is_the_reversed_factor(void)
{
    enum { MAX = 33 };
    for (int n = 1; n <= MAX; n++) {
        const size_t sn = (size_t)n, count = sn * sn;
        double b[MAX * MAX], a[MAX * MAX], rev[MAX * MAX], u[MAX * MAX + MAX], extra[MAX], rextra[MAX];
        double x[MAX], rhs[MAX];
        for (size_t k = 0; k < count; k++) b[k] = rnd(-1, 1);
        for (size_t i = 0; i < sn; i++) /* B B^T: positive semi-definite, symmetric to the bit */
            for (size_t j = 0; j <= i; j++) {
                double v = 0.0;
                for (size_t k = 0; k < sn; k++) v += b[i * sn + k] * b[j * sn + k];
                a[i * sn + j] = a[j * sn + i] = v;
            }
        for (int j = 0; j < n; j++) extra[j] = rnd(0.01, 0.1), rhs[j] = x[j] = rnd(-1, 1);
        for (size_t k = 0; k < count; k++) rev[k] = a[count - 1 - k];
        for (int j = 0; j < n; j++) rextra[j] = extra[n - 1 - j];
        assert_int_equal(hk_cholesky_factor(n, rev, 1.0, rextra, rev), 1);
        assert_int_equal(hk_upper_cholesky(n, a, extra, u), 1);
        for (size_t i = 0; i < sn; i++)
            for (size_t j = i; j < sn; j++) {
                assert_memory_equal(&u[i * sn + j], &rev[count - 1 - (i * sn + j)], sizeof(double));
                assert_memory_equal(&u[j * sn + i], &u[i * sn + j], sizeof(double)); /* U^T below */
            }
        for (size_t i = 0; i < sn; i++) { /* then the diagonal's reciprocals */
            const double inverse = 1.0 / u[i * sn + i];
            assert_memory_equal(&u[count + i], &inverse, sizeof(double));
        }
        /* only the lower triangle is read: the same factor with the strict upper one
         * not a number, in place (u may be a) */
        double lower[MAX * MAX + MAX];
        memcpy(lower, a, count * sizeof(double));
        for (size_t i = 0; i < sn; i++)
            for (size_t j = i + 1; j < sn; j++) lower[i * sn + j] = NAN;
        assert_int_equal(hk_upper_cholesky(n, lower, extra, lower), 1);
        assert_memory_equal(lower, u, HK_UPPER_FACTOR_SIZE(n) * sizeof(double));
        /* U^T y = rhs by U's rows, to the bit of the sum down each column (the contacts'
         * solve finishes a strand so) */
        double y[MAX], want[MAX];
        memcpy(y, rhs, sn * sizeof(double));
        hk_upper_transpose_solve(n, u, y);
        for (size_t i = 0; i < sn; i++) {
            double v = rhs[i];
            for (size_t k = 0; k < i; k++) v -= u[k * sn + i] * want[k];
            want[i] = v * (1.0 / u[i * sn + i]);
        }
        assert_memory_equal(y, want, sn * sizeof(double));
        hk_upper_solve(n, u, x);
        double rnorm = 0.0, bnorm = 0.0;
        for (size_t i = 0; i < sn; i++) {
            double r = extra[i] * x[i] - rhs[i];
            for (size_t j = 0; j < sn; j++) r += a[i * sn + j] * x[j];
            rnorm += r * r, bnorm += rhs[i] * rhs[i];
        }
        assert_true(sqrt(rnorm) <= 1e-9 * sqrt(bnorm));
    }
    double indefinite[4] = {1.0, 2.0, 2.0, 1.0}, f[6], none[2] = {0.0, 0.0};
    assert_int_equal(hk_upper_cholesky(2, indefinite, none, f), 0);
}

/* Both paths, AVX's where the CPU has it and the baseline's, on every size from 1 (the
 * column's rows taken two at a time leave an odd one in every other column). */
static void test_upper_cholesky_is_the_reversed_factor(void **state)
{
    (void)state;
    if (hk_avx_paths_allow(1)) upper_cholesky_is_the_reversed_factor();
    hk_avx_paths_allow(0);
    upper_cholesky_is_the_reversed_factor();
    hk_avx_paths_allow(1);
}

/* Gauss-Newton stiffness of a point inside two overlapping shapes, a stiff sphere and a
 * soft one with a wide envelope (the head and the styling sphere before the face): it
 * is the sum over the shapes, w sum_i k_i n_i n_i^T with n_i the spheres' unit normals
 * (dent = r - |p - c|, so grad(dent) = -n), not w g g^T / (2 e) of the summed energy
 * and gradient, which was 3.5 times too soft there and made Newton's iteration of
 * TR-BDF2 diverge on the guides before the face. */
static void test_body_stiffness_of_overlapping_shapes(void **state)
{
    (void)state;
    const hk_Shape shapes[2] = {hk_shape_sphere(hk_v3(0.0, 0.0, 0.0), 0.1, 0.0, 10.0),
                                hk_shape_sphere(hk_v3(0.0, 0.05, 0.15), 0.095, 0.05, 0.01)};
    const double alpha = 0.9, weight = 0.005;
    hk_BodyContact bc = {shapes, 2, alpha, weight, 0.2, 0.4, 0.05};
    const hk_RigidState head = hk_rigid_identity();
    const hk_Vec3 p = hk_v3(0.01, 0.03, 0.0935); /* 0.8 mm into the stiff sphere */
    hk_PointForce pf;
    assert_int_equal(hk_body_contact_force(&bc, &head, p, hk_v3_zero(), hk_v3(1, 0, 0), &pf), 1);
    hk_Mat3 want = hk_m3_zero();
    int touching = 0;
    for (int i = 0; i < 2; i++) {
        const hk_Vec3 d = hk_v3_sub(p, shapes[i].centre);
        const double dent = shapes[i].half.x - hk_v3_norm(d) + alpha * shapes[i].volume;
        if (!(dent > 0.0)) continue;
        touching++;
        const hk_Vec3 n = hk_v3_normalize(d);
        const hk_Mat3 nn = hk_m3_outer(n, n);
        const hk_Mat3 ki = hk_m3_scale(&nn, weight * shapes[i].penalty);
        want = hk_m3_add(&want, &ki);
    }
    assert_int_equal(touching, 2);
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            hk_assert_near(pf.stiffness.m[r][c], want.m[r][c], 1e-12 + 1e-9 * fabs(want.m[r][c]));
}

static void test_body_friction_blend(void **state)
{
    (void)state;
    /* A floor: a large cuboid below y = 0, the hair along +x touching it. */
    const hk_Vec3 axes[3] = {hk_v3(1, 0, 0), hk_v3(0, 1, 0), hk_v3(0, 0, 1)};
    hk_Shape floor = hk_shape_cuboid(hk_v3(0, -1, 0), hk_v3(2, 1, 2), axes, 0.0, 1e4);
    hk_BodyContact bc = {&floor, 1, 0.0, 0.01, 0.2, 0.6, 0.05};
    const hk_RigidState still = hk_rigid_identity();
    const hk_Vec3 pos = hk_v3(0, -0.001, 0), tangent = hk_v3(1, 0, 0);
    hk_PointForce pf;
    /* at rest: only the normal force, up, of w k dent */
    assert_int_equal(hk_body_contact_force(&bc, &still, pos, hk_v3_zero(), tangent, &pf), 1);
    hk_assert_rel(pf.force.y, 0.01 * 1e4 * 0.001, 1e-12, 0.0);
    hk_assert_near(pf.force.x, 0.0, 1e-15);
    const double fn = pf.force.y;
    /* sliding fast (Coulomb regime): tip first = against the scales, root first = with
     * them, sideways = the mean (cos = 0) */
    const struct {
        hk_Vec3 v;
        double mu;
    } cases[] = {{hk_v3(1, 0, 0), 0.6},
                 {hk_v3(-1, 0, 0), 0.2},
                 {hk_v3(0, 0, 1), 0.4},
                 {hk_v3(0.5, 0, 0.5), 0.4 + 0.2 * sqrt(0.5)}};
    for (int i = 0; i < 4; i++) {
        assert_int_equal(hk_body_contact_force(&bc, &still, pos, cases[i].v, tangent, &pf), 1);
        const hk_Vec3 ft = hk_v3(pf.force.x, 0.0, pf.force.z);
        hk_assert_rel(hk_v3_norm(ft), cases[i].mu * fn, 1e-12, 0.0);
        assert_true(hk_v3_dot(ft, cases[i].v) < 0.0); /* opposes the sliding */
        hk_assert_rel(pf.force.y, fn, 1e-12, 0.0);
    }
    /* slow sliding: viscous, proportional to the speed */
    assert_int_equal(hk_body_contact_force(&bc, &still, pos, hk_v3(-0.01, 0, 0), tangent, &pf), 1);
    hk_assert_rel(pf.force.x, 0.2 * fn * 0.01 / 0.05, 1e-12, 0.0);
    /* the body moves with the hair: no sliding, no friction */
    hk_RigidState moving = still;
    moving.vel = hk_v3(0.3, 0, 0);
    assert_int_equal(hk_body_contact_force(&bc, &moving, pos, hk_v3(0.3, 0, 0), tangent, &pf), 1);
    hk_assert_near(pf.force.x, 0.0, 1e-15);
    /* out of contact: nothing */
    assert_int_equal(hk_body_contact_force(&bc, &still, hk_v3(0, 0.001, 0), hk_v3_zero(), tangent, &pf), 0);
    /* The friction alone from the penalty's gradient (the full stiffness, whose normal
     * force is in the potential): the same friction and damping, no normal force and
     * no stiffness. The sample's penalty energy w k dent^2 / 2 has the gradient
     * -w k dent along y. */
    const hk_Vec3 grad = hk_v3(0.0, -fn, 0.0);
    for (int i = 0; i < 4; i++) {
        hk_PointForce alone;
        assert_int_equal(hk_body_contact_force(&bc, &still, pos, cases[i].v, tangent, &pf), 1);
        assert_int_equal(hk_body_contact_friction(&bc, &still, pos, cases[i].v, tangent, grad, &alone), 1);
        hk_assert_near(hk_v3_dist(alone.force, hk_v3_sub(pf.force, hk_v3(0.0, fn, 0.0))), 0.0, 1e-15);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                hk_assert_near(alone.damping.m[r][c], pf.damping.m[r][c], 1e-15);
                hk_assert_near(alone.stiffness.m[r][c], 0.0, 0.0);
            }
    }
    assert_int_equal(hk_body_contact_friction(&bc, &still, pos, hk_v3(1, 0, 0), tangent, hk_v3_zero(), &pf), 0);
}

/* The two-point paths of the sweeps (two offsets of one element at once, two lanes of
 * vector arithmetic) against the one-point ones, bit for bit, and so the two Gauss
 * points' sums into the element's terms; and an end from its known pose
 * (hk_end_kinematics) against the whole kinematics. */
static void test_point_pairs_bit_for_bit(void **state)
{
    (void)state;
    hk_FrameKinematics start;
    start.frame = hk_root_frame(hk_v3(0.3, -0.5, 0.8));
    start.pos = hk_v3(0.01, 0.12, -0.03);
    start.omega = hk_v3(2.0, -1.0, 0.5);
    start.vel = hk_v3(0.3, 0.1, -0.2);
    start.alpha = hk_v3(-7.0, 3.0, 11.0);
    start.acc = hk_v3(1.0, -9.81, 0.4);
    const hk_Vec3 ks[] = {{0, 0, 0}, {30, -80, 12}, {200, 150, -90}};
    const hk_Vec3 kd = {-40, 25, 10};
    const double u[2] = {0.0043, 0.0191};
    for (size_t t = 0; t < sizeof ks / sizeof *ks; t++) {
        hk_PointKinematics pair[2], one;
        hk_point_kinematics2(&start, ks[t], kd, u, pair);
        hk_Vec3 pos[2], vel[2], jpos[2], jvel[2];
        hk_Mat3 jac[2];
        hk_point_velocity2(&start, ks[t], kd, u, pos, vel);
        hk_point_jacobian2(&start, ks[t], kd, u, jpos, jvel, jac);
        for (int l = 0; l < 2; l++) {
            hk_point_kinematics(&start, ks[t], kd, u[l], 2, &one);
            assert_true(memcmp(&pair[l], &one, sizeof one) == 0);
            hk_Vec3 p1, v1;
            hk_Mat3 j1;
            hk_point_velocity(&start, ks[t], kd, u[l], &p1, &v1);
            assert_true(memcmp(&pos[l], &p1, sizeof p1) == 0 && memcmp(&vel[l], &v1, sizeof v1) == 0);
            hk_point_jacobian(&start, ks[t], kd, u[l], &p1, &v1, &j1);
            assert_true(memcmp(&jpos[l], &p1, sizeof p1) == 0 && memcmp(&jvel[l], &v1, sizeof v1) == 0);
            assert_true(memcmp(&jac[l], &j1, sizeof j1) == 0);
            /* a body contact's pair: order 1's position, velocity, Jacobian, tangent */
            hk_PointKinematics contact[2], first;
            hk_point_contact2(&start, ks[t], kd, u, contact);
            hk_point_kinematics(&start, ks[t], kd, u[l], 1, &first);
            const hk_Vec3 n0 = hk_m3_col(&contact[l].k.frame, 0), n1 = hk_m3_col(&first.k.frame, 0);
            assert_true(memcmp(&contact[l].k.pos, &first.k.pos, sizeof(hk_Vec3)) == 0);
            assert_true(memcmp(&contact[l].k.vel, &first.k.vel, sizeof(hk_Vec3)) == 0);
            assert_true(memcmp(&contact[l].jac, &first.jac, sizeof(hk_Mat3)) == 0);
            assert_true(memcmp(&n0, &n1, sizeof n0) == 0);
            /* an element's end taken from the pose that the sweep (order 2, rates kd)
             * found, with other rates (the contacts' free velocity): order 1's bits */
            const hk_EndPose pose = {pair[l].k.frame, pair[l].jac, pair[l].jac_rot, pair[l].k.pos};
            const hk_Vec3 other = {15, -60, 35};
            hk_PointKinematics reused, fresh;
            hk_end_kinematics(&start, &pose, other, &reused);
            hk_point_kinematics(&start, ks[t], other, u[l], 1, &fresh);
            assert_true(memcmp(&reused, &fresh, sizeof fresh) == 0);
        }
        /* the pair's quadrature terms into an element's sums that already hold some
         * (their signs mixed), against the same two points added one at a time */
        hk_ElementTerms lanes, alone;
        double *sums = &lanes.xi[0][0];
        for (size_t i = 0; i < sizeof lanes / sizeof(double); i++) sums[i] = 1e-3 * (double)(i % 7) - 2e-3;
        alone = lanes;
        const double a[2] = {3.1e-4, 7.3e-5};
        const hk_Mat3 b[2] = {{{{2e-9, 1e-10, -3e-10}, {1e-10, 5e-9, 2e-10}, {-3e-10, 2e-10, 4e-9}}},
                              {{{7e-9, -2e-10, 1e-10}, {-2e-10, 3e-9, 5e-10}, {1e-10, 5e-10, 6e-9}}}};
        const hk_Vec3 f[2] = {{0.3, -1.2, 0.05}, {-0.7, 0.2, 1.1}}, tau[2] = {{1e-6, -2e-6, 3e-7}, {-5e-7, 4e-6, 1e-6}};
        hk_element_terms_add_quadrature2(&lanes, pair, a, b, f, tau);
        for (int l = 0; l < 2; l++)
            hk_element_terms_add_quadrature(&alone, pair[l].k.pos, a[l], &b[l], &pair[l].jac, &pair[l].jac_rot, f[l],
                                            tau[l]);
        assert_true(memcmp(&lanes, &alone, sizeof alone) == 0);
    }
}

/* A copy of the strand a (the same elements, material, root and coordinates). */
static hk_SuperHelix *strand_copy(const hk_SuperHelix *a)
{
    hk_SuperHelix *b = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(a->n, a->length, &b, &err), HK_OK);
    b->material = a->material;
    b->root = a->root;
    b->root_frame = a->root_frame;
    memcpy(b->q, a->q, sizeof(double) * (size_t)(3 * a->n));
    memcpy(b->q_rest, a->q_rest, sizeof(double) * (size_t)(3 * a->n));
    return b;
}

/* Whether the CPU has AVX (its paths turned on), so that they can be compared with the
 * baseline's. */
static int avx_paths_to_compare(void)
{
    if (hk_avx_paths_allow(1)) return 1;
    print_message("no AVX on this machine: nothing to compare\n");
    return 0;
}

/* The positive part's AVX and SSE2 paths (hk_symmetric_positive_part) on the matrices
 * a strand's steps really decompose: a curly strand of N = 10 (30 x 30, as a guide of
 * the bench's head) with the full stiffness, refreshed every step, on a moving head.
 * Each step's matrix gives the same bytes on both paths, with negative eigenvalues in
 * most steps (the eigenvector path runs), and the whole run gives the same bytes, the
 * other AVX paths (core/linalg.h: the dense solve, the Hessian's rows) switched with it. */
static void test_positive_part_paths_on_strand(void **state)
{
    (void)state;
    if (!avx_paths_to_compare()) return;
    const int n = 10, dim = 3 * n, steps = 20;
    hk_SuperHelix *a = curly_strand(n), *b = strand_copy(a);
    hk_DynamicsDef p = hk_default_dynamics_def();
    p.integrator = HK_INTEGRATOR_LINEAR_EULER;
    p.solver = HK_DYNAMICS_DENSE;
    p.stiffness = HK_STIFFNESS_FULL;
    p.hessian_interval = 1;
    hk_StrandDynamics *da = NULL, *db = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(a, &p, NULL, &da, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_create(b, &p, NULL, &db, &err), HK_OK);
    hk_RigidState head = hk_rigid_identity();
    head.omega = hk_v3(0.5, -1.0, 2.0);
    head.alpha = hk_v3(3.0, 1.0, -2.0);
    double *avx = malloc(sizeof(double) * (size_t)(dim * dim)), *sse2 = malloc(sizeof(double) * (size_t)(dim * dim));
    double *work = malloc(sizeof(double) * HK_POSITIVE_PART_WORK(dim));
    int indefinite = 0;
    for (int step = 0; step < steps; step++) {
        hk_avx_paths_allow(1);
        assert_int_equal(hk_strand_dynamics_step(da, &head, NULL, 0, 1.0 / 30, &err), HK_OK);
        int neg_avx = -1, neg_sse2 = -2;
        assert_int_equal(hk_symmetric_positive_part(dim, da->hess, avx, work, &neg_avx), 1);
        hk_avx_paths_allow(0);
        assert_int_equal(hk_strand_dynamics_step(db, &head, NULL, 0, 1.0 / 30, &err), HK_OK);
        assert_int_equal(hk_symmetric_positive_part(dim, da->hess, sse2, work, &neg_sse2), 1);
        assert_int_equal(neg_avx, neg_sse2);
        assert_memory_equal(avx, sse2, sizeof(double) * (size_t)(dim * dim));
        indefinite += neg_avx > 0;
    }
    hk_avx_paths_allow(1);
    print_message("curly N = 10: %d of %d steps' matrices indefinite\n", indefinite, steps);
    assert_true(indefinite >= steps / 2);
    assert_memory_equal(a->q, b->q, sizeof(double) * (size_t)dim);
    assert_memory_equal(hk_strand_dynamics_velocity(da), hk_strand_dynamics_velocity(db), sizeof(double) * (size_t)dim);
    free(avx), free(sse2), free(work);
    hk_strand_dynamics_destroy(da);
    hk_strand_dynamics_destroy(db);
    hk_superhelix_destroy(a);
    hk_superhelix_destroy(b);
}

static void shake_state(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

/* The guides' evaluation compiled for AVX (its twins, core/avx_twins.h) and the
 * baseline's give the same bits: a curly strand of N = 10 with the default integrator
 * (TR-BDF2, Newton's iteration, the error control splitting steps) on a shaking head,
 * 30 steps through hk_strand_dynamics_advance on each path, the states compared byte for
 * byte after every step. */
static void test_avx_twins_advance_the_same_bits(void **state)
{
    (void)state;
    if (!avx_paths_to_compare()) return;
    const int n = 10, dim = 3 * n, steps = 30;
    hk_SuperHelix *a = curly_strand(n), *b = strand_copy(a);
    const hk_DynamicsDef p = hk_default_dynamics_def();
    hk_StrandDynamics *da = NULL, *db = NULL;
    hk_HeadMotion *shake = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(a, &p, NULL, &da, &err), HK_OK);
    assert_int_equal(hk_strand_dynamics_create(b, &p, NULL, &db, &err), HK_OK);
    assert_int_equal(hk_head_motion_scripted("shake", 60.0, 2.0, hk_default_head_pivot(), &shake, &err), HK_OK);
    int substeps = 0;
    for (int step = 0; step < steps; step++) {
        int sa = 0, sb = 0;
        hk_avx_paths_allow(1);
        assert_int_equal(hk_strand_dynamics_advance(da, shake_state, shake, step / 30.0, 1.0 / 30, NULL, 0, &sa, &err),
                         HK_OK);
        hk_avx_paths_allow(0);
        assert_int_equal(hk_strand_dynamics_advance(db, shake_state, shake, step / 30.0, 1.0 / 30, NULL, 0, &sb, &err),
                         HK_OK);
        assert_int_equal(sa, sb);
        substeps += sa;
        assert_memory_equal(a->q, b->q, sizeof(double) * (size_t)dim);
        assert_memory_equal(hk_strand_dynamics_velocity(da), hk_strand_dynamics_velocity(db),
                            sizeof(double) * (size_t)dim);
    }
    hk_avx_paths_allow(1);
    print_message("curly N = 10 shaken: %d steps taken in %d frames\n", substeps, steps);
    hk_head_motion_destroy(shake);
    hk_strand_dynamics_destroy(da);
    hk_strand_dynamics_destroy(db);
    hk_superhelix_destroy(a);
    hk_superhelix_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gauss_rules_exact),
        cmocka_unit_test(test_point_kinematics_match_finite_differences),
        cmocka_unit_test(test_mass_matrix_gives_kinetic_energy),
        cmocka_unit_test(test_linear_solve_residual),
        cmocka_unit_test(test_upper_cholesky_is_the_reversed_factor),
        cmocka_unit_test(test_linear_and_dense_agree),
        cmocka_unit_test(test_body_friction_blend),
        cmocka_unit_test(test_body_stiffness_of_overlapping_shapes),
        cmocka_unit_test(test_point_pairs_bit_for_bit),
        cmocka_unit_test(test_positive_part_paths_on_strand),
        cmocka_unit_test(test_avx_twins_advance_the_same_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
