/* Guide-guide interactions of the full-head dynamics (paper 000 §4.1, "Hair
 * interactions"): the public API, its input checks and the schedule of the broad
 * phase (every rescan_interval updates) against the tracking of pairs in between
 * (temporal coherence, after Raghupathi et al. 2003). */
#include <omp.h>
#include <string.h>

#include "hair_contacts_internal.h"
#include "core/avx_twins.h"

/* Largest strand and total sizes accepted: far beyond any head of guides, small
 * enough that every index and the broad phase's entries stay well inside int. */
#define HK_HC_MAX_SAMPLES (1 << 24)
#define HK_HC_MAX_STRANDS (1 << 24)

hk_HairContactDef hk_default_hair_contact_def(void)
{
    hk_HairContactDef p;
    memset(&p, 0, sizeof p); /* along 0, the default threads */
    /* A guide stands for a clump of a few hundred hairs (paper 000 §4.2): 300 fibres
     * of 40 um radius loosely packed make a lock about 5 mm across. */
    p.distance = 0.005;
    /* A guide carries one hair's mass, about 6.5e-6 kg/m, so a 20 cm guide weighs
     * 1.3e-5 N: k = 0.5 N/m holds that whole weight at 2.6e-5 m, 0.5% of d0. With an
     * effective mass m ~ 4e-7 kg at a contact, sqrt(k / m) dt ~ 36 at dt = 1/30 s: far
     * too stiff for an explicit step, fine for the implicit one the dynamics takes
     * (backward Euler on a linear spring is stable for any k), while k L^2 stays within
     * ~1e3 of the guide's mass terms m L^2 / dt^2 so the solve stays well conditioned. */
    p.stiffness = 0.5;
    /* About critical damping 2 sqrt(k m) = 9e-4 N s/m: with c_n dt / m ~ 80 the normal
     * relative speed is gone within a step, an inelastic collision of hair volumes. */
    p.damping = 1e-3;
    /* Of the order of the air drag on a whole guide (paper 000 §4.2: nu = 5e-6..5e-5
     * kg/(m s) over 0.2 m gives 1e-6..1e-5 N s/m): c_t dt / m ~ 0.8, so touching clumps
     * lose about half their relative sliding speed per frame without gluing. */
    p.friction = 1e-5;
    /* Fibre on fibre: Bertails-Descoubes, Cadoux, Daviet and Acary ("A nonsmooth Newton
     * solver for capturing exact Coulomb friction in fiber assemblies", ACM TOG 2011)
     * take mu = 0.3 for hair on hair, within the 0.1-0.4 measured for human hair
     * fibres sliding along each other. */
    p.friction_coefficient = 0.3;
    /* Roots of neighbouring guides are about 1 cm apart and leave the scalp along the
     * same layered envelope: the first 2 cm would be in permanent contact, fighting
     * the clamped root for nothing. */
    p.root_exclusion = 0.02;
    /* On a head of 401 guides a rescan costs ~25 tracked updates; rescanning every
     * other update, a contact that tracking cannot see (strands approaching from
     * beyond 2 d0) is found one update late, which concerns ~2% of the contacts of
     * a head swinging at 0.5 Hz (docs/dynamics.md, "Hair–hair contacts"). */
    p.rescan_interval = 2;
    return p;
}

