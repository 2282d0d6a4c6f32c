/* Private parts of the guide-guide contacts, shared by hair_contacts.c (API and
 * input checks), segment_distance.c, hair_proximity.c (pairs and their walk),
 * hair_broad_phase.c (spatial hash) and hair_contact_forces.c (penalty forces), and
 * seen by tests/test_hair_contacts.c for its brute-force references. */
#ifndef HK_HAIR_CONTACTS_INTERNAL_H
#define HK_HAIR_CONTACTS_INTERNAL_H

#include "hairkit/hair_contacts.h"

/* Closest points of the segments [p0, p1] and [q0, q1]: parameters *u, *v in [0, 1]
 * of the points p0 + u (p1 - p0) and q0 + v (q1 - q0), and their squared distance
 * as the return value. Zero-length and parallel segments are handled (for parallel
 * ones the closest pair is not unique; one of them is returned, always the same for
 * the same input). */
double hk_segment_closest(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double *u, double *v);

/* A strand as the contacts see it: its samples and its first segment that reaches
 * beyond the root exclusion. Segments first..count-2 take part in contacts; the
 * first of them is clipped to start at s = root_exclusion. */
typedef struct hk_HcStrand {
    int count;
    int first; /* count - 1 when no segment takes part */
    const double *s;
    const hk_Vec3 *pos;
    const hk_Vec3 *vel; /* may be NULL */
} hk_HcStrand;

/* The view of an (already checked) strand for a root exclusion. */
hk_HcStrand hk_hc_strand_view(const hk_StrandSamples *in, double root_exclusion);

/* Ends of the part of segment k that takes part in contacts, and where that part
 * starts on the full segment (*t0 in [0, 1), 0 unless k is the clipped first one). */
void hk_hc_segment_ends(const hk_HcStrand *st, int k, double root_exclusion, hk_Vec3 *p0, hk_Vec3 *p1, double *t0);

/* The part of a segment that takes part in contacts, as hk_hc_segment_ends gives it. */
typedef struct hk_HcEnds {
    hk_Vec3 p0, p1;
    double t0;
} hk_HcEnds;

/* Squared distance of two segments' parts (x of strand si, y of strand sj), with the
 * parameters of the closest points on the full segments: hk_hc_pair_distance2 for
 * ends found once (the broad phase measures each segment against several). */
double hk_hc_ends_distance2(const hk_HcEnds *x, const hk_HcEnds *y, double *u, double *v);

/* Squared distance of segment a of strand si and segment b of strand sj (both taking
 * part), with the parameters of the closest points on the full segments. Always
 * evaluated in this argument order, so that the same pair gives the same bits. */
double hk_hc_pair_distance2(const hk_HcStrand *si, int a, const hk_HcStrand *sj, int b, double root_exclusion,
                            double *u, double *v);

/* How pairs are measured and compared. Squared distances are ranked on a grid of
 * quantum = 2^-40 d0^2 (a few fm at d0 = 5 mm) before the tie-break on the segment
 * indices: the rounding noise of equal distances (parallel strands sampled alike)
 * then no longer makes a local minimum of every other segment pair. */
typedef struct hk_HcMetric {
    double root_exclusion;
    double quantum;
} hk_HcMetric;

hk_HcMetric hk_hc_metric(const hk_HairContactDef *p);

/* Rank of a squared distance: floor(d2 / quantum), saturated for far pairs. */
long long hk_hc_rank(double d2, double quantum);

/* A tracked pair (i < j) and what the last update measured of it. */
typedef struct hk_HcPair {
    int i, a, j, b;
    double d2;   /* squared distance of the closest points */
    double u, v; /* parameters of the closest points on the full segments a and b */
} hk_HcPair;

/* Is (a, b) strictly below its up to 8 neighbours (a +- 1, b +- 1) in the order of
 * (rank of the squared distance, a, b)? d2 is the pair's own squared distance. */
int hk_hc_is_local_min(const hk_HcStrand *si, int a, const hk_HcStrand *sj, int b, double d2, const hk_HcMetric *m);

/* Walks the pair to the local minimum it leads to (moving to the smallest neighbour
 * while it is smaller), at most max_steps moves. Returns the distance evaluations. */
long hk_hc_walk(const hk_HcStrand *si, const hk_HcStrand *sj, const hk_HcMetric *m, hk_HcPair *p, int max_steps);

/* What an update computes for each pair, before it is dealt to the strands. */
typedef struct hk_HcContact {
    int active;         /* d < d0: the pair is a contact and gets forces */
    double distance;    /* |point[0] - point[1]| */
    int force_index[2]; /* position in each strand's sorted force list, -1 if inactive */
    double s[2];
    hk_Vec3 point[2];
    hk_Vec3 normal; /* unit, from point[1] to point[0] (any pair, active or not) */
    hk_Vec3 force;  /* on point[0]; point[1] gets its opposite */
    hk_Mat3 stiffness, damping;
} hk_HcContact;

