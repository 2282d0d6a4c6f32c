/* Validation of Super-Helix dynamics against independent references (issue 6):
 *  - first bending frequency of a clamped-free rod, omega = 1.8751^2 sqrt(E I /
 *    (rho A L^4)) (Euler-Bernoulli beam theory; DESIGN.md), at N = 10;
 *  - a damped strand comes to rest on the statics solution (the Newton minimiser of
 *    the same energy, a second method);
 *  - the total energy never rises without external work (implicit Euler dissipates);
 *  - the gyroscopic couple w x I w bends a rod on a spinning head by m L^2 / (2 EI)
 *    (Euler's equations and a cantilever under a distributed couple);
 *  - a natural helix at zero gravity stays at rest;
 *  - a head translating at constant velocity carries the strand rigidly, and a head
 *    falling freely with gravity leaves the strand weightless (equivalence principle);
 *  - air drag: a strand falling with its head as a body of the strand's mass and drag
 *    falls (approaching the terminal velocity v_t = rho S g / nu) is weightless all the
 *    way, and a head going down steadily at V leaves the strand in the statics shape
 *    under gravity g (1 - V / v_t);
 *  - the four hair types of paper 000 Appendix B stay stable at dt = 1/30 s on a
 *    shaking head. */
#include "hk_test.h"
#include "hk_test_strand.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/dynamics.h"
#include "hairkit/io.h"
#include "hairkit/statics.h"

/* Horizontal straight strand along +x, N equal elements, gravity g along -y. */
static hk_SuperHelix *strand(int n, double length, double g)
{
    double len[64];
    for (int i = 0; i < n; i++) len[i] = length / n;
    hk_SuperHelix *sh = NULL;
    hk_Error err;
    assert_int_equal(hk_superhelix_create(n, len, &sh, &err), HK_OK);
    sh->material = hk_rod_material(5e-5, 5e-5, 1e9, 0.48, 1300.0, hk_v3(0, -g, 0));
    sh->root_frame = hk_root_frame(hk_v3(1, 0, 0));
    return sh;
}

static hk_DynamicsDef undamped(void)
{
    hk_DynamicsDef p = hk_default_dynamics_def();
    p.internal_friction = 0.0;
    p.air_drag = 0.0;
    return p;
}

static hk_Vec3 tip_of(const hk_SuperHelix *sh)
{
    hk_Vec3 tip;
    hk_superhelix_eval(sh, NULL, sh->total_length, &tip, NULL);
    return tip;
}

static void test_cantilever_first_frequency(void **state)
{
    (void)state;
    const double length = 0.1;
    hk_SuperHelix *sh = strand(10, length, 1.0);
    const hk_RodMaterial *m = &sh->material;
    /* Small gravity: lambda = rho g A L^3 / (E I) = 0.01, a linear vibration about the
     * sagged shape. */
    const double ei = m->stiffness[1], rho_a = m->mass_per_length;
    m = NULL;
    sh->material.gravity = hk_v3(0.0, -0.01 * ei / (rho_a * length * length * length), 0.0);
    const double omega = 1.8751 * 1.8751 * sqrt(ei / (rho_a * pow(length, 4)));
    const double period = 2.0 * HK_PI / omega;
    /* dt = period / 2000: implicit Euler's phase error (omega dt)^2 / 3 ~ 3e-6. */
    const double dt = period / 2000.0;
    hk_DynamicsDef p = undamped();
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    /* Released straight: the tip oscillates between 0 and twice the static sag. Upward
     * crossings of the mid level give the period. */
    const int steps = 2000 * 4;
    double *y = malloc(sizeof(double) * (steps + 1));
    y[0] = tip_of(sh).y;
    double lo = y[0], hi = y[0];
    for (int i = 1; i <= steps; i++) {
        assert_int_equal(hk_strand_dynamics_step(d, NULL, NULL, 0, dt, &err), HK_OK);
        y[i] = tip_of(sh).y;
        lo = fmin(lo, y[i]);
        hi = fmax(hi, y[i]);
    }
    const double mid = 0.5 * (lo + hi);
    double first = -1.0, last = -1.0;
    int crossings = 0;
    for (int i = 1; i <= steps; i++)
        if (y[i - 1] < mid && y[i] >= mid) {
            const double t = dt * (i - 1 + (mid - y[i - 1]) / (y[i] - y[i - 1]));
            if (first < 0.0) first = t;
            last = t;
            crossings++;
        }
    assert_true(crossings >= 3);
    const double measured = (last - first) / (crossings - 1);
    print_message("cantilever: period %.6f s, Euler-Bernoulli %.6f s (%+.3f%%), sag %.4g m\n", measured, period,
                  100.0 * (measured / period - 1.0), -lo);
    hk_assert_rel(measured, period, 0.02, 0.0);
    /* and the sag: twice the static deflection lambda L / 8 at the lowest point */
    hk_assert_rel(-lo, 2.0 * 0.01 * length / 8.0, 0.05, 0.0);
    free(y);
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
}

