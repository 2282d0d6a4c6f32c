/* Follicle sampling by a particle system on an implicit surface (Piuze et al. 2011 §4.3 after
 * Witkin & Heckbert, "Using particles to sample and control implicit surfaces",
 * SIGGRAPH 1994): Gaussian repulsion with an adaptive radius per particle, velocities
 * projected on the surface's tangent plane and a Newton step back onto f = 0,
 * fission of under-crowded particles and death of over-crowded ones, fixed particles
 * that repel but never move.
 *
 * Adaptations, and why:
 * - The target is a spacing d rather than W&H's desired energy alone: the ideal
 *   radius is sigma* = d / 2 and the desired energy E^ = 6 K(2) is what a particle of
 *   radius sigma* feels in a hexagonal packing of spacing d (its 6 neighbours at
 *   rho = 2; the kernel K is cut at rho = 3, inside the second ring at 2 sqrt(3)).
 *   Each particle's radius follows its energy to E^, so sigma_i / sigma* estimates
 *   the local spacing over d: above SIGMA_HI the particle fissions, below SIGMA_LO it
 *   may die. A narrow band (5%) puts the count within a few % of the hexagonal
 *   packing's area / (sqrt(3)/2 d^2); a wide one lets it settle anywhere inside.
 * - W&H move particles continuously and decide on fission and death as they go. Here
 *   an iteration moves every particle from the same snapshot (in parallel), then
 *   visits births and deaths in index order with random numbers keyed by (seed,
 *   particle id, iteration): the same seed gives the same bytes with any threads.
 * - W&H let only particles near equilibrium fission or die; a particle nearly alone
 *   (radius 1.5 sigma*) fissions anyway, or growth from one seed crawls.
 * - After the population settles (no birth or death for QUIET_ITERATIONS), the
 *   radii are set to sigma* and the particles relax with a fixed count: equal radii
 *   make the repulsion equalise the spacing.
 * - A mask inside(x) says where hair grows: a move or a child that would leave it is
 *   refused. Without fixed particles along its edge, particles crowd there (they
 *   miss neighbours outside); the paper's fixed contour particles fill that role. */
#include <math.h>
#include <omp.h>
#include <string.h>
#include <time.h>

#include "core/core_internal.h"
#include "follicle_internal.h"
#include "hairkit/follicle_sampling.h"
#include "hairkit/rng.h"

hk_FollicleSamplingDef hk_default_follicle_sampling_def(void)
{
    hk_FollicleSamplingDef d;
    memset(&d, 0, sizeof d);
    d.spacing = 0.0;
    d.max_particles = 100000;
    d.max_iterations = 600;
    d.relax_iterations = 80;
    d.seed = 1;
    return d;
}

void hk_follicle_samples_free(hk_FollicleSamples *s)
{
    hk_free(s->points);
    hk_free(s->normals);
    memset(s, 0, sizeof *s);
}

/* Tuning (radii in sigma*, lengths in d), chosen on spheres and the wick; see
 * docs/follicle-sampling.md. */
#define SIGMA_HI         1.05 /* fission above */
#define SIGMA_LO         0.95 /* death below */
#define SIGMA_LONELY     1.5  /* fission even while moving */
#define SIGMA_CAP        2.0  /* radius bounds: the cap bounds the neighbour grid's cells */
#define SIGMA_FLOOR      0.25
#define P_FISSION        0.5  /* per iteration, for a particle that qualifies */
#define P_DEATH          0.1  /* W&H: deaths at random, lest a crowd die all at once */
#define DT               0.3  /* Euler step of the repulsion velocity (stable below ~0.6) */
#define MAX_STEP         0.2  /* largest move per iteration, in d */
#define SETTLED_SPEED    0.05 /* a particle moving less (in sigma_i) may fission or die */
#define QUIET_ITERATIONS 40

