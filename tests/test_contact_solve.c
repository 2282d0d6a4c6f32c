/* The guide-guide contacts solved together (src/dynamics/hair_contact_solve.c):
 *  - the solve predicts each strand's step from its free step and its answer to
 *    impulses (Y = A^-1 J^T); ending the step with that prediction
 *    (hk_contact_solve_commit) must give the state a second method gives: the strand's
 *    own linearly implicit step with the solved impulses as point forces
 *    (hk_strand_dynamics_advance), which evaluates everything afresh;
 *  - the solve's work staged by the caller (hk_contact_solve_open to _prepare, as
 *    hair_sim.c does beside the contacts' update, and _sweep then _finish, or
 *    _finish_strand strand by strand in any order) gives the bits of the solve alone,
 *    step after step (each warm started from the last), and its evaluations;
 *  - the point Jacobians agree with finite differences of the points' positions, and
 *    those taken with the ends of the step's sweep are the bits of a fresh walk;
 *  - the forces are equal and opposite, and the friction stays in Coulomb's cone. */
#include "hk_test.h"

#include <math.h>
#include <omp.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/core_internal.h"
#include "core/linalg.h"
#include "dynamics/contact_rows.h"
#include "dynamics/dynamics_internal.h"
#include "dynamics/hair_contact_solve.h"
#include "hairkit/io.h"
#include "hairkit/statics.h"

#define STRANDS 3
#define SAMPLES 41

typedef struct World {
    hk_SuperHelix *sh[STRANDS];
    hk_StrandDynamics *d[STRANDS];
    hk_HairContacts *contacts;
    hk_ContactSolve *solve;
    double s[SAMPLES];
    hk_Vec3 pos[STRANDS][SAMPLES], vel[STRANDS][SAMPLES];
} World;

/* Three 20 cm strands of examples/guides200's hair rooted close together and
 * crossing as they fall, with the linearly implicit Euler step of full heads (the
 * dense solver, whose points' rows of Z^T both read and answer, or the O(N) one,
 * whose rows of J and of Y^T differ). */
/* examples/guides200's hairstyle in *style, and its dynamics with the linearly implicit
 * Euler step of full heads and the given solver. */
static hk_DynamicsDef guides_dynamics(hk_Hairstyle *style, hk_DynamicsSolver solver)
{
    hk_Error err;
    *style = hk_default_hairstyle();
    assert_int_equal(hk_hairstyle_load(HK_SOURCE_DIR "/examples/guides200/hairstyle.txt", style, &err), HK_OK);
    hk_DynamicsDef p = style->dynamics;
    p.integrator = HK_INTEGRATOR_LINEAR_EULER;
    p.solver = solver;
    p.stiffness = solver == HK_DYNAMICS_DENSE ? HK_STIFFNESS_FULL : HK_STIFFNESS_GAUSS_NEWTON;
    p.hessian_interval = 1;
    return p;
}

static void world_make_with(World *w, const hk_HairContactDef *cp, hk_DynamicsSolver solver)
{
    hk_Error err;
    hk_Hairstyle style;
    hk_DynamicsDef p = guides_dynamics(&style, solver);
    p.max_turn = p.max_travel = 1e9; /* one step each, as the commit takes it */
    const hk_Vec3 roots[STRANDS] = {hk_v3(0, 0, 0), hk_v3(0.004, 0.0, 0.05), hk_v3(-0.03, 0.003, 0.02)};
    const hk_Vec3 dirs[STRANDS] = {hk_v3(0, 0, 1), hk_v3(0, 0.01, -1), hk_v3(1, 0.02, 0.1)};
    const hk_StrandEnvDef env = hk_default_strand_env_def();
    for (int i = 0; i < STRANDS; i++) {
        assert_int_equal(hk_superhelix_from_def(&style.strand, roots[i], hk_v3_normalize(dirs[i]), &w->sh[i], &err),
                         HK_OK);
        assert_int_equal(hk_strand_dynamics_create(w->sh[i], &p, &env, &w->d[i], &err), HK_OK);
    }
    const double len = hk_strand_def_length(&style.strand);
    for (int j = 0; j < SAMPLES; j++) w->s[j] = len * j / (SAMPLES - 1);
    assert_int_equal(hk_hair_contacts_create(STRANDS, cp, &w->contacts, &err), HK_OK);
    assert_int_equal(hk_contact_solve_create(STRANDS, &w->solve, &err), HK_OK);
    hk_hairstyle_free(&style);
}