/* A wavy strand of real hair (paper 000 Appendix B, Caucasian 1) leaving a head
 * sideways. */
static hk_SuperHelix *wavy_strand(int n, double length)
{
    hk_SuperHelix *sh = strand(n, length, 9.81);
    sh->material = hk_rod_material(35e-6, 35e-6 * 1.1, 2e9, 0.48, 1300.0, hk_v3(0, -9.81, 0));
    double tau, kappa;
    hk_helix_natural_curvature(0.01, 0.005, &tau, &kappa);
    hk_superhelix_set_uniform_rest(sh, tau, kappa, 0.0);
    sh->root_frame = hk_root_frame(hk_v3(1, 0.3, 0.2));
    return sh;
}

static double max_distance(const hk_SuperHelix *a, const double *qa, const double *qb)
{
    enum { M = 41 };
    double worst = 0.0;
    for (int i = 0; i < M; i++) {
        hk_Vec3 pa, pb;
        hk_superhelix_eval(a, qa, a->total_length * i / (M - 1), &pa, NULL);
        hk_superhelix_eval(a, qb, a->total_length * i / (M - 1), &pb, NULL);
        worst = fmax(worst, hk_v3_dist(pa, pb));
    }
    return worst;
}

static void test_damped_strand_rests_on_statics(void **state)
{
    (void)state;
    const double length = 0.15;
    hk_SuperHelix *sh = wavy_strand(10, length);
    /* Reference: Newton's minimum of the same energy. */
    hk_StrandEnvDef env = hk_default_strand_env_def();
    hk_StaticsDef opt = hk_default_statics_def();
    hk_Error err;
    hk_MinimizeResult res;
    assert_int_equal(hk_statics_solve(sh, &env, &opt, &res, &err), HK_OK);
    double *rest = malloc(sizeof(double) * 30);
    memcpy(rest, sh->q, sizeof(double) * 30);
    memcpy(sh->q, sh->q_rest, sizeof(double) * 30);
    hk_DynamicsDef p = hk_default_dynamics_def();
    hk_StrandDynamics *d = NULL;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    const double dt = 1.0 / 30.0;
    double kinetic = 1.0;
    int steps = 0;
    for (; steps < 3000 && !(steps > 30 && kinetic < 1e-16); steps++) {
        assert_int_equal(hk_strand_dynamics_step(d, NULL, NULL, 0, dt, &err), HK_OK);
        hk_strand_dynamics_energy(d, NULL, &kinetic, NULL);
    }
    const double gap = max_distance(sh, sh->q, rest);
    print_message("damped strand: at rest after %.1f s, %.3g L from the statics shape\n", steps * dt, gap / length);
    assert_true(gap < 1e-3 * length);
    free(rest);
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
}

/* Energy of a strand released from its natural shape, sideways and slightly up, with
 * full gravity; returns the largest excess of the total energy over its initial value
 * and fails if the energy rises over a single step when `monotone`. */