typedef struct Sampler {
    hk_ImplicitFunction fn;
    const hk_FollicleSamplingDef *def;
    double d, sigma_star, e_star;
    int fixed; /* particles [0, fixed) are the fixed ones */
    int n;     /* free particles are [fixed, fixed + n) */
    int cap;   /* fixed + max free */
    hk_Vec3 *pos, *nrm;
    double *sigma;
    uint64_t *id;
    /* per iteration, for the free particles */
    hk_Vec3 *new_pos, *new_nrm;
    double *new_sigma, *speed;
    hk_PointGrid grid;
    uint64_t next_id;
    int parallel_from; /* particles below which an iteration runs on one thread */
} Sampler;

typedef struct Accum {
    const Sampler *s;
    int self;
    hk_Vec3 p;
    double sigma;
    double energy, denergy; /* E_i and dE_i / d ln sigma_i */
    hk_Vec3 repulsion;      /* W&H's D_i */
} Accum;

/* W&H's Gaussian kernel in rho = r / sigma, cut at rho = 3 in the "shifted force"
 * way of molecular dynamics (Allen & Tildesley, Computer Simulation of Liquids,
 * §5.2.3): with u = rho^2 and G(u) = exp(-u / 2),
 *   K(u) = G(u) - G(9) + (u - 9) G(9) / 2,
 * so the energy and the force both vanish at the cut. A hard cut makes the force
 * jump and the particles chatter across it instead of coming to rest. Returns K and
 * writes g = -K'(rho) / rho = G(u) - G(9), which is what the velocities use. */
#define CUT2 9.0
static double kernel(double u, double *g)
{
    const double e = exp(-0.5 * u), e9 = exp(-0.5 * CUT2);
    *g = e - e9;
    return e - e9 + (u - CUT2) * 0.5 * e9;
}

/* Particle i against j (W&H §5): K(r / sigma_i) enters i's energy E_i, and the velocity
 *   D_i = sigma_i^2 sum_j (r_ij / sigma_i^2 g^i_j + r_ij / sigma_j^2 g^j_i)
 * descends both particles' energies, scaled to i's radius. dE_i / d ln sigma_i is
 * sum_j rho^2 g^i_j. */
static void visit_neighbour(void *user, int j)
{
    Accum *a = user;
    if (j == a->self) return;
    const Sampler *s = a->s;
    const hk_Vec3 r = hk_v3_sub(a->p, s->pos[j]);
    const double r2 = hk_v3_norm2(r);
    const double si2 = a->sigma * a->sigma, sj2 = s->sigma[j] * s->sigma[j];
    double coef = 0.0, g;
    if (r2 < CUT2 * si2) {
        a->energy += kernel(r2 / si2, &g);
        a->denergy += r2 / si2 * g;
        coef += g;
    }
    if (r2 < CUT2 * sj2) {
        kernel(r2 / sj2, &g);
        coef += si2 / sj2 * g;
    }
    a->repulsion = hk_v3_madd(a->repulsion, r, coef);
}

static int inside(const Sampler *s, hk_Vec3 x) { return !s->def->inside || s->def->inside(s->def->inside_user, x); }

/* Projects q onto the surface within tol and the mask: 1 on success. */
static int place(const Sampler *s, hk_Vec3 q, double tol, hk_Vec3 *out, hk_Vec3 *out_n)
{
    return hk_implicit_project(s->fn, q, tol, 0.5 * s->d, out, out_n) && inside(s, *out);
}

