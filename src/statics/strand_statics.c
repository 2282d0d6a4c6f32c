/* Rest shape of one strand: minimisation of the Super-Helix energy (Bertails et al. 2006 §3,
 * Lansink 2010 §4.1.1.4) with the thesis's Rosenbrock search or the Newton default. */
#include "hairkit/statics.h"

#include <math.h>
#include <string.h>
#include <strings.h>

typedef struct StrandProblem {
    const hk_SuperHelix *sh;
    const hk_StrandEnvDef *env;
    hk_StrandWorkspace *ws;
} StrandProblem;

static double strand_value(void *user, const double *q)
{
    const StrandProblem *pb = user;
    return hk_strand_energy(pb->sh, pb->env, q, pb->ws, NULL, NULL, NULL);
}

static double strand_derivs(void *user, const double *q, double *grad, double *hess)
{
    const StrandProblem *pb = user;
    return hk_strand_energy(pb->sh, pb->env, q, pb->ws, grad, hess, NULL);
}

hk_StaticsDef hk_default_statics_def(void)
{
    hk_StaticsDef o;
    o.solver = HK_SOLVER_NEWTON;
    o.rosenbrock = hk_default_rosenbrock_def();
    o.newton = hk_default_newton_def();
    /* Each Newton step turns no element by more than half a radian: far from rest it
     * keeps the strand from leaping through wild twists into a poor local minimum. */
    o.newton.max_step = 0.5;
    return o;
}

hk_RosenbrockDef hk_rosenbrock_def_for(const hk_StrandDef *def)
{
    hk_RosenbrockDef o = hk_default_rosenbrock_def();
    o.max_stages = def->max_iter;
    o.epsilon = def->epsilon;
    /* The thesis gives no initial step. One radian of bending over the strand length
     * is the natural unit of curvature; the search grows or shrinks it from there. */
    const double length = hk_strand_def_length(def);
    if (length > 0.0) o.initial_step = 1.0 / length;
    return o;
}

const char *hk_solver_name(hk_SolverKind kind) { return kind == HK_SOLVER_ROSENBROCK ? "rosenbrock" : "newton"; }

int hk_solver_from_name(const char *name)
{
    if (!strcasecmp(name, "newton")) return HK_SOLVER_NEWTON;
    if (!strcasecmp(name, "rosenbrock")) return HK_SOLVER_ROSENBROCK;
    return -1;
}

/* Characteristic energy of a strand: bending it by a radian over its length plus
 * lifting its weight by its length. Convergence is measured against it, so that the
 * stopping test does not depend on where the zero of gravity energy lies. */
static double energy_scale(const hk_SuperHelix *sh)
{
    const double len = sh->total_length;
    double bend = 0.0;
    for (int i = 0; i < 3; i++) bend += sh->material.stiffness[i];
    bend *= 1.0 / len;
    return bend + sh->material.mass_per_length * hk_v3_norm(sh->material.gravity) * len * len;
}

hk_Status hk_statics_solve(hk_SuperHelix *sh, const hk_StrandEnvDef *env, const hk_StaticsDef *options,
                           hk_MinimizeResult *result, hk_Error *err)
{
    const hk_StrandEnvDef no_env = hk_default_strand_env_def();
    const hk_StaticsDef defaults = hk_default_statics_def();
    if (!env) env = &no_env;
    if (!options) options = &defaults;
    const int dim = 3 * sh->n;
    StrandProblem pb = {sh, env, NULL};
    hk_Status st = hk_strand_workspace_create(sh, env, &pb.ws, err);
    if (st != HK_OK) return st;
    /* q and the metric in one block. */
    double *q = hk_alloc_array((size_t)dim * 3, sizeof(double), err);
    if (!q) {
        hk_strand_workspace_destroy(pb.ws);
        return HK_ERR_NOMEM;
    }
    double *metric = q + dim, *unit = q + 2 * dim;
    memcpy(q, sh->q, (size_t)dim * sizeof(double));
    if (options->solver == HK_SOLVER_ROSENBROCK) {
        st = hk_rosenbrock_minimize(dim, q, strand_value, &pb, &options->rosenbrock, result, err);
    } else {
        /* The elastic diagonal l_Q K_i makes the damping independent of units. */
        for (int p = 0; p < sh->n; p++)
            for (int i = 0; i < 3; i++) {
                metric[3 * p + i] = sh->length[p] * sh->material.stiffness[i];
                /* A change of 1 / l_Q turns element Q's end by a radian. */
                unit[3 * p + i] = 1.0 / sh->length[p];
            }
        hk_NewtonDef no = options->newton;
        if (!(no.energy_scale > 0.0)) no.energy_scale = energy_scale(sh);
        if (!no.step_unit) no.step_unit = unit;
        st = hk_newton_minimize(dim, q, strand_derivs, &pb, metric, &no, result, err);
    }
    if (st == HK_OK) memcpy(sh->q, q, (size_t)dim * sizeof(double));
    hk_free(q);
    hk_strand_workspace_destroy(pb.ws);
    return st;
}