static double energy_run(double dt, double seconds, int damped, int monotone, hk_DynamicsStiffness stiffness)
{
    hk_SuperHelix *sh = wavy_strand(8, 0.2);
    hk_DynamicsDef p = damped ? hk_default_dynamics_def() : undamped();
    p.stiffness = stiffness;
    p.solver = stiffness == HK_STIFFNESS_FULL ? HK_DYNAMICS_DENSE : HK_DYNAMICS_LINEAR;
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    double t0, u0;
    hk_strand_dynamics_energy(d, NULL, &t0, &u0);
    const double e0 = t0 + u0, scale = fabs(u0);
    double prev = e0, excess = 0.0;
    const int steps = (int)(seconds / dt + 0.5);
    for (int i = 0; i < steps; i++) {
        assert_int_equal(hk_strand_dynamics_advance(d, NULL, NULL, i * dt, dt, NULL, 0, NULL, &err), HK_OK);
        double t, u;
        hk_strand_dynamics_energy(d, NULL, &t, &u);
        if (monotone && !(t + u <= prev + 1e-12 * scale))
            fail_msg("energy rose at step %d (dt %g): %.12g -> %.12g", i, dt, prev, t + u);
        prev = t + u;
        excess = fmax(excess, (prev - e0) / scale);
    }
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
    return excess;
}

/* On a still head the energy never rises, with the paper's damping (gamma, nu in
 * Appendix B's ranges) and without, at the paper's dt = 1/30 s and at 1 ms, with either
 * stiffness: TR-BDF2 with the energy guard (docs/dynamics.md, "Time stepping"). The
 * linearly implicit Euler it replaced gained energy undamped (61 % of the available
 * energy at dt = 1/120 s, issue 12). tests/test_dynamics_stepping.c checks the undamped
 * energy over 10 s at dt from 1/24 s to 1 ms against the available energy. */
static void test_energy_never_rises(void **state)
{
    (void)state;
    const hk_DynamicsStiffness kinds[2] = {HK_STIFFNESS_FULL, HK_STIFFNESS_GAUSS_NEWTON};
    for (int k = 0; k < 2; k++) {
        energy_run(1.0 / 30.0, 10.0, 1, 1, kinds[k]);
        energy_run(1e-3, 3.0, 1, 1, kinds[k]);
        energy_run(1.0 / 30.0, 10.0, 0, 1, kinds[k]);
        energy_run(1e-3, 2.0, 0, 1, kinds[k]);
    }
}

/* The section's rotary inertia (Euler's equations, I w' + w x I w): with an
 * exaggerated, anisotropic rotary inertia, no gravity and no damping, a strand set
 * spinning and bending must conserve its energy up to the step's O(dt) error - the
 * drift shrinks with dt. A missing or wrong I w' term leaves a drift that does not
 * shrink. (The gyroscopic w x I w does no work on w, so energy cannot see it: the
 * spinning rod below checks it.) */
static double spinning_drift(double dt)
{
    hk_SuperHelix *sh = wavy_strand(6, 0.1);
    sh->material.gravity = hk_v3_zero();
    const double rho_s = sh->material.mass_per_length;
    sh->material.rotary_inertia[1] = 0.5 * rho_s * 0.01 * 0.01;
    sh->material.rotary_inertia[2] = 1.5 * rho_s * 0.01 * 0.01;
    sh->material.rotary_inertia[0] = sh->material.rotary_inertia[1] + sh->material.rotary_inertia[2];
    hk_DynamicsDef p = undamped();
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    double *v = hk_strand_dynamics_velocity(d);
    for (int i = 0; i < 18; i++) v[i] = (i % 3 == 0 ? 400.0 : 40.0) * ((i * 7 % 5) - 2.0);
    double t0, u0;
    hk_strand_dynamics_energy(d, NULL, &t0, &u0);
    const double e0 = t0 + u0;
    double worst = 0.0;
    for (int i = 0; i < (int)(0.05 / dt + 0.5); i++) {
        assert_int_equal(hk_strand_dynamics_step(d, NULL, NULL, 0, dt, &err), HK_OK);
        double t, u;
        hk_strand_dynamics_energy(d, NULL, &t, &u);
        worst = fmax(worst, fabs(t + u - e0) / e0);
    }
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
    return worst;
}

static void test_rotary_terms_conserve_energy(void **state)
{
    (void)state;
    const double coarse = spinning_drift(1e-4), fine = spinning_drift(2.5e-5);
    print_message("spinning strand: energy drift %.3g at dt 0.1 ms, %.3g at 25 us\n", coarse, fine);
    assert_true(fine < coarse / 2.5); /* first order: 4 expected */
}