static hk_Status check_params(const hk_HairContactDef *p, hk_Error *err)
{
    if (!(isfinite(p->distance) && p->distance > 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: distance must be > 0, got %g", p->distance);
    if (!(isfinite(p->stiffness) && p->stiffness >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: stiffness must be >= 0, got %g", p->stiffness);
    if (!(isfinite(p->damping) && p->damping >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: damping must be >= 0, got %g", p->damping);
    if (!(isfinite(p->friction) && p->friction >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: friction must be >= 0, got %g", p->friction);
    if (!(isfinite(p->friction_coefficient) && p->friction_coefficient >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: friction coefficient must be >= 0, got %g",
                            p->friction_coefficient);
    if (!(isfinite(p->root_exclusion) && p->root_exclusion >= 0.0))
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: root_exclusion must be >= 0, got %g",
                            p->root_exclusion);
    if (p->along != 0 && p->along != 1)
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: along must be 0 or 1, got %d", p->along);
    if (p->rescan_interval < 1)
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: rescan_interval must be >= 1, got %d",
                            p->rescan_interval);
    return HK_OK;
}

int hk_hc_threads(const hk_HairContacts *c) { return c->p.threads > 0 ? c->p.threads : omp_get_max_threads(); }

void hk_hc_set_threads(hk_HairContacts *c, int threads) { c->p.threads = threads; }

void hk_hc_set_geometry_only(hk_HairContacts *c, int on) { c->geometry_only = on; }

hk_Status hk_hair_contacts_create(int strand_count, const hk_HairContactDef *p, hk_HairContacts **out, hk_Error *err)
{
    if (!out) return hk_error_set(err, HK_ERR_INVALID, "hair contacts: no output pointer");
    *out = NULL;
    if (strand_count < 1 || strand_count > HK_HC_MAX_STRANDS)
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: strand count must be in [1, %d], got %d",
                            HK_HC_MAX_STRANDS, strand_count);
    hk_HairContactDef params = p ? *p : hk_default_hair_contact_def();
    hk_Status st = check_params(&params, err);
    if (st != HK_OK) return st;
    hk_HairContacts *c = hk_calloc_array(1, sizeof *c, err);
    if (!c) return HK_ERR_NOMEM;
    c->strand_count = strand_count;
    c->p = params;
    const size_t g = (size_t)strand_count;
    c->counts = hk_calloc_array(g, sizeof *c->counts, err);
    c->views = hk_calloc_array(g, sizeof *c->views, err);
    c->force_start = hk_calloc_array(g + 1, sizeof *c->force_start, err);
    c->force_order = hk_calloc_array(g, sizeof *c->force_order, err);
    if (!c->counts || !c->views || !c->force_start || !c->force_order) {
        hk_hair_contacts_destroy(c);
        return HK_ERR_NOMEM;
    }
    *out = c;
    return HK_OK;
}

void hk_hair_contacts_destroy(hk_HairContacts *c)
{
    if (!c) return;
    hk_hc_grid_free(c);
    hk_free(c->counts), hk_free(c->views), hk_free(c->pairs), hk_free(c->pairs_tmp), hk_free(c->bucket),
        hk_free(c->pair_order), hk_free(c->pair_key);
    hk_free(c->contacts), hk_free(c->forces), hk_free(c->force_start), hk_free(c->force_key);
    hk_free(c->force_order), hk_free(c->candidates);
    hk_free(c);
}

void hk_hair_contacts_request_rescan(hk_HairContacts *c)
{
    if (c) c->rescan_requested = 1;
}

/* Checks every strand before anything is changed. */
static hk_Status check_strands(const hk_HairContacts *c, const hk_StrandSamples *strands, int strand_count,
                               hk_Error *err)
{
    if (!strands) return hk_error_set(err, HK_ERR_INVALID, "hair contacts: no strands");
    if (strand_count != c->strand_count)
        return hk_error_set(err, HK_ERR_INVALID, "hair contacts: %d strands given, %d expected", strand_count,
                            c->strand_count);
    long total = 0;
    for (int g = 0; g < strand_count; g++) {
        const hk_StrandSamples *st = &strands[g];
        if (st->count < 2 || st->count > HK_HC_MAX_SAMPLES)
            return hk_error_set(err, HK_ERR_INVALID, "hair contacts: strand %d has %d samples, need 2..%d", g,
                                st->count, HK_HC_MAX_SAMPLES);
        if (!st->s || !st->pos)
            return hk_error_set(err, HK_ERR_INVALID, "hair contacts: strand %d has no %s", g,
                                st->s ? "positions" : "arc lengths");
        total += st->count - 1;
        if (total > HK_HC_MAX_SAMPLES)
            return hk_error_set(err, HK_ERR_INVALID, "hair contacts: more than %d segments in all", HK_HC_MAX_SAMPLES);
        for (int k = 0; k < st->count; k++) {
            if (!isfinite(st->s[k]) || (k > 0 && !(st->s[k] >= st->s[k - 1])))
                return hk_error_set(err, HK_ERR_INVALID,
                                    "hair contacts: strand %d sample %d: arc length %g is not finite or decreases", g,
                                    k, st->s[k]);
            if (!hk_v3_isfinite(st->pos[k]))
                return hk_error_set(err, HK_ERR_INVALID, "hair contacts: strand %d sample %d: position not finite", g,
                                    k);
            if (st->vel && !hk_v3_isfinite(st->vel[k]))
                return hk_error_set(err, HK_ERR_INVALID, "hair contacts: strand %d sample %d: velocity not finite", g,
                                    k);
        }
    }
    return HK_OK;
}

static void clear_forces(hk_HairContacts *c)
{
    memset(c->force_start, 0, (size_t)(c->strand_count + 1) * sizeof *c->force_start);
    c->contact_count = 0;
    for (int k = 0; k < c->pair_count && k < c->contact_cap; k++)
        c->contacts[k].force_index[0] = c->contacts[k].force_index[1] = -1;
}

hk_Status hk_hair_contacts_update(hk_HairContacts *c, const hk_StrandSamples *strands, int strand_count, hk_Error *err)
{
    HK_AVX_TWIN_RETURN(hk_hair_contacts_update, c, strands, strand_count, err);
    if (!c) return hk_error_set(err, HK_ERR_INVALID, "hair contacts: no contacts object");
    clear_forces(c);
    hk_Status st = check_strands(c, strands, strand_count, err);
    if (st != HK_OK) return st;
    int counts_changed = 0;
    for (int g = 0; g < strand_count; g++) {
        counts_changed |= strands[g].count != c->counts[g];
        c->views[g] = hk_hc_strand_view(&strands[g], c->p.root_exclusion);
    }
    const int rescan = c->updates == 0 || counts_changed || c->rescan_requested ||
                       c->updates % c->p.rescan_interval == 0 || c->p.along;
    c->distance_evaluations = 0;
    c->last_update_rescanned = rescan;
    if (rescan) {
        st = hk_hc_broad_phase(c, err);
    } else {
        st = hk_hc_track(c, err);
    }
    if (st == HK_OK) st = hk_hc_forces(c, err);
    if (st != HK_OK) {
        /* The tracked pairs may be half-updated: start afresh next time. */
        clear_forces(c);
        c->pair_count = 0;
        c->rescan_requested = 1;
        if (err && err->code == HK_OK) hk_error_set(err, st, "hair contacts: update failed");
        return st;
    }
    for (int g = 0; g < strand_count; g++) c->counts[g] = strands[g].count;
    c->rescan_requested = 0;
    c->updates++;
    return HK_OK;
}

int hk_hair_contacts_pair_count(const hk_HairContacts *c) { return c ? c->pair_count : 0; }

int hk_hair_contacts_contact_count(const hk_HairContacts *c) { return c ? c->contact_count : 0; }

int hk_hair_contacts_pair(const hk_HairContacts *c, int index, hk_HairContactPair *out)
{
    if (!c || !out || index < 0 || index >= c->pair_count) return 0;
    const hk_HcPair *p = &c->pairs[index];
    const hk_HcContact *ct = &c->contacts[index];
    out->strand[0] = p->i, out->strand[1] = p->j;
    out->segment[0] = p->a, out->segment[1] = p->b;
    for (int k = 0; k < 2; k++) out->s[k] = ct->s[k], out->point[k] = ct->point[k];
    out->distance = ct->distance;
    out->force[0] = ct->force_index[0], out->force[1] = ct->force_index[1];
    return 1;
}

const hk_PointForce *hk_hair_contacts_forces(const hk_HairContacts *c, int strand, int *count)
{
    int n = 0;
    const hk_PointForce *f = NULL;
    if (c && strand >= 0 && strand < c->strand_count) {
        n = c->force_start[strand + 1] - c->force_start[strand];
        if (n > 0) f = c->forces + c->force_start[strand];
    }
    if (count) *count = n;
    return f;
}