static void world_make(World *w, const hk_HairContactDef *cp) { world_make_with(w, cp, HK_DYNAMICS_DENSE); }

static void world_free(World *w)
{
    for (int i = 0; i < STRANDS; i++) hk_strand_dynamics_destroy(w->d[i]), hk_superhelix_destroy(w->sh[i]);
    hk_hair_contacts_destroy(w->contacts);
    hk_contact_solve_destroy(w->solve);
}

/* The pairs of the strands' state now. */
static void world_pairs(World *w)
{
    hk_Error err;
    hk_StrandSamples ss[STRANDS];
    for (int i = 0; i < STRANDS; i++) {
        hk_strand_dynamics_points(w->d[i], NULL, w->s, SAMPLES, w->pos[i], w->vel[i]);
        ss[i] = (hk_StrandSamples){SAMPLES, w->s, w->pos[i], w->vel[i]};
    }
    assert_int_equal(hk_hair_contacts_update(w->contacts, ss, STRANDS, &err), HK_OK);
}

static void world_solve(World *w, double h, hk_ContactSolveStats *stats)
{
    hk_Error err;
    world_pairs(w);
    const hk_RigidState still = hk_rigid_identity();
    assert_int_equal(hk_contact_solve(w->solve, w->contacts, w->d, STRANDS, &still, h, stats, &err), HK_OK);
}

/* world_solve with the solve's work staged as hair_sim.c does: two threads, one
 * laying out the points while the other predicts the strands, each strand's points
 * after its prediction once the layout is known, the rest and the pairs' laws in the
 * same region with no barrier between (the laws wait for their strands' points); after
 * the sweeps the solve finished by a team of two, or strand by strand in the reverse
 * order when `by_strand` is set. When `late` is set, strand 1's points and the laws
 * are left to the solve. */
static void world_solve_staged(World *w, double h, int late, int by_strand, hk_ContactSolveStats *stats)
{
    hk_Error err;
    world_pairs(w);
    const hk_RigidState still = hk_rigid_identity();
    assert_int_equal(hk_contact_solve_open(w->solve, w->d, STRANDS, &err), HK_OK);
    atomic_int laid_out;
    atomic_init(&laid_out, 0);
    hk_Status layout_st = HK_OK;
#pragma omp parallel num_threads(2)
    {
#pragma omp single nowait
        {
            layout_st = hk_contact_solve_layout(w->solve, w->contacts, w->d, STRANDS, h, &err);
            atomic_store(&laid_out, 1);
        }
#pragma omp for schedule(dynamic, 1) nowait
        for (int i = 0; i < STRANDS; i++) {
            hk_contact_solve_predict(w->solve, w->d[i], i, &still, h);
            if (atomic_load(&laid_out) && !(late && i == 1)) hk_contact_solve_points(w->solve, w->d[i], i, &still);
        }
        long spins = 0;
        while (!atomic_load(&laid_out)) hk_spin_pause(&spins);
        if (!late) {
#pragma omp for schedule(dynamic, 1) nowait
            for (int i = 0; i < STRANDS; i++) hk_contact_solve_points(w->solve, w->d[i], i, &still);
            hk_contact_solve_prepare(w->solve, w->contacts, h);
        }
    }
    assert_int_equal(layout_st, HK_OK);
    assert_int_equal(hk_contact_solve_sweep(w->solve, w->contacts, w->d, STRANDS, &still, h, stats, &err), HK_OK);
    if (by_strand) {
#pragma omp parallel for schedule(dynamic, 1) num_threads(2)
        for (int i = STRANDS - 1; i >= 0; i--) hk_contact_solve_finish_strand(w->solve, i);
    } else {
#pragma omp parallel num_threads(2)
        hk_contact_solve_finish(w->solve);
    }
}