/* The gyroscopic term w x I w of Euler's equations, which does no work and so escapes
 * the energy test above. A section turning steadily at w about an axis that is not one
 * of its principal axes needs the torque w x I w (Euler's equations with w' = 0;
 * Goldstein, Classical Mechanics, §5.5-5.6; Landau & Lifshitz, Mechanics, §36): here
 * the clamped rod must supply it, and bends to do so.
 *
 * Set-up: a straight rod of length L clamped at the origin, leaving at theta = 45
 * degrees from the y axis, on a head turning steadily at W about y (no gravity, no
 * centreline mass: rho S = 0, so only the section's rotary inertia moves; no air drag).
 * In the head's frame the rod settles (internal friction damps its relative motion) to
 * a shape at rest, every section turning rigidly at w = W y, w' = 0. For a section with
 * moments I_t about its tangent t and I_n about the normals (isotropic bending),
 *     I w = I_n w + (I_t - I_n) (w . t) t,   w x I w = (I_t - I_n) W^2 cos(theta) y x t,
 * so the inertial couple on the rod, -w x I w, is m = (I_t - I_n) W^2 cos(theta)
 * sin(theta) per unit length about t x y / |t x y|, turning t towards the axis when
 * I_t > I_n (a disc, the hair's own section: I_t = I1 + I2 = 2 I_n, flattens to spin
 * about its largest moment) and away from it when I_t < I_n (a needle). The couple
 * lies in the plane of y and t, so the rod bends in that plane, without twist.
 *
 * Reference (Euler-Bernoulli cantilever under a distributed couple): a couple has no
 * lever arm, so the bending moment at s is M(s) = int_s^L m ds' = m (L - s), the
 * curvature M / EI, and the tip tangent has turned by
 *     phi = int_0^L M / EI ds = m L^2 / (2 EI)
 * towards the axis. This is exact for the planar elastica except for m's dependence on
 * the local angle, m ~ sin(2 theta), which is stationary at 45 degrees: the relative
 * error is below 2 phi^2 (8e-4 for phi = 0.02). The Super-Helix's piecewise constant
 * curvatures are the element means of the exact one (the generalized force of element
 * P's curvature is int M ds over P, its stiffness EI l_P), so their sum, the tip angle,
 * is exact for any N.
 *
 * Without the w x I w term the rod stays straight (phi = 0; every other load vanishes:
 * w' = 0 and rho S = 0), with its sign flipped it bends away from the axis.
 *
 * spin_state: the head turned by w t about +y, turning at w. */
static void spin_state(double w, double t, hk_RigidState *out)
{
    const double c = cos(w * t), s = sin(w * t);
    *out = hk_rigid_identity();
    out->rot = hk_m3_from_cols(hk_v3(c, 0, -s), hk_v3(0, 1, 0), hk_v3(s, 0, c));
    out->omega = hk_v3(0, w, 0);
}

/* Tip angle towards the spin axis and out of the plane, for rotary inertias i_t, i_n. */
static void spinning_rod_bend(int n, double length, double theta, hk_DynamicsSolver solver, double i_t, double i_n,
                              double w, double *towards, double *out_of_plane)
{
    hk_SuperHelix *sh = strand(n, length, 0.0);
    sh->material.mass_per_length = 0.0;
    sh->material.rotary_inertia[0] = i_t;
    sh->material.rotary_inertia[1] = sh->material.rotary_inertia[2] = i_n;
    sh->root_frame = hk_root_frame(hk_v3(sin(theta), cos(theta), 0.0));
    hk_DynamicsDef p = undamped();
    p.internal_friction = 1e-10; /* the paper's gamma: about critical for the first mode */
    p.solver = solver;
    if (solver == HK_DYNAMICS_LINEAR) p.stiffness = HK_STIFFNESS_GAUSS_NEWTON;
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    const double dt = 2e-3;
    for (int i = 0; i < 2000; i++) {
        hk_RigidState head;
        spin_state(w, (i + 1) * dt, &head);
        assert_int_equal(hk_strand_dynamics_step(d, &head, NULL, 0, dt, &err), HK_OK);
    }
    for (int j = 0; j < 3 * n; j++) /* settled: at rest in the head's frame */
        hk_assert_near(hk_strand_dynamics_velocity(d)[j] * length, 0.0, 1e-9);
    hk_Mat3 tip;
    hk_superhelix_eval(sh, NULL, sh->total_length, NULL, &tip);
    const hk_Vec3 t0 = hk_m3_col(&sh->root_frame, 0), t1 = hk_m3_col(&tip, 0), y = hk_v3(0, 1, 0);
    const hk_Vec3 in = hk_v3_normalize(hk_v3_madd(y, t0, -hk_v3_dot(y, t0))); /* towards the axis */
    *towards = atan2(hk_v3_dot(t1, in), hk_v3_dot(t1, t0));
    *out_of_plane = hk_v3_dot(t1, hk_v3_cross(t0, in));
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
}