/* One particle's move and radius update from the current snapshot. */
static void update_particle(Sampler *s, int i, int adapt)
{
    const int k = s->fixed + i;
    Accum a = {s, k, s->pos[k], s->sigma[k], 0.0, 0.0, hk_v3_zero()};
    hk_point_grid_query(&s->grid, a.p, visit_neighbour, &a);
    double sigma = s->sigma[k];
    if (adapt) {
        /* Newton step on ln sigma towards E_i = E^ (W&H's radius control), damped by
         * beta for isolated particles (dE -> 0) and limited per iteration. */
        double step = -(a.energy - s->e_star) / (a.denergy + 0.1 * s->e_star);
        step = fmax(-0.15, fmin(0.15, step));
        sigma = fmin(SIGMA_CAP * s->sigma_star, fmax(SIGMA_FLOOR * s->sigma_star, sigma * exp(step)));
    }
    s->new_sigma[i] = sigma;
    /* the constrained velocity: the tangential part of D_i (W&H §4) */
    const hk_Vec3 n = s->nrm[k];
    hk_Vec3 v = hk_v3_scale(a.repulsion, DT);
    v = hk_v3_madd(v, n, -hk_v3_dot(v, n));
    const double len = hk_v3_norm(v);
    if (len > MAX_STEP * s->d) v = hk_v3_scale(v, MAX_STEP * s->d / len);
    s->new_pos[i] = s->pos[k];
    s->new_nrm[i] = n;
    s->speed[i] = 0.0;
    if (len < 1e-9 * s->d) return;
    /* a move that leaves the mask or fails to project is halved, then refused */
    for (int tries = 0; tries < 3; tries++, v = hk_v3_scale(v, 0.5)) {
        hk_Vec3 q, qn;
        if (place(s, hk_v3_add(a.p, v), 1e-6 * s->d, &q, &qn)) {
            s->new_pos[i] = q;
            s->new_nrm[i] = qn;
            s->speed[i] = hk_v3_dist(q, a.p);
            return;
        }
    }
}

/* Any unit vector perpendicular to n, continuous enough for a random rotation. */
static hk_Vec3 tangent_of(hk_Vec3 n)
{
    const hk_Vec3 a = fabs(n.x) < 0.6 ? hk_v3_unit(0) : (fabs(n.y) < 0.6 ? hk_v3_unit(1) : hk_v3_unit(2));
    return hk_v3_normalize(hk_v3_cross(n, a));
}

/* Births and deaths, in index order. Returns the number of changes. */
static int population(Sampler *s, int iteration, int *births, int *deaths)
{
    const uint64_t seed = s->def->seed;
    const int n0 = s->n;
    int changes = 0, alive = s->n;
    for (int i = 0; i < n0; i++) {
        const int k = s->fixed + i;
        /* W&H decide near equilibrium only, except that a particle far too big
         * (nearly alone) splits at once: growth from a few seeds stays fast */
        const int settled = s->speed[i] <= SETTLED_SPEED * s->sigma[k];
        const int lonely = s->sigma[k] >= SIGMA_LONELY * s->sigma_star;
        if (!settled && !lonely) continue;
        const double u = hk_rng_uniform(seed, s->id[k], 2 * (uint64_t)iteration);
        if (s->sigma[k] > SIGMA_HI * s->sigma_star && s->fixed + s->n < s->cap) {
            if (u >= P_FISSION) continue;
            /* W&H fission: two children half the parent's radius apart along a random
             * tangent, each with the radius of half the area, sigma / sqrt(2). */
            const double theta = 2.0 * HK_PI * hk_rng_uniform(seed, s->id[k], 2 * (uint64_t)iteration + 1);
            const hk_Vec3 n = s->nrm[k], t1 = tangent_of(n), t2 = hk_v3_cross(n, t1);
            const hk_Vec3 t = hk_v3_add(hk_v3_scale(t1, cos(theta)), hk_v3_scale(t2, sin(theta)));
            const double delta = 0.5 * s->sigma[k];
            hk_Vec3 pa, na, pb, nb;
            if (!place(s, hk_v3_madd(s->pos[k], t, delta), 1e-6 * s->d, &pa, &na) ||
                !place(s, hk_v3_madd(s->pos[k], t, -delta), 1e-6 * s->d, &pb, &nb))
                continue;
            const double sigma = s->sigma[k] / sqrt(2.0);
            const int c = s->fixed + s->n;
            s->pos[k] = pa, s->nrm[k] = na, s->sigma[k] = sigma, s->id[k] = s->next_id++;
            s->pos[c] = pb, s->nrm[c] = nb, s->sigma[c] = sigma, s->id[c] = s->next_id++;
            s->speed[c - s->fixed] = 0.0;
            s->n++;
            alive++;
            (*births)++;
            changes++;
        } else if (s->sigma[k] < SIGMA_LO * s->sigma_star && u < P_DEATH && (alive > 1 || s->fixed > 0)) {
            /* (the decisions read radii from before this pass: without fixed
             * particles, keep one, lest a crowd of seeds die to the last) */
            s->id[k] = 0; /* marked; ids of the living start at 1 */
            alive--;
            (*deaths)++;
            changes++;
        }
    }
    /* compact the living, keeping their order */
    int m = 0;
    for (int i = 0; i < s->n; i++) {
        const int k = s->fixed + i;
        if (s->id[k] == 0) continue;
        const int t = s->fixed + m++;
        s->pos[t] = s->pos[k], s->nrm[t] = s->nrm[k], s->sigma[t] = s->sigma[k], s->id[t] = s->id[k];
    }
    s->n = m;
    return changes;
}