static hk_HairContactDef params(void)
{
    hk_HairContactDef cp = hk_default_hair_contact_def();
    cp.distance = 0.005, cp.stiffness = 0.005, cp.damping = 8e-5, cp.root_exclusion = 0.0, cp.along = 1;
    return cp;
}

/* Two worlds alike, each with the contacts of params(). */
static void twin_worlds_with(World *a, World *b, hk_DynamicsSolver solver)
{
    const hk_HairContactDef cp = params();
    world_make_with(a, &cp, solver);
    world_make_with(b, &cp, solver);
}

static void twin_worlds(World *a, World *b) { twin_worlds_with(a, b, HK_DYNAMICS_DENSE); }

static void test_commit_matches_the_step_with_forces(void **state)
{
    (void)state;
    World a, b;
    twin_worlds(&a, &b);
    const double h = 1.0 / 30.0;
    int pushing = 0;
    hk_Error err;
    for (int step = 0; step < 40; step++) {
        hk_ContactSolveStats sa, sb;
        world_solve(&a, h, &sa);
        world_solve(&b, h, &sb);
        pushing += sa.pushing;
        const hk_RigidState still = hk_rigid_identity();
        double worst = 0.0, scale = 0.0;
        for (int i = 0; i < STRANDS; i++) {
            int count = 0;
            const hk_PointForce *f = hk_contact_solve_forces(b.solve, i, &count);
            if (!hk_contact_solve_commit(a.solve, a.d[i], i, &still, h))
                assert_int_equal(hk_strand_dynamics_advance(a.d[i], NULL, NULL, 0.0, h,
                                                            hk_contact_solve_forces(a.solve, i, &count), count, NULL,
                                                            &err),
                                 HK_OK);
            assert_int_equal(hk_strand_dynamics_advance(b.d[i], NULL, NULL, 0.0, h, f, count, NULL, &err), HK_OK);
            const double *va = hk_strand_dynamics_velocity(a.d[i]), *vb = hk_strand_dynamics_velocity(b.d[i]);
            for (int k = 0; k < 3 * a.sh[i]->n; k++) {
                worst = fmax(worst, fabs(va[k] - vb[k]));
                scale = fmax(scale, fabs(vb[k]));
                /* the same state for the next step (rounding apart) */
                a.sh[i]->q[k] = b.sh[i]->q[k];
                hk_strand_dynamics_velocity(a.d[i])[k] = vb[k];
            }
        }
        if (worst > 1e-9 * scale + 1e-12) print_message("step %d worst %g scale %g\n", step, worst, scale);
        assert_true(worst <= 1e-9 * scale + 1e-12);
    }
    print_message("%d pairs pushed over 40 steps\n", pushing);
    assert_true(pushing > 20);
    world_free(&a);
    world_free(&b);
}

/* Worlds a and b solved alike: the same forces; each strand committed (at rest's head)
 * to the same state, to the bit. */
static void commit_both_alike(World *a, World *b, double h)
{
    const hk_RigidState still = hk_rigid_identity();
    for (int i = 0; i < STRANDS; i++) {
        int na = 0, nb = 0;
        const hk_PointForce *fa = hk_contact_solve_forces(a->solve, i, &na);
        const hk_PointForce *fb = hk_contact_solve_forces(b->solve, i, &nb);
        assert_int_equal(na, nb);
        if (na > 0) assert_memory_equal(fa, fb, (size_t)na * sizeof *fa);
        assert_int_equal(hk_contact_solve_commit(a->solve, a->d[i], i, &still, h),
                         hk_contact_solve_commit(b->solve, b->d[i], i, &still, h));
        assert_memory_equal(a->sh[i]->q, b->sh[i]->q, 3 * (size_t)a->sh[i]->n * sizeof(double));
        assert_memory_equal(hk_strand_dynamics_velocity(a->d[i]), hk_strand_dynamics_velocity(b->d[i]),
                            3 * (size_t)a->sh[i]->n * sizeof(double));
    }
}