static void test_gyroscopic_couple_bends_a_spinning_rod(void **state)
{
    (void)state;
    const double length = 0.1, theta = 0.25 * HK_PI, w = 2.0 * HK_PI;
    /* EI = E pi a^4 / 4 of strand()'s section (a = 50 um, E = 1 GPa). */
    const double ei = 1e9 * HK_PI * pow(5e-5, 4) / 4.0;
    /* A section exaggerated to a 1 cm radius of gyration, as in the energy test above. */
    const double i_n = 1e-9;
    const struct {
        double i_t;
        const char *name;
    } sections[2] = {{2.0 * i_n, "disc"}, {0.5 * i_n, "needle"}};
    const hk_DynamicsSolver solvers[2] = {HK_DYNAMICS_DENSE, HK_DYNAMICS_LINEAR};
    const int counts[2] = {1, 5};
    for (int k = 0; k < 2; k++) {
        const double m = (sections[k].i_t - i_n) * w * w * cos(theta) * sin(theta);
        const double phi = m * length * length / (2.0 * ei);
        for (int c = 0; c < 2; c++)
            for (int sv = 0; sv < 2; sv++) {
                double towards, out;
                spinning_rod_bend(counts[c], length, theta, solvers[sv], sections[k].i_t, i_n, w, &towards, &out);
                print_message("spinning %s rod, N = %d, %s solver: tip turned %.6f rad towards the axis, "
                              "m L^2 / (2 EI) = %.6f (%+.3f%%), out of plane %.2g\n",
                              sections[k].name, counts[c], sv == 0 ? "dense" : "O(N)", towards, phi,
                              100.0 * (towards / phi - 1.0), out);
                hk_assert_rel(towards, phi, 2e-3, 0.0);
                hk_assert_near(out, 0.0, 1e-6 * fabs(phi));
            }
    }
}

static void test_helix_at_zero_gravity_stays(void **state)
{
    (void)state;
    hk_SuperHelix *sh = wavy_strand(10, 0.2);
    sh->material.gravity = hk_v3_zero();
    double tau, kappa;
    hk_helix_natural_curvature(0.004, 0.01, &tau, &kappa); /* curly */
    hk_superhelix_set_uniform_rest(sh, tau, kappa, 0.0);
    hk_DynamicsDef p = undamped();
    hk_StrandDynamics *d = NULL;
    hk_Error err;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    for (int i = 0; i < 100; i++) assert_int_equal(hk_strand_dynamics_step(d, NULL, NULL, 0, 1.0 / 30.0, &err), HK_OK);
    for (int i = 0; i < 30; i++) {
        hk_assert_near(sh->q[i], sh->q_rest[i], 1e-12 * kappa);
        hk_assert_near(hk_strand_dynamics_velocity(d)[i], 0.0, 1e-12 * kappa);
    }
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);
}

