/* Guide-guide hair interactions for the full-head dynamics (paper 000 §4.1, "Hair
 * interactions").
 *
 * Detection exploits temporal coherence as in Raghupathi et al. 2003: instead of a
 * quadratic proximity search every step, pairs of closest points between guide
 * strands are kept from one update to the next and walked to the locally closest
 * segment pair. A spatial-hash broad phase discovers new pairs every few updates.
 * Contacts between the hair volumes the guides stand for are answered with
 * dissipative penalty forces as in Choe et al. 2005: a normal elastic response on
 * the overlap plus a normal damping, never pulling, and a tangential viscous
 * friction (paper 000 §4.1).
 *
 * Vocabulary. A strand is given as a polyline of `count` samples; segment k joins
 * samples k and k + 1. A pair is (strand i, segment a, strand j, segment b) with
 * i < j whose segment distance is a local minimum over the neighbouring segment
 * pairs (a +- 1, b +- 1), ties broken by (a, b), and is below 2 d0. A pair is a
 * contact when that distance is below d0. One pair stands for one crossing (or one
 * place where two guides come closest); an extended side-by-side contact is felt at
 * its closest point, which moves along as the strands move.
 *
 * Out of scope: self-contacts of a strand (a pair never joins two segments of the
 * same strand) and contacts missed between discrete updates (a guide that crosses
 * another within one step is not pushed back; hair volumes interpenetrate anyway). */
#ifndef HAIRKIT_HAIR_CONTACTS_H
#define HAIRKIT_HAIR_CONTACTS_H

#include "hairkit/core.h"
#include "hairkit/dynamics.h" /* hk_PointForce: a force at one point of a strand */
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One guide strand at the current time: `count` >= 2 samples with arc lengths s
 * (non-decreasing; the root is at s = 0), world positions and world velocities.
 * vel may be NULL (all velocities zero). The arrays are read during
 * hk_hair_contacts_update only. */
typedef struct hk_StrandSamples {
    int count;
    const double *s;
    const hk_Vec3 *pos;
    const hk_Vec3 *vel;
} hk_StrandSamples;

typedef struct hk_HairContactDef {
    double distance;             /* contact distance d0 (m) > 0: the guides stand for clumps of hair of
                                    this diameter; pairs are tracked while closer than 2 d0 */
    double stiffness;            /* normal penalty stiffness k (N/m) >= 0 on the overlap (d0 - d) */
    double damping;              /* normal dissipation c_n (N s/m) >= 0 on the normal relative speed */
    double friction;             /* tangential viscous friction c_t (N s/m) >= 0 on the sliding velocity */
    double friction_coefficient; /* Coulomb's mu >= 0 of the full head's coupled solve
                                    (hk_hair_sim, docs/dynamics.md "Static friction"): touching
                                    guides stick while the tangential impulse stays within mu
                                    times the normal one; 0 gives the viscous friction above.
                                    hk_hair_contacts_forces does not use it */
    double root_exclusion;       /* no contacts on a strand closer than this arc length to its
                                    root (m) >= 0: neighbouring roots sit close on the scalp */
    int rescan_interval;         /* >= 1: full broad-phase search every this many updates; pairs are
                                    only tracked in between */
    int along;                   /* 0: a pair per local minimum of the distance (a crossing, or
                                    the closest point of strands side by side); 1: a pair per
                                    segment of the lower-numbered strand and neighbouring strand,
                                    at their closest points, so that strands side by side are held
                                    along their length instead of at one point that jumps along
                                    them from update to update; every update then rescans */
    int threads;                 /* OpenMP threads of the updates and forces; <= 0: the OpenMP
                                    default (the results do not depend on it) */
} hk_HairContactDef;

/* Defaults for the guides of a human head (20 cm guides with one hair's mass per
 * length, about 6.5e-6 kg/m, dt = 1/30 s, forces treated implicitly; see
 * docs/dynamics.md, "Hair–hair contacts" for the reasoning):
 *   distance 5 mm, stiffness 0.5 N/m, damping 1e-3 N s/m, friction 1e-5 N s/m,
 *   friction_coefficient 0.3,
 *   root_exclusion 2 cm, rescan_interval 2, along 0, the default threads.
 * The dynamics depends on k / m, c_n / m and c_t / m: if a guide carries the mass of a
 * whole clump, scale the three coefficients by the same mass ratio. */
HK_API hk_HairContactDef hk_default_hair_contact_def(void);

/* One tracked pair, for reports, pictures and tests. */
typedef struct hk_HairContactPair {
    int strand[2];    /* strand[0] < strand[1] */
    int segment[2];   /* segment k joins samples k and k + 1 */
    double s[2];      /* arc lengths of the closest points */
    hk_Vec3 point[2]; /* the closest points */
    double distance;  /* |point[0] - point[1]| */
    int force[2];     /* for a contact, the index of its force in hk_hair_contacts_forces of
                         strand[0] and strand[1] (several forces may share an s); else -1 */
} hk_HairContactPair;

typedef struct hk_HairContacts hk_HairContacts;

/* Contacts between strand_count >= 1 guides. Fails on out-of-range parameters. */
HK_API hk_Status hk_hair_contacts_create(int strand_count, const hk_HairContactDef *p, hk_HairContacts **out,
                                         hk_Error *err);
HK_API void hk_hair_contacts_destroy(hk_HairContacts *c);

/* Detection then forces for the strands at the current time (strand_count must be the
 * one given at creation).
 *
 * Between rescans, each tracked pair is walked to the locally closest segment pair
 * (to a neighbour (a +- 1, b +- 1) while that is closer), pairs reaching the same one
 * merge, and pairs beyond 2 d0 are dropped: O(segments + pairs x walk length), the
 * walks being a step or two. A rescan (the first update, every rescan_interval
 * updates, after hk_hair_contacts_request_rescan, and whenever a strand's sample count
 * changed) replaces the pairs by every pair within 2 d0, from a spatial hash of the
 * segments: O(segments + segment pairs sharing a cell), linear for hair of bounded
 * density, never all pairs of segments. Between rescans a pair that did not exist
 * at the last one (strands approaching from farther than 2 d0, or a second dip in
 * the distance of two strands already touching) is not seen.
 *
 * On an error (bad counts, NaN, ...) there are no forces until the next successful
 * update (pairs report force = -1) and the tracked pairs are kept. Results are the
 * same bytes whatever the number of OpenMP threads. */
HK_API hk_Status hk_hair_contacts_update(hk_HairContacts *c, const hk_StrandSamples *strands, int strand_count,
                                         hk_Error *err);

/* Makes the next update run the broad phase (after a jump of the head, a reset, ...). */
HK_API void hk_hair_contacts_request_rescan(hk_HairContacts *c);

/* Tracked pairs after the last update, in the order (strand[0], segment[0],
 * strand[1], segment[1]); contacts are the pairs closer than d0. */
HK_API int hk_hair_contacts_pair_count(const hk_HairContacts *c);
HK_API int hk_hair_contacts_contact_count(const hk_HairContacts *c);
/* Fills *out with pair `index`; returns 0 (and leaves *out alone) when out of range. */
HK_API int hk_hair_contacts_pair(const hk_HairContacts *c, int index, hk_HairContactPair *out);

/* Forces on strand `strand` (sorted by s, ties in pair order), valid until the next
 * update; NULL with *count = 0 when there are none or the strand is out of range. */
HK_API const hk_PointForce *hk_hair_contacts_forces(const hk_HairContacts *c, int strand, int *count);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_HAIR_CONTACTS_H */