/* The staged solve and the solve alone: the same forces, the same steps, to the bit. */
static void test_staged_solve_gives_the_same_bits(void **state)
{
    (void)state;
    World a, b;
    twin_worlds(&a, &b);
    const double h = 1.0 / 30.0;
    int pushing = 0;
    for (int step = 0; step < 40; step++) {
        hk_ContactSolveStats sa, sb;
        world_solve(&a, h, &sa);
        world_solve_staged(&b, h, step % 3 == 2, step % 2 == 1, &sb);
        assert_int_equal(sa.pushing, sb.pushing);
        assert_int_equal(sa.sweeps, sb.sweeps);
        assert_true(sa.evaluations >= STRANDS); /* (one at least per strand's prediction) */
        assert_int_equal(sa.evaluations, sb.evaluations);
        pushing += sa.pushing;
        commit_both_alike(&a, &b, h);
    }
    print_message("%d pairs pushed over 40 steps\n", pushing);
    assert_true(pushing > 20);
    world_free(&a);
    world_free(&b);
}

/* Worlds a and b (with solver) solved alike but for b's records of one kind turned
 * off by allow(0) (hair_contact_solve.c): the same forces, the same steps, to the bit,
 * over steps whose sweeps reach the later full sweeps (10 and 20), where the idle
 * checks' records are read and the pushing pairs' records written back. */
static void solve_with_and_without(void (*allow)(int), hk_DynamicsSolver solver)
{
    World a, b;
    twin_worlds_with(&a, &b, solver);
    const double h = 1.0 / 30.0;
    int pushing = 0, long_solves = 0;
    for (int step = 0; step < 40; step++) {
        hk_ContactSolveStats sa, sb;
        world_solve(&a, h, &sa);
        allow(0);
        world_solve(&b, h, &sb);
        allow(1);
        assert_int_equal(sa.pushing, sb.pushing);
        assert_int_equal(sa.sweeps, sb.sweeps);
        pushing += sa.pushing;
        long_solves += sa.sweeps > 11;
        commit_both_alike(&a, &b, h);
    }
    print_message("%d pairs pushed, %d solves past sweep 11 over 40 steps\n", pushing, long_solves);
    assert_true(pushing > 20);
    assert_true(long_solves > 0);
    world_free(&a);
    world_free(&b);
}

/* The full sweeps' idle checks from their records (IdleCheck) and visit's own test. */
static void test_idle_records_give_the_same_bits(void **state)
{
    (void)state;
    solve_with_and_without(hk_contact_solve_idle_records_allow, HK_DYNAMICS_DENSE);
}

/* The sweeps from the pushing pairs' records (PushRecord) and in place, with either
 * solver (the records copy one set of rows or two). */
static void test_push_records_give_the_same_bits(void **state)
{
    (void)state;
    solve_with_and_without(hk_contact_solve_push_records_allow, HK_DYNAMICS_DENSE);
    solve_with_and_without(hk_contact_solve_push_records_allow, HK_DYNAMICS_LINEAR);
}