static void test_translating_head_moves_strand_rigidly(void **state)
{
    (void)state;
    for (int fall = 0; fall < 2; fall++) {
        hk_SuperHelix *sh = wavy_strand(10, 0.2);
        if (!fall) sh->material.gravity = hk_v3_zero();
        hk_DynamicsDef p = undamped(); /* still air would drag the strand */
        hk_StrandDynamics *d = NULL;
        hk_Error err;
        assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
        hk_Vec3 rest[11];
        hk_superhelix_nodes(sh, NULL, rest, NULL);
        /* constant velocity without gravity; free fall (acceleration g) with gravity */
        const hk_Vec3 v0 = hk_v3(0.5, -0.2, 0.3), acc = fall ? sh->material.gravity : hk_v3_zero();
        const double dt = 1.0 / 30.0;
        hk_RigidState head = hk_rigid_identity();
        for (int i = 1; i <= 60; i++) {
            const double t = i * dt;
            head.trans = hk_v3_add(hk_v3_scale(v0, t), hk_v3_scale(acc, 0.5 * t * t));
            head.vel = hk_v3_madd(v0, acc, t);
            head.acc = acc;
            if (i == 1) /* the strand starts with the head's velocity */
                for (int j = 0; j < 30; j++) hk_strand_dynamics_velocity(d)[j] = 0.0;
            assert_int_equal(hk_strand_dynamics_step(d, &head, NULL, 0, dt, &err), HK_OK);
        }
        hk_Vec3 now[11];
        hk_superhelix_nodes(sh, NULL, now, NULL);
        for (int j = 0; j < 11; j++) hk_assert_near(hk_v3_dist(now[j], hk_v3_add(rest[j], head.trans)), 0.0, 1e-12);
        hk_strand_dynamics_destroy(d);
        hk_superhelix_destroy(sh);
    }
}

/* Air drag against its terminal velocity (issue 13, item 5). The drag law is paper 000
 * eq. 5a as docs/dynamics.md writes the generalized force: -int J^T nu r' ds, a force
 * -nu r' per unit length on the absolute velocity r' (still air; AirDrag in
 * include/hairkit/io.h). A length of strand of mass rho S falling in it obeys
 * rho S v' = -rho S g - nu v (v upward), so from rest
 *     v(t) = -v_t (1 - exp(-t / tau)),   v_t = rho S g / nu,   tau = rho S / nu,
 * with the terminal velocity v_t. The root of a strand is clamped to the head, so the
 * strand cannot fall on its own; its head is made to fall so instead. In the head's frame
 * each length of strand then feels its weight -rho S g, the inertial force -rho S a_head
 * = +rho S g exp(-t / tau) and the drag -nu v_head = +rho S g (1 - exp(-t / tau)): zero
 * in sum at every instant, so the strand keeps its zero-gravity rest shape (straight)
 * to rounding while its speed approaches v_t. A head going down steadily at V leaves the
 * weight rho S g - nu V = rho S g (1 - V / v_t) per length: the strand settles on the
 * statics shape (Newton's minimum, a second method) under the gravity g (1 - V / v_t):
 * half the sag at V = v_t / 2, none at v_t, the sag mirrored upwards at 2 v_t. With
 * nu = 1e-4 kg/(m s) (ten times the default; tau = 0.1 s, v_t = 1 m/s for this strand)
 * the runs are short: 1 s of fall (10 tau), 1.5 s of descent. */
typedef struct DragFall {
    double vt, tau, g;
} DragFall;

static void drag_fall_state(void *user, double t, hk_RigidState *out)
{
    const DragFall *f = user;
    *out = hk_rigid_identity();
    if (t < 0.0) return; /* released at t = 0: its acceleration is -g from then on */
    const double e = exp(-t / f->tau);
    out->trans = hk_v3(0.0, -f->vt * (t - f->tau * (1.0 - e)), 0.0);
    out->vel = hk_v3(0.0, -f->vt * (1.0 - e), 0.0);
    out->acc = hk_v3(0.0, -f->g * e, 0.0);
}

static void steady_descent_state(void *user, double t, hk_RigidState *out)
{
    const double v = *(const double *)user;
    *out = hk_rigid_identity();
    if (t <= 0.0) return;
    out->trans = hk_v3(0.0, -v * t, 0.0);
    out->vel = hk_v3(0.0, -v, 0.0);
}

/* Tip of sh (world) relative to the head's translation. */
static hk_Vec3 tip_in_head(const hk_SuperHelix *sh, const hk_RigidState *head)
{
    return hk_v3_sub(tip_of(sh), head->trans);
}