static hk_Status check_def(const hk_FollicleSamplingDef *d, const hk_Vec3 *seeds, int seed_count, hk_Error *err)
{
    if (!(d->spacing > 0.0) || !isfinite(d->spacing))
        return hk_error_set(err, HK_ERR_INVALID, "follicle spacing must be > 0, got %g", d->spacing);
    if (d->max_particles < 1 || d->max_particles > HK_SAMPLING_MAX_PARTICLES)
        return hk_error_set(err, HK_ERR_INVALID, "max_particles must be in [1, %d], got %d", HK_SAMPLING_MAX_PARTICLES,
                            d->max_particles);
    if (d->fixed_count < 0 || d->fixed_count > HK_SAMPLING_MAX_PARTICLES - d->max_particles ||
        (d->fixed_count && !d->fixed))
        return hk_error_set(err, HK_ERR_INVALID, "fixed particles: %d with max_particles %d (together at most %d)",
                            d->fixed_count, d->max_particles, HK_SAMPLING_MAX_PARTICLES);
    if (d->max_iterations < 1 || d->max_iterations > 1000000 || d->relax_iterations < 0 ||
        d->relax_iterations > d->max_iterations)
        return hk_error_set(err, HK_ERR_INVALID,
                            "iterations: max %d, relax %d (need 1 <= max <= 1e6, 0 <= relax <= max)", d->max_iterations,
                            d->relax_iterations);
    if (seed_count < 1 || !seeds)
        return hk_error_set(err, HK_ERR_INVALID, "follicle sampling needs at least one seed particle, got %d",
                            seed_count);
    if (seed_count > d->max_particles)
        return hk_error_set(err, HK_ERR_INVALID, "%d seeds exceed max_particles %d", seed_count, d->max_particles);
    double extent = 0.0;
    for (int i = 0; i < seed_count; i++) {
        if (!hk_v3_isfinite(seeds[i])) return hk_error_set(err, HK_ERR_INVALID, "seed %d is not finite", i);
        extent = fmax(extent, fmax(fabs(seeds[i].x), fmax(fabs(seeds[i].y), fabs(seeds[i].z))));
    }
    for (int i = 0; i < d->fixed_count; i++) {
        if (!hk_v3_isfinite(d->fixed[i]))
            return hk_error_set(err, HK_ERR_INVALID, "fixed particle %d is not finite", i);
        extent = fmax(extent, fmax(fabs(d->fixed[i].x), fmax(fabs(d->fixed[i].y), fabs(d->fixed[i].z))));
    }
    /* the neighbour grid counts cells in 32 bits (and so much detail is absurd) */
    if (d->spacing < 1e-8 * extent)
        return hk_error_set(err, HK_ERR_INVALID, "follicle spacing %g is too small for coordinates as large as %g",
                            d->spacing, extent);
    return HK_OK;
}

/* An iteration costs a few evaluations of f per particle, from well under a
 * microsecond (an analytic sphere) to tens (a fitted surface of thousands of
 * centres). Waking threads for less than ~0.2 ms of work loses more than it gains
 * (much more on virtual machines, where sleeping OpenMP workers wake slowly), so time
 * a few evaluations once. Only the speed depends on this: each particle's update is
 * the same on any thread. */