static void test_point_jacobians_match_finite_differences(void **state)
{
    (void)state;
    const hk_HairContactDef cp = params();
    World w;
    world_make(&w, &cp);
    hk_StrandDynamics *d = w.d[1];
    hk_SuperHelix *sh = w.sh[1];
    assert_true(sh->n > 0 && sh->n < 100);
    const int dim = 3 * sh->n;
    const size_t udim = (size_t)dim;
    for (int k = 0; k < dim; k++) sh->q[k] += 0.5 * sin(3.0 * k); /* a bent, twisted strand */
    const double s[3] = {0.013, 0.1, 0.2};
    double *jac = malloc(sizeof(double) * 9 * udim), *screws = malloc(sizeof(double) * 6 * udim);
    double *rates = calloc(udim, sizeof(double));
    hk_Vec3 pos[3];
    int element[3];
    hk_dynamics_point_jacobians(d, NULL, rates, s, 3, screws, jac, 0, pos, NULL, element);
    /* packed: each point's columns up to its element's, the same bits, blocks one after
     * another */
    double *packed = malloc(sizeof(double) * 9 * udim);
    hk_dynamics_point_jacobians(d, NULL, rates, s, 3, screws, packed, 1, NULL, NULL, NULL);
    const double *block = packed;
    for (int i = 0; i < 3; i++) {
        const size_t m = (size_t)(3 * element[i] + 3);
        assert_true(m <= udim);
        for (int r = 0; r < 3; r++) {
            const double *row = jac + (size_t)(3 * i + r) * udim;
            assert_memory_equal(block + (size_t)r * m, row, m * sizeof(double));
            for (size_t c = m; c < udim; c++) assert_true(row[c] == 0.0);
        }
        block += 3 * m;
    }
    assert_true(element[0] < element[2]); /* blocks of two sizes at least */
    /* the baseline's path (two columns a vector) gives the AVX path's bits */
    hk_avx_paths_allow(0);
    hk_dynamics_point_jacobians(d, NULL, rates, s, 3, screws, packed, 0, NULL, NULL, NULL);
    hk_avx_paths_allow(1);
    assert_memory_equal(packed, jac, 9 * udim * sizeof(double));
    free(packed);
    const double e = 1e-7;
    double worst = 0.0;
    for (int c = 0; c < dim; c++) {
        hk_Vec3 plus[3], minus[3];
        sh->q[c] += e;
        hk_strand_dynamics_points(d, NULL, s, 3, plus, NULL);
        sh->q[c] -= 2 * e;
        hk_strand_dynamics_points(d, NULL, s, 3, minus, NULL);
        sh->q[c] += e;
        for (int i = 0; i < 3; i++) {
            const hk_Vec3 fd = hk_v3_scale(hk_v3_sub(plus[i], minus[i]), 0.5 / e);
            const double x[3] = {fd.x, fd.y, fd.z};
            for (int r = 0; r < 3; r++)
                worst = fmax(worst, fabs(x[r] - jac[(size_t)(3 * i + r) * (size_t)dim + (size_t)c]));
        }
    }
    print_message("point Jacobians against central differences: %.2g\n", worst);
    assert_true(worst < 1e-7);
    free(jac), free(screws), free(rates);
    world_free(&w);
}

/* The contact points' Jacobians, velocities and screws of strand 1 of world w at its
 * state now, with the head in state head and the rates given. */
typedef struct PointRows {
    double jac[9 * 90], screws[6 * 90];
    hk_Vec3 pos[3], vel[3];
    int element[3];
} PointRows;

static void point_rows(World *w, const hk_RigidState *head, const double *rates, PointRows *out)
{
    const double s[3] = {0.013, 0.1, 0.2};
    assert_true(3 * w->sh[1]->n <= 90);
    memset(out, 0, sizeof *out);
    hk_dynamics_point_jacobians(w->d[1], head, rates, s, 3, out->screws, out->jac, 0, out->pos, out->vel, out->element);
}

/* The points' Jacobians take the elements' ends from the step's sweep when the state is
 * the one it swept (hk_dynamics_end_poses): the same bits as a strand that never swept,
 * which walks them afresh; and a state changed since (q moved from outside, the root
 * placed with another head pose) must walk afresh too: with the stale ends the
 * Jacobians would differ. */