static void test_air_drag_terminal_velocity(void **state)
{
    (void)state;
    const double length = 0.02, g = 9.81, nu = 1e-4, dt = 0.01;
    /* The rest shapes at rest: straight without gravity, sagging with it. */
    hk_SuperHelix *ref = strand(4, length, g);
    const double rho_s = ref->material.mass_per_length;
    const DragFall fall = {rho_s * g / nu, rho_s / nu, g};
    const hk_Vec3 straight = tip_of(ref);
    hk_StrandEnvDef env = hk_default_strand_env_def();
    hk_StaticsDef so = hk_default_statics_def();
    hk_MinimizeResult res;
    hk_Error err;
    assert_int_equal(hk_statics_solve(ref, &env, &so, &res, &err), HK_OK);
    const double sag = straight.y - tip_of(ref).y;
    print_message("rho S = %.4g kg/m, nu = %g kg/(m s): terminal velocity %.4f m/s, tau %.4f s; the %g cm strand "
                  "sags %.3f mm at rest\n",
                  rho_s, nu, fall.vt, fall.tau, 100 * length, 1e3 * sag);
    assert_true(sag > 1e-4);
    hk_superhelix_destroy(ref);
    hk_DynamicsDef p = hk_default_dynamics_def();
    p.air_drag = nu;

    /* Falling with its head, from rest, straight: weightless all the way. */
    hk_SuperHelix *sh = strand(4, length, g);
    hk_StrandDynamics *d = NULL;
    assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
    double worst = 0.0;
    hk_RigidState head = hk_rigid_identity();
    for (int i = 0; i < 100; i++) {
        assert_int_equal(hk_strand_dynamics_advance(d, drag_fall_state, (void *)&fall, i * dt, dt, NULL, 0, NULL, &err),
                         HK_OK);
        drag_fall_state((void *)&fall, (i + 1) * dt, &head);
        worst = fmax(worst, hk_v3_dist(tip_in_head(sh, &head), straight));
    }
    double s = length;
    hk_Vec3 pos, vel;
    hk_strand_dynamics_points(d, &head, &s, 1, &pos, &vel);
    print_message("falling 1 s (10 tau) with drag: tip at %.4f m/s (v_t %.4f), at most %.2g m from the straight "
                  "shape (the sag at rest %.2g m)\n",
                  -vel.y, fall.vt, worst, sag);
    hk_assert_rel(-vel.y, fall.vt, 1e-4, 0.0); /* 1 - exp(-10) */
    assert_true(worst < 1e-6 * sag);
    hk_strand_dynamics_destroy(d);
    hk_superhelix_destroy(sh);

    /* Going down steadily at V from the sagging rest shape: the statics under
     * g (1 - V / v_t). */
    const double speeds[3] = {0.5, 1.0, 2.0};
    for (int k = 0; k < 3; k++) {
        const double v = speeds[k] * fall.vt;
        hk_SuperHelix *expect = strand(4, length, g * (1.0 - speeds[k]));
        assert_int_equal(hk_statics_solve(expect, &env, &so, &res, &err), HK_OK);
        sh = strand(4, length, g);
        assert_int_equal(hk_statics_solve(sh, &env, &so, &res, &err), HK_OK);
        assert_int_equal(hk_strand_dynamics_create(sh, &p, NULL, &d, &err), HK_OK);
        for (int i = 0; i < 150; i++)
            assert_int_equal(
                hk_strand_dynamics_advance(d, steady_descent_state, (void *)&v, i * dt, dt, NULL, 0, NULL, &err),
                HK_OK);
        steady_descent_state((void *)&v, 150 * dt, &head);
        const hk_Vec3 tip = tip_in_head(sh, &head), want = tip_of(expect);
        print_message("going down at %.2f v_t: tip %+.4f mm from straight (statics under %+.3f g: %+.4f mm; %.2g m "
                      "apart)\n",
                      speeds[k], 1e3 * (tip.y - straight.y), 1.0 - speeds[k], 1e3 * (want.y - straight.y),
                      hk_v3_dist(tip, want));
        assert_true(hk_v3_dist(tip, want) < 1e-3 * sag);
        hk_strand_dynamics_destroy(d);
        hk_superhelix_destroy(sh);
        hk_superhelix_destroy(expect);
    }
}