static int parallel_threshold(hk_ImplicitFunction fn, hk_Vec3 x)
{
    hk_Vec3 g;
    double sink = 0.0;
    const double t0 = hk_seconds_now();
    for (int k = 0; k < 16; k++) sink += fn.eval(fn.user, hk_v3_add(x, hk_v3(1e-9 * k, 0, 0)), &g);
    const double per_eval = (hk_seconds_now() - t0) / 16.0;
    if (!isfinite(sink) || !(per_eval > 0.0)) return 64;
    const double n = 2e-4 / (3.0 * per_eval);
    return n < 16.0 ? 16 : (n > 1e6 ? 1000000 : (int)n);
}

static void sampler_free(Sampler *s)
{
    hk_free(s->pos), hk_free(s->nrm), hk_free(s->sigma), hk_free(s->id);
    hk_free(s->new_pos), hk_free(s->new_nrm), hk_free(s->new_sigma), hk_free(s->speed);
    hk_point_grid_free(&s->grid);
}

static hk_Status sampler_alloc(Sampler *s, hk_Error *err)
{
    const size_t cap = (size_t)s->cap, free_cap = (size_t)(s->cap - s->fixed);
    s->pos = hk_alloc_array(cap, sizeof(hk_Vec3), err);
    s->nrm = hk_alloc_array(cap, sizeof(hk_Vec3), err);
    s->sigma = hk_alloc_array(cap, sizeof(double), err);
    s->id = hk_alloc_array(cap, sizeof(uint64_t), err);
    s->new_pos = hk_alloc_array(free_cap, sizeof(hk_Vec3), err);
    s->new_nrm = hk_alloc_array(free_cap, sizeof(hk_Vec3), err);
    s->new_sigma = hk_alloc_array(free_cap, sizeof(double), err);
    s->speed = hk_alloc_array(free_cap, sizeof(double), err);
    if (!s->pos || !s->nrm || !s->sigma || !s->id || !s->new_pos || !s->new_nrm || !s->new_sigma || !s->speed)
        return HK_ERR_NOMEM;
    return HK_OK;
}

/* Moves every free particle once; adapt: update the radii too. Returns the largest
 * move. */
static hk_Status iterate(Sampler *s, int adapt, int threads, double *max_move, hk_Error *err)
{
    *max_move = 0.0;
    if (s->n == 0) return HK_OK; /* every free particle died: the fixed ones cover all */
    double sigma_max = 0.0;
    for (int k = 0; k < s->fixed + s->n; k++) sigma_max = fmax(sigma_max, s->sigma[k]);
    hk_Status st = hk_point_grid_build(&s->grid, s->pos, s->fixed + s->n, 3.0 * sigma_max, err);
    if (st != HK_OK) return st;
#pragma omp parallel for schedule(dynamic, 16) num_threads(threads) if (s->n >= s->parallel_from)
    for (int i = 0; i < s->n; i++) update_particle(s, i, adapt);
    double m = 0.0;
    for (int i = 0; i < s->n; i++) {
        const int k = s->fixed + i;
        s->pos[k] = s->new_pos[i], s->nrm[k] = s->new_nrm[i], s->sigma[k] = s->new_sigma[i];
        m = fmax(m, s->speed[i]);
    }
    *max_move = m;
    return HK_OK;
}