static void test_point_jacobians_reuse_only_the_swept_state(void **state)
{
    (void)state;
    World a, b; /* a sweeps, b never does */
    twin_worlds(&a, &b);
    hk_SuperHelix *sa = a.sh[1], *sb = b.sh[1];
    const int dim = 3 * sa->n;
    for (int k = 0; k < dim; k++) sa->q[k] = sb->q[k] += 0.5 * sin(3.0 * k); /* bent, twisted */
    hk_RigidState head = hk_rigid_identity(), other = hk_rigid_identity();
    head.rot = hk_root_frame(hk_v3(0.3, 1.0, 0.2));
    head.trans = hk_v3(0.01, -0.02, 0.03);
    head.vel = hk_v3(0.1, 0.0, -0.2);
    head.omega = hk_v3(0.5, 1.0, -0.3);
    other.rot = hk_root_frame(hk_v3(0.31, 1.0, 0.2));
    double rates[90];
    for (int k = 0; k < dim; k++) rates[k] = cos(2.0 * k);
    static PointRows ra, rb, before;
    /* the same state as the sweep's: the ends reused */
    assert_true(hk_dynamics_euler_delta(a.d[1], &head, NULL, 0, 1.0 / 30.0));
    assert_non_null(hk_dynamics_end_poses(a.d[1]));
    assert_null(hk_dynamics_end_poses(b.d[1]));
    point_rows(&a, &head, rates, &ra);
    point_rows(&b, &head, rates, &rb);
    assert_memory_equal(&ra, &rb, sizeof ra);
    before = ra;
    /* q changed from outside after the sweep (by enough to move the ends' rows) */
    sa->q[4] += 1e-3, sb->q[4] += 1e-3;
    assert_null(hk_dynamics_end_poses(a.d[1]));
    point_rows(&a, &head, rates, &ra);
    point_rows(&b, &head, rates, &rb);
    assert_memory_equal(&ra, &rb, sizeof ra);
    assert_true(memcmp(ra.screws, before.screws, sizeof ra.screws) != 0);
    /* swept with one head pose, the points taken with another */
    assert_true(hk_dynamics_euler_delta(a.d[1], &head, NULL, 0, 1.0 / 30.0));
    assert_non_null(hk_dynamics_end_poses(a.d[1]));
    point_rows(&a, &other, rates, &ra);
    point_rows(&b, &other, rates, &rb);
    assert_memory_equal(&ra, &rb, sizeof ra);
    assert_true(memcmp(ra.screws, before.screws, sizeof ra.screws) != 0);
    world_free(&a);
    world_free(&b);
}

/* hk_dynamics_reversed_factor, which the contacts' solve reads in place: the factor U of
 * the step's dense solve (A = U U^T, the bits hk_dynamics_resolve solves with) with U^T
 * in its strict lower part (row i there is column i of U), for an even size (3N = 30)
 * and an odd one (27), on both paths; none with the O(N) solver. */
static void test_reversed_factor_holds_u_and_its_transpose(void **state)
{
    (void)state;
    hk_Error err;
    hk_Hairstyle style;
    const hk_StrandEnvDef env = hk_default_strand_env_def();
    const hk_RigidState head = hk_rigid_identity();
    for (int dense = 0; dense < 2; dense++) {
        const hk_DynamicsDef p = guides_dynamics(&style, dense ? HK_DYNAMICS_DENSE : HK_DYNAMICS_LINEAR);
        const int full = style.strand.element_count;
        for (int elements = full - 1; elements <= full; elements++)
            for (int avx = 0; avx < 2; avx++) {
                if (!hk_avx_paths_allow(avx) && avx) continue; /* no AVX: the baseline alone */
                style.strand.element_count = elements;
                hk_SuperHelix *sh;
                hk_StrandDynamics *d;
                assert_int_equal(hk_superhelix_from_def(&style.strand, hk_v3(0, 0, 0), hk_v3(0, 0.3, -1), &sh, &err),
                                 HK_OK);
                assert_int_equal(hk_strand_dynamics_create(sh, &p, &env, &d, &err), HK_OK);
                const int dim = 3 * sh->n;
                for (int k = 0; k < dim; k++) sh->q[k] += 0.5 * sin(3.0 * k); /* bent, twisted */
                assert_true(hk_dynamics_euler_delta(d, &head, NULL, 0, 1.0 / 30.0));
                const double *u = hk_dynamics_reversed_factor(d);
                if (!dense) {
                    assert_null(u);
                } else {
                    assert_non_null(u);
                    const size_t sd = (size_t)dim;
                    for (size_t i = 0; i < sd; i++)
                        for (size_t k = 0; k < i; k++) assert_memory_equal(&u[i * sd + k], &u[k * sd + i], sizeof *u);
                    double rhs[90], x[90];
                    for (int k = 0; k < dim; k++) rhs[k] = x[k] = cos(2.0 * k);
                    hk_upper_solve(dim, u, x);
                    assert_int_equal(hk_dynamics_resolve(d, rhs, rhs), 1);
                    assert_memory_equal(x, rhs, sd * sizeof *x);
                }
                hk_strand_dynamics_destroy(d);
                hk_superhelix_destroy(sh);
            }
        hk_avx_paths_allow(1);
        style.strand.element_count = full;
        hk_hairstyle_free(&style);
    }
}