/* The four hair types of paper 000 Appendix B (examples/strand/), 20 cm strands (10 cm
 * for the fuzzy one) growing from the top of the head ellipsoid inside its 2 cm
 * envelope (level 0.5 of examples/strand/head.txt), from their statics rest shape as a
 * groomed head starts, on a head shaking 40 degrees at 1.5 Hz for 3 s at the paper's
 * dt = 1/30 s: every step succeeds and the
 * motion stays physical - no strand ever moves faster than 20 m/s (a blow-up reaches
 * astronomical speeds within a few steps), and the kinetic energy ends below that of
 * the whole strand moving with the head's fastest point, 1 m/s. */
static void head_state_of(void *user, double t, hk_RigidState *out) { hk_head_motion_eval(user, t, out); }

static void test_appendix_b_hair_stable_on_a_shaking_head(void **state)
{
    (void)state;
    const char *types[4] = {"straight", "wavy", "curly", "fuzzy"};
    hk_CollisionSet collision = {0};
    hk_Error err;
    assert_int_equal(hk_collision_load(HK_SOURCE_DIR "/examples/strand/head.txt", &collision, &err), HK_OK);
    hk_HeadMotion *shake = NULL;
    assert_int_equal(hk_head_motion_scripted("shake", 40.0, 1.5, hk_default_head_pivot(), &shake, &err), HK_OK);
    for (int k = 0; k < 4; k++) {
        /* from the statics rest shape, as a groomed head starts */
        hk_Hairstyle def;
        hk_StrandEnvDef body;
        hk_SuperHelix *sh = hk_test_strand_on_head(types[k], collision.shapes, collision.count, &def, &body);
        hk_DynamicsDef p = def.dynamics;
        hk_StrandDynamics *d = NULL;
        assert_int_equal(hk_strand_dynamics_create(sh, &p, &body, &d, &err), HK_OK);
        const int n = sh->n;
        double fastest = 0.0, kinetic = 0.0;
        for (int f = 0; f < 90; f++) {
            if (hk_strand_dynamics_advance(d, head_state_of, shake, f / 30.0, 1.0 / 30.0, NULL, 0, NULL, &err) != HK_OK)
                fail_msg("%s hair, frame %d: %s", types[k], f, err.message);
            hk_RigidState head;
            hk_head_motion_eval(shake, (f + 1) / 30.0, &head);
            double s[2] = {0.5 * sh->total_length, sh->total_length};
            hk_Vec3 pos[2], vel[2];
            hk_strand_dynamics_points(d, &head, s, 2, pos, vel);
            fastest = fmax(fastest, fmax(hk_v3_norm(vel[0]), hk_v3_norm(vel[1])));
            hk_strand_dynamics_energy(d, &head, &kinetic, NULL);
        }
        const double bound = 0.5 * sh->material.mass_per_length * sh->total_length * 1.0;
        print_message("%-8s N = %2d: fastest sample %.2f m/s, final kinetic energy %.3g J (bound %.3g J)\n", types[k],
                      n, fastest, kinetic, bound);
        assert_true(fastest < 20.0);
        assert_true(kinetic < bound);
        hk_strand_dynamics_destroy(d);
        hk_superhelix_destroy(sh);
        hk_hairstyle_free(&def);
    }
    hk_head_motion_destroy(shake);
    hk_collision_free(&collision);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cantilever_first_frequency),
        cmocka_unit_test(test_damped_strand_rests_on_statics),
        cmocka_unit_test(test_energy_never_rises),
        cmocka_unit_test(test_rotary_terms_conserve_energy),
        cmocka_unit_test(test_gyroscopic_couple_bends_a_spinning_rod),
        cmocka_unit_test(test_helix_at_zero_gravity_stays),
        cmocka_unit_test(test_translating_head_moves_strand_rigidly),
        cmocka_unit_test(test_air_drag_terminal_velocity),
        cmocka_unit_test(test_appendix_b_hair_stable_on_a_shaking_head),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