struct hk_HairContacts {
    int strand_count;
    hk_HairContactDef p;
    long updates; /* successful updates so far */
    int rescan_requested;
    int *counts;        /* sample counts seen by the last successful update */
    hk_HcStrand *views; /* per strand, for the current update */

    hk_HcPair *pairs; /* tracked pairs, sorted by (i, a, j, b), unique */
    int pair_count, pair_cap;
    hk_HcPair *pairs_tmp; /* sorting buffer */
    int pairs_tmp_cap;
    int *bucket; /* counting-sort buckets (segments + 1) */
    int bucket_cap;
    int *pair_order; /* 2 per pair: the pairs by (j, b), the sort's first pass, then by (i, a, j, b) */
    int pair_order_cap;
    int *pair_key; /* 2 per pair: the global indices of its segments (j, b), then those of (i, a) */
    int pair_key_cap;

    hk_HcContact *contacts; /* per pair */
    int contact_cap, contact_count;

    hk_PointForce *forces; /* per strand, consecutive: strand g owns [force_start[g], force_start[g+1]) */
    int force_cap;
    int *force_start; /* strand_count + 1 */
    void *force_key;  /* sorting keys of the forces (s, record) */
    int force_key_cap;
    int *force_order; /* strand_count: fill positions while dealing the forces */

    /* Broad-phase scratch (hair_broad_phase.c). */
    void *grid;

    /* Every segment pair within 2 d0 found by the last broad phase (the tests compare
     * them with a brute-force search). */
    hk_HcPair *candidates;
    int candidate_count, candidate_cap;

    /* The pairs' geometry only (hk_hc_set_geometry_only): no penalty forces, no lists. */
    int geometry_only;

    /* Test and benchmark hooks. */
    long distance_evaluations; /* segment-pair distances computed by the last update */
    int last_update_rescanned;
};

/* The threads of the contacts' parallel loops: p.threads, or OpenMP's default. */
int hk_hc_threads(const hk_HairContacts *c);

/* Changes the threads of the next updates (the hair simulation's own change). */
void hk_hc_set_threads(hk_HairContacts *c, int threads);

/* With on = 1 the next updates find the pairs and their geometry (points, s, distance,
 * normal, active) but no penalty forces: hk_hair_contacts_forces then lists none and
 * the pairs' force indices are -1. The hair simulation's solve (hair_contact_solve.h)
 * takes the geometry alone; the penalty forces and their sorted lists were 0.4 % of
 * a frame there (examples/guides200 shaking). */
void hk_hc_set_geometry_only(hk_HairContacts *c, int on);

/* A value and an index, sorted by (at, index): a total order, so that any sort gives
 * the same result. */
typedef struct hk_HcKey {
    double at;
    int index;
} hk_HcKey;

/* Sorts keys[0, n) by (at, index) by insertion: about linear on keys nearly in order
 * (the contact solve's points dealt by segment, the split's roots as the last step
 * left them). */
void hk_hc_sort_keys(hk_HcKey *keys, int n);

/* Appends n pairs (growing the array); 0 and err filled when out of memory. */
int hk_hc_append_pairs(hk_HcPair **array, int *count, int *cap, const hk_HcPair *p, int n, hk_Error *err);

/* Appends a pair, the same way. Inline: the broad phase keeps 15,000 candidates a
 * rescan (examples/guides200 shaking), and the call cost 7.6 million instructions in
 * 8 frames. */
static inline int hk_hc_push_pair(hk_HcPair **array, int *count, int *cap, const hk_HcPair *p, hk_Error *err)
{
    if (*count >= *cap) return hk_hc_append_pairs(array, count, cap, p, 1, err);
    (*array)[(*count)++] = *p;
    return 1;
}

/* Sorts (*pairs)[0..n) by (i, a, j, b), stable: counting sorts on the global index of
 * the segment (j, b), then of (i, a). O(segments + pairs). The pairs are
 * sorted into c->pairs_tmp, which then takes the place of *pairs (and *cap), not
 * copied back. Until the next sort, hk_hc_run gives the run [*begin, *end) of the
 * pairs of segment (i, a). */
hk_Status hk_hc_sort(hk_HairContacts *c, hk_HcPair **pairs, int *cap, int n, hk_Error *err);
void hk_hc_run(const hk_HairContacts *c, int i, int a, int *begin, int *end);

/* Sorts c->pairs and drops repeated ones (two tracked pairs that reached the same). */
hk_Status hk_hc_sort_unique(hk_HairContacts *c, hk_Error *err);

/* Walks every tracked pair (in parallel), drops those beyond 2 d0, sorts, merges. */
hk_Status hk_hc_track(hk_HairContacts *c, hk_Error *err);

/* Broad phase: replaces c->pairs by every local-minimum pair within 2 d0. */
hk_Status hk_hc_broad_phase(hk_HairContacts *c, hk_Error *err);
void hk_hc_grid_free(hk_HairContacts *c);

/* Penalty forces of the pairs, dealt to the strands and sorted by s. */
hk_Status hk_hc_forces(hk_HairContacts *c, hk_Error *err);

#endif