hk_Status hk_sample_follicles(hk_ImplicitFunction fn, const hk_Vec3 *seeds, int seed_count,
                              const hk_FollicleSamplingDef *def, hk_FollicleSamples *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    if (!fn.eval) return hk_error_set(err, HK_ERR_INVALID, "follicle sampling needs a surface");
    const hk_FollicleSamplingDef defaults = hk_default_follicle_sampling_def();
    if (!def) def = &defaults;
    hk_Status st = check_def(def, seeds, seed_count, err);
    if (st != HK_OK) return st;
    const int threads = def->threads > 0 ? def->threads : omp_get_max_threads();
    Sampler s;
    memset(&s, 0, sizeof s);
    s.fn = fn;
    s.def = def;
    s.d = def->spacing;
    s.sigma_star = 0.5 * s.d;
    s.e_star = 6.0 * kernel(4.0, &(double){0.0});
    s.fixed = def->fixed_count;
    s.cap = def->fixed_count + def->max_particles;
    s.next_id = 1;
    if ((st = sampler_alloc(&s, err)) != HK_OK) goto done;
    for (int k = 0; k < s.fixed; k++) {
        s.pos[k] = def->fixed[k];
        s.nrm[k] = hk_v3_zero(); /* fixed particles never use theirs */
        s.sigma[k] = s.sigma_star;
        s.id[k] = s.next_id++;
    }
    for (int i = 0; i < seed_count; i++) {
        hk_Vec3 p, n;
        if (!hk_implicit_project(fn, seeds[i], 1e-6 * s.d, 0.5 * s.d, &p, &n)) {
            st = hk_error_set(err, HK_ERR_NUMERIC, "seed %d at (%g, %g, %g) cannot be projected onto the surface", i,
                              seeds[i].x, seeds[i].y, seeds[i].z);
            goto done;
        }
        if (!inside(&s, p)) continue;
        const int k = s.fixed + s.n++;
        s.pos[k] = p, s.nrm[k] = n, s.sigma[k] = s.sigma_star, s.id[k] = s.next_id++;
    }
    if (s.n == 0) {
        st = hk_error_set(err, HK_ERR_INVALID, "all %d seeds fall outside the region where hair grows", seed_count);
        goto done;
    }

    s.parallel_from = parallel_threshold(fn, s.pos[s.fixed]);

    /* population control, then relaxation with the count frozen */
    const int population_budget = def->max_iterations - def->relax_iterations;
    int it = 0, quiet = 0;
    double max_move = 0.0;
    /* Progress: the population phase usually settles early (QUIET_ITERATIONS without a
     * birth or death); the bar counts it against its budget, then the relaxation. */
    const double total = (double)def->max_iterations;
    for (; it < population_budget && quiet < QUIET_ITERATIONS && s.n > 0; it++) {
        if ((st = iterate(&s, 1, threads, &max_move, err)) != HK_OK) goto done;
        quiet = population(&s, it, &out->births, &out->deaths) ? 0 : quiet + 1;
        if (def->progress) def->progress(def->progress_user, "follicles", (double)it / total);
    }
    for (int k = 0; k < s.fixed + s.n; k++) s.sigma[k] = s.sigma_star;

    for (int r = 0; r < def->relax_iterations && s.n > 0; r++, it++) {
        if ((st = iterate(&s, 0, threads, &max_move, err)) != HK_OK) goto done;
        if (def->progress) def->progress(def->progress_user, "follicles", (double)(population_budget + r) / total);
        if (max_move < 1e-6 * s.d) {
            it++;
            break;
        }
    }
    out->iterations = it;
    if (def->progress) def->progress(def->progress_user, "follicles", 1.0);

    out->points = hk_alloc_array((size_t)s.n, sizeof(hk_Vec3), err);
    out->normals = hk_alloc_array((size_t)s.n, sizeof(hk_Vec3), err);
    if (!out->points || !out->normals) {
        st = HK_ERR_NOMEM;
        goto done;
    }
/* The iterations project to 1e-6 d; finish with Newton to 1e-9 d where rounding
 * allows and the mask agrees (else the point stays where it was). */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int i = 0; i < s.n; i++) {
        const int k = s.fixed + i;
        hk_Vec3 p, n;
        if (hk_implicit_project(fn, s.pos[k], 1e-9 * s.d, 0.0, &p, &n) && inside(&s, p)) s.pos[k] = p, s.nrm[k] = n;
        out->points[i] = s.pos[k];
        out->normals[i] = s.nrm[k];
    }
    out->count = s.n;
done:
    sampler_free(&s);
    if (st != HK_OK) hk_follicle_samples_free(out);
    return st;
}