/* contact_rows.c, the kernels of the answers, for an odd and an even support on both
 * paths: a point's rows turned into a basis are hk_v3_dot's bits; the back substitution
 * solves U z = j (to rounding: a residual below 1e-13 of the right-hand side's size,
 * with U's diagonal at 2 or more and its other entries below 0.5), a row solved alone
 * has the bits it has beside one or two others (the answers solve rows so, normal_rows
 * and reversed_rows), and the AVX twin gives the baseline's bits. */
static void test_contact_rows_kernels(void **state)
{
    (void)state;
    enum { DIM = 30 };
    static double u[DIM * DIM], inverse[DIM]; /* column i at u + i DIM: U[k][i] for k <= i */
    for (int i = 0; i < DIM; i++) {
        for (int k = 0; k < DIM; k++) u[i * DIM + k] = k == i ? 2.0 + 0.1 * i : k < i ? 0.5 * sin(7.0 * i + k) : -1.0;
        inverse[i] = 1.0 / u[i * DIM + i];
    }
    const hk_Vec3 basis[3] = {hk_v3(0.48, -0.6, 0.64), hk_v3(0.8, 0.6, 0.0), hk_v3(-0.384, 0.512, 0.768)};
    double first[2][3 * DIM + 3 * DIM]; /* the baseline's results, per support */
    for (int avx = 0; avx < 2; avx++) {
        if (!hk_avx_paths_allow(avx) && avx) continue; /* no AVX: the baseline alone */
        for (int m = 17; m <= 18; m++) {
            double j[3][DIM], z[3][DIM], alone[DIM], two[2][DIM], rows[3 * DIM];
            for (int r = 0; r < 3; r++)
                for (int k = 0; k < DIM; k++) j[r][k] = z[r][k] = k < m ? cos(5.0 * r + k) : 0.0;
            hk_contact_back_substitute(u, inverse, DIM, m, z[0], z[1], z[2], 3);
            memcpy(two, j[1], sizeof two);
            hk_contact_back_substitute(u, inverse, DIM, m, two[0], two[1], NULL, 2);
            assert_memory_equal(two, z[1], sizeof two);
            for (int r = 0; r < 3; r++) {
                memcpy(alone, j[r], sizeof alone);
                hk_contact_back_substitute(u, inverse, DIM, m, alone, NULL, NULL, 1);
                assert_memory_equal(alone, z[r], sizeof alone);
                for (int k = 0; k < m; k++) {
                    double uz = 0.0;
                    for (int i = k; i < m; i++) uz += u[i * DIM + k] * z[r][i];
                    assert_true(fabs(uz - j[r][k]) <= 1e-13);
                }
                for (int k = m; k < DIM; k++) assert_true(z[r][k] == 0.0);
            }
            for (int r = 0; r < 3; r++)
                for (int k = 0; k < m; k++) rows[r * m + k] = j[r][k];
            hk_contact_rows_in_basis(rows, (size_t)m, (size_t)m, basis);
            for (int r = 0; r < 3; r++)
                for (int k = 0; k < m; k++) {
                    const double in_basis = hk_v3_dot(basis[r], hk_v3(j[0][k], j[1][k], j[2][k]));
                    assert_memory_equal(&rows[r * m + k], &in_basis, sizeof in_basis);
                }
            double *mine = first[m - 17];
            if (avx) {
                assert_memory_equal(mine, z, sizeof z);
                assert_memory_equal(mine + 3 * DIM, rows, 3 * (size_t)m * sizeof *rows);
            } else {
                memcpy(mine, z, sizeof z);
                memcpy(mine + 3 * DIM, rows, 3 * (size_t)m * sizeof *rows);
            }
        }
    }
    hk_avx_paths_allow(1);
}

static void test_forces_opposite_and_in_the_cone(void **state)
{
    (void)state;
    const hk_HairContactDef cp = params();
    World w;
    world_make(&w, &cp);
    const double h = 1.0 / 30.0;
    hk_Error err;
    int checked = 0;
    for (int step = 0; step < 40; step++) {
        hk_ContactSolveStats st;
        world_solve(&w, h, &st);
        /* Every pair's force on its two points, found by their arc lengths (each
         * strand's list is sorted by s; the pairs' points here are distinct). */
        for (int k = 0; k < hk_hair_contacts_pair_count(w.contacts); k++) {
            hk_HairContactPair pr;
            assert_true(hk_hair_contacts_pair(w.contacts, k, &pr));
            hk_Vec3 f[2] = {hk_v3_zero(), hk_v3_zero()};
            int found[2] = {0, 0};
            for (int side = 0; side < 2; side++) {
                int count = 0;
                const hk_PointForce *list = hk_contact_solve_forces(w.solve, pr.strand[side], &count);
                for (int x = 0; x < count; x++)
                    if (list[x].s == pr.s[side]) f[side] = hk_v3_add(f[side], list[x].force), found[side]++;
            }
            if (found[0] != 1 || found[1] != 1 || !(pr.distance > 1e-6)) continue;
            hk_assert_near(hk_v3_norm(hk_v3_add(f[0], f[1])), 0.0, 1e-12 * (1.0 + hk_v3_norm(f[0])));
            const hk_Vec3 n = hk_v3_scale(hk_v3_sub(pr.point[0], pr.point[1]), 1.0 / pr.distance);
            const double fn = hk_v3_dot(f[0], n), ft = hk_v3_norm(hk_v3_madd(f[0], n, -fn));
            const double rounding = 1e-12 * hk_v3_norm(f[0]);
            assert_true(fn >= -rounding);
            assert_true(ft <= cp.friction_coefficient * fn + rounding);
            checked += fn > 0.0;
        }
        for (int i = 0; i < STRANDS; i++) {
            int count = 0;
            const hk_PointForce *f = hk_contact_solve_forces(w.solve, i, &count);
            assert_int_equal(hk_strand_dynamics_advance(w.d[i], NULL, NULL, 0.0, h, f, count, NULL, &err), HK_OK);
        }
    }
    print_message("%d pushing pairs checked\n", checked);
    assert_true(checked > 20);
    world_free(&w);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_point_jacobians_match_finite_differences),
        cmocka_unit_test(test_point_jacobians_reuse_only_the_swept_state),
        cmocka_unit_test(test_commit_matches_the_step_with_forces),
        cmocka_unit_test(test_staged_solve_gives_the_same_bits),
        cmocka_unit_test(test_idle_records_give_the_same_bits),
        cmocka_unit_test(test_push_records_give_the_same_bits),
        cmocka_unit_test(test_forces_opposite_and_in_the_cone),
        cmocka_unit_test(test_reversed_factor_holds_u_and_its_transpose),
        cmocka_unit_test(test_contact_rows_kernels),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
