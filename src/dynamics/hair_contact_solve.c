/* Guide-guide contacts solved together over all guides, with Coulomb friction
 * (hair_contact_solve.h; docs/dynamics.md, "Contacts solved together").
 *
 * Notation for pair c between strand i (its point a, side 0) and strand j (point b,
 * side 1): lambda_c is the impulse on a over the step (b gets -lambda_c), u_c = x'_a -
 * x'_b the relative velocity at the step's end. With J the points' Jacobians, A_i the
 * matrix of strand i's linearly implicit step and v_i^free its velocity without the
 * contacts,
 *     v_i = v_i^free + A_i^-1 sum_c (+-) J_ic^T lambda_c,
 * so u_c = u_c^free + J_a dv_i - J_b dv_j, with dv the strands' velocity changes kept
 * up to date as the impulses change (Y = A^-1 J^T is computed once per point: three
 * solves with the step's factored matrix, and only for the points of pairs that push).
 * With the dense solver the strand's matrix is factored as A = U U^T, U upper
 * triangular (Cholesky with the unknowns reversed), and the solve works with
 * Z = U^-1 J^T instead: J A^-1 J^T = Z^T Z, and keeping w = U^T dv, a point's velocity
 * change is J dv = Z^T w and an impulse adds Z lambda to w; dv = U^-T w once at the
 * end. A point's rows of J are zero beyond its own element, and so are its rows of Z,
 * so that each costs one triangular solve over its first 3(p + 1) unknowns instead of
 * two over all of them, and its products stop there too.
 * A point belongs to one pair: its rows of J are turned into the pair's basis (normal,
 * tangents) before anything else, so that u_c, Y, the Delassus block and the impulses
 * are all in that basis and a pair that does not push is told by one row. Projected
 * Gauss-Seidel visits the pairs in a fixed order and solves each one's law given the
 * others' impulses; the sweeps stop when no impulse changed by more than
 * HK_PGS_TOLERANCE of the largest. The order: the guides are split in two by a plane
 * (hair_contact_split.h); the pairs of either side, in pair order, are swept side by
 * side by two threads, then the pairs across the plane, themselves in two halves side
 * by side (a second plane), then those across both planes in two halves side by side.
 * The groups swept side by side share no strand, so the same pairs give the same bits
 * whatever the number of threads. Nested
 * dissection into 8 blocks (with a barrier per level) was tried before, when a fixed
 * second of settling made the still head's test sensitive to the order; coloured
 * sweeps (3 December 2026) were no faster on 2 threads, as the colour order loses the
 * caches' reuse of a guide's consecutive pairs, and their barriers, 400 a step, made a
 * loaded machine several times slower (docs/dynamics.md, "Contacts solved together"). */
#include <math.h>
#include <omp.h>
#include <stddef.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core/core_internal.h"
#include "core/linalg.h"     /* hk_avx_path: the rows' AVX paths */
#include "core/simd_lanes.h" /* Pair, Quad: the rows' sums in lanes (rows_dot_lanes) */
#include "contact_rows.h"
#include "dynamics_internal.h"
#include "hair_contact_law.h"
#include "hair_contact_solve.h"
#include "hair_contact_split.h"
#include "hair_contacts_internal.h"

/* 21 sweeps, the idle pairs checked on sweeps 0, 10 and 20 only: against 20 sweeps
 * with the checks on every fourth and the last, 5.5 % fewer instructions in the sweeps
 * and the impulses nearer a solve of 200 sweeps from the same start (8.4 % of their
 * size against 8.9 % over 90 frames of examples/guides200 shaking, 7.9 against 8.4 over
 * 180): the checks find few new pushing pairs, an extra sweep over the pushing ones
 * converges more (docs/dynamics.md, "How far the sweeps converge"). */
#define HK_PGS_SWEEPS     21
#define HK_PGS_FULL_EVERY 10
#define HK_PGS_TOLERANCE  1e-4

/* A point's Y^T (or Z^T): NORMAL_ONLY, a reversed strand's point with row 0 of Z^T
 * alone, its rows 1 and 2 those of J in the basis (answer_points). */
enum { UNANSWERED = 0, WANTED = 1, ANSWERED = 2, NORMAL_ONLY = 3 };

/* A strand's stages in a step, bits of cs->stage (set with release, read with
 * acquire): its step without the contacts is found (predict_free), its points taken
 * by a thread, their Jacobians set (predict_points). The threads of a team wait on
 * these, strand by strand, instead of on each other at barriers. */
enum { PREDICTED = 1, POINTS_CLAIMED = 2, POINTED = 4 };

/* A point: at its s, index 2 pair + side. */
typedef hk_HcKey Slot;

/* Where the sweeps find one of a pair's points: set once per step (prepare_pairs), so
 * that a visit reads them from its pair instead of from the strands' offsets. */
typedef struct PointRows {
    const double *rows; /* its 3 rows that read its velocity change from dv: J, or Z^T */
    const double *resp; /* its 3 rows of Y^T (or Z^T): the answer to an impulse */
    double *dv;         /* its strand's velocity change (or w = U^T dv) */
    int m;              /* its support (zero from column m on), also the rows' stride */
} PointRows;

/* The fields of a pair that a visit reads and writes, those of the idle pairs' check
 * first, in two cache lines, then those a visit that pushes reads: 348 bytes, copied
 * whole into the pushing pairs' stream (PushRecord). (With the law's parts in full and
 * the basis and keys among them a pair took 552 bytes, all read by a visit that pushes;
 * the pairs' fields were a third of the sweeps' first-level cache misses, callgrind's
 * cache model on examples/guides200 shaking.) */
typedef struct PairHot {
    hk_Vec3 lambda;     /* impulse on a in the basis (finished, in world space: cs->impulses) */
    double beta, gamma; /* normal law lambda_n = max(0, beta - gamma u_n) */
    hk_Vec3 free;       /* relative velocity in the basis at the strands' free velocities */
    PointRows point[2]; /* point a (strand i) and point b (strand j) */
    double w[3][3];     /* Delassus block in the basis: B^T (J_a Y_a + J_b Y_b) B */
    double nu;          /* the multiplier of its friction's disc at its last visit (disc_qp) */
    LawParts law;       /* what the pair's law takes from w alone */
    int ready;          /* w is set (both points' responses are), and with it law */
} PairHot;

/* A pair: what a visit touches, then the fields it does not read. */
typedef struct PairState {
    PairHot hot;
    int strand[2];    /* i and j */
    int slot[2];      /* slots of point a and point b */
    int key[4];       /* (i, a, j, b): warm start from the last step's same pair */
    hk_Vec3 basis[3]; /* n (from b to a), t1, t2 */
} PairState;

/* A growable array: its items and how many it has room for. */
typedef struct Buffer {
    void *items;
    size_t cap;
} Buffer;

/* Makes room for count items of size bytes (contents not kept); 0 when out of memory. */
static int reserve(Buffer *b, size_t count, size_t size, hk_Error *err)
{
    if (count <= b->cap) return 1;
    void *grown = hk_alloc_array(count, size, err);
    if (!grown) return 0;
    hk_free(b->items);
    b->items = grown;
    b->cap = count;
    return 1;
}

struct hk_ContactSolve {
    int strand_count;
    int *slot_start;                 /* strand_count + 1: the strands' points, slots [start, next) */
    size_t *dim_start;               /* strand_count + 1: offsets of the strands' 3N vectors */
    size_t *jac_start;               /* strand_count + 1: offsets of the strands' first 3 x 3N block */
    int *movable;                    /* per strand: its step's matrix answered */
    int *evaluations;                /* per strand: the evaluations of its step without the contacts */
    int *reversed;                   /* per strand: A = U U^T (factor); its points' rows of Z in yt, w in dv */
    const double **factor;           /* per strand: a reversed strand's U, U^T below it, then 1 / U_ii,
                                        read where its dynamics keeps it (hk_dynamics_reversed_factor) */
    const hk_HairContacts *contacts; /* the solve's pairs (layout): their normals, the bases' first vectors */
    Buffer slots;                    /* Slot per point */
    Buffer at;                       /* double per point: its s, as the Jacobians take them */
    Buffer vel;                      /* hk_Vec3 per point: its velocity with v^free */
    Buffer forces;                   /* hk_PointForce per point */
    Buffer jac, yt;                  /* double, 3 x m per point (m its support): rows of J and of
                                        Y^T = (A^-1 J^T)^T; a reversed strand's rows of J, then of
                                        Z^T = (U^-1 J^T)^T, in yt alone (predict_points) */
    Buffer support;                  /* int per point: its rows of J are zero from this column on */
    Buffer block;                    /* size_t per point: where its 3 rows start in jac and yt */
    Buffer answered;                 /* char per point: its rows of Y^T are set */
    Buffer dv;                       /* double, 3N per strand: the velocity change of the impulses */
    Buffer vfree;                    /* double, 3N per strand: its velocity after a step without them */
    Buffer screws;                   /* double, 18N per strand: work of the Jacobians */
    Buffer pairs, old_pairs;         /* PairState per pair, this step's and the last one's */
    Buffer impulses, old_impulses;   /* hk_Vec3 per pair: its impulse finished, in world space */
    Buffer by_pair;                  /* int per point, strand by strand: 2 pair + side in pair order */
    Buffer by_pair_fill;             /* int per strand: dealing by_pair (layout) */
    Buffer active;                   /* int per pair: the pushing pairs of the last full sweep */
    Buffer pushed;                   /* char per pair: its impulse is not zero (as visit tests it) */
    Buffer checks;                   /* double: the idle checks' records in the sweeps' order (IdleCheck) */
    size_t check_stride;             /* doubles a pair may take in checks: its header and two rows */
    Buffer pushes[2];                /* double: the pushing pairs' records in the sweeps' order, those read
                                        and those written by a full sweep (PushRecord) */
    size_t push_stride;              /* doubles a pair may take in pushes: its fields and 2 x 6 rows */
    Buffer delta;                    /* hk_Vec3 per pair: its warm start (apply_to_strand) */
    Buffer order, weight;            /* int and double per pair: the sweeps' order, the split's weights */
    Buffer roots;                    /* hk_Vec3 per strand: its root, where the split reads it */
    Buffer segment_place;            /* int per strand and per segment + 1: dealing the points (layout) */
    hk_ContactSplit split;           /* scratch of the split */
    int bounds[HK_SPLIT_GROUPS + 1]; /* the split's groups: order[bounds[x], bounds[x + 1]) */
    int old_count;
    int solved_count;        /* the pairs of the last solve swept (hk_contact_solve_sweep) */
    atomic_int finished;     /* its strands finished (finish_strand) */
    int last_count;          /* ... once finished, their impulses in world space (warm start of
                                the next layout); -1: no solve to keep */
    double dt;               /* the step of the solve under way */
    int opened;              /* hk_contact_solve_open sized the strands' arrays for the next solve */
    int laid_out;            /* hk_contact_solve_layout dealt the next solve's points */
    int prepared;            /* hk_contact_solve_prepare set the next solve's pairs */
    atomic_int *stage;       /* per strand: PREDICTED, POINTS_CLAIMED, POINTED (its step's stages) */
    hk_StrandDynamics **dyn; /* the strands of the solve under way */
    double mu, viscous;      /* its friction coefficient and viscous friction (times the step) */
};

static size_t dim_of(const hk_ContactSolve *cs, int strand)
{
    return cs->dim_start[strand + 1] - cs->dim_start[strand];
}

hk_Status hk_contact_solve_create(int strand_count, hk_ContactSolve **out, hk_Error *err)
{
    *out = NULL;
    if (strand_count < 1) return hk_error_set(err, HK_ERR_INVALID, "contact solve: %d strands", strand_count);
    hk_ContactSolve *cs = hk_calloc_array(1, sizeof *cs, err);
    if (!cs) return HK_ERR_NOMEM;
    cs->strand_count = strand_count;
    cs->slot_start = hk_calloc_array((size_t)strand_count + 1, sizeof(int), err);
    cs->dim_start = hk_calloc_array((size_t)strand_count + 1, sizeof(size_t), err);
    cs->jac_start = hk_calloc_array((size_t)strand_count + 1, sizeof(size_t), err);
    cs->movable = hk_calloc_array((size_t)strand_count, sizeof(int), err);
    cs->evaluations = hk_calloc_array((size_t)strand_count, sizeof(int), err);
    cs->reversed = hk_calloc_array((size_t)strand_count, sizeof(int), err);
    cs->factor = hk_calloc_array((size_t)strand_count, sizeof(const double *), err);
    cs->stage = hk_calloc_array((size_t)strand_count, sizeof(atomic_int), err);
    cs->last_count = -1;
    if (!cs->slot_start || !cs->dim_start || !cs->jac_start || !cs->movable || !cs->evaluations || !cs->reversed ||
        !cs->factor || !cs->stage) {
        hk_contact_solve_destroy(cs);
        return HK_ERR_NOMEM;
    }
    *out = cs;
    return HK_OK;
}

void hk_contact_solve_destroy(hk_ContactSolve *cs)
{
    if (!cs) return;
    hk_free(cs->slot_start);
    hk_free(cs->dim_start);
    hk_free(cs->jac_start);
    hk_free(cs->movable);
    hk_free(cs->evaluations);
    hk_free(cs->reversed);
    hk_free((void *)cs->factor);
    hk_free(cs->stage);
    Buffer *all[] = {&cs->slots,    &cs->at,           &cs->vfree,     &cs->vel,           &cs->forces,
                     &cs->jac,      &cs->yt,           &cs->support,   &cs->answered,      &cs->dv,
                     &cs->screws,   &cs->pairs,        &cs->old_pairs, &cs->active,        &cs->order,
                     &cs->weight,   &cs->roots,        &cs->delta,     &cs->segment_place, &cs->block,
                     &cs->impulses, &cs->old_impulses, &cs->by_pair,   &cs->by_pair_fill,  &cs->pushed,
                     &cs->checks,   &cs->pushes[0],    &cs->pushes[1]};
    for (size_t k = 0; k < sizeof all / sizeof *all; k++) hk_free(all[k]->items);
    hk_contact_split_free(&cs->split);
    hk_free(cs);
}

/* Sizes the arrays and deals the pairs' points to the strands, each strand's nearly
 * sorted by s (sort_points finishes, strand by strand). The strands' own arrays are
 * sized (hk_contact_solve_open). One thread: it runs beside the strands' steps
 * without the contacts (hair_sim.c), which touch none of its arrays. */
static hk_Status layout(hk_ContactSolve *cs, const hk_HairContacts *c, hk_Error *err)
{
    const int g = cs->strand_count, n = c->pair_count;
    /* The last solve's pairs, finished, become the old ones of the warm start. */
    if (cs->last_count >= 0) {
        Buffer swap = cs->old_pairs;
        cs->old_pairs = cs->pairs;
        cs->pairs = swap;
        swap = cs->old_impulses;
        cs->old_impulses = cs->impulses;
        cs->impulses = swap;
        cs->old_count = cs->last_count;
        cs->last_count = -1;
    }
    memset(cs->slot_start, 0, (size_t)(g + 1) * sizeof(int));
    for (int k = 0; k < n; k++) {
        cs->slot_start[c->pairs[k].i + 1]++;
        cs->slot_start[c->pairs[k].j + 1]++;
    }
    cs->jac_start[0] = 0;
    for (int s = 0; s < g; s++) {
        cs->jac_start[s + 1] = cs->jac_start[s] + (size_t)cs->slot_start[s + 1] * 3 * dim_of(cs, s);
        cs->slot_start[s + 1] += cs->slot_start[s];
    }
    const size_t slots = (size_t)cs->slot_start[g], jacs = cs->jac_start[g];
    if (!reserve(&cs->slots, slots, sizeof(Slot), err) || !reserve(&cs->at, slots, sizeof(double), err) ||
        !reserve(&cs->vel, slots, sizeof(hk_Vec3), err) || !reserve(&cs->forces, slots, sizeof(hk_PointForce), err) ||
        !reserve(&cs->jac, jacs, sizeof(double), err) || !reserve(&cs->yt, jacs, sizeof(double), err) ||
        !reserve(&cs->support, slots, sizeof(int), err) || !reserve(&cs->answered, slots, sizeof(char), err) ||
        !reserve(&cs->block, slots, sizeof(size_t), err) || !reserve(&cs->pairs, (size_t)n, sizeof(PairState), err) ||
        !reserve(&cs->active, (size_t)n, sizeof(int), err) || !reserve(&cs->order, (size_t)n, sizeof(int), err) ||
        !reserve(&cs->pushed, (size_t)n, sizeof(char), err) ||
        !reserve(&cs->checks, (size_t)n * cs->check_stride, sizeof(double), err) ||
        !reserve(&cs->pushes[0], (size_t)n * cs->push_stride, sizeof(double), err) ||
        !reserve(&cs->pushes[1], (size_t)n * cs->push_stride, sizeof(double), err) ||
        !reserve(&cs->weight, (size_t)n, sizeof(double), err) ||
        !reserve(&cs->roots, (size_t)g, sizeof(hk_Vec3), err) ||
        !reserve(&cs->delta, (size_t)n, sizeof(hk_Vec3), err) ||
        !reserve(&cs->impulses, (size_t)n, sizeof(hk_Vec3), err) || !reserve(&cs->by_pair, slots, sizeof(int), err) ||
        !reserve(&cs->by_pair_fill, (size_t)g, sizeof(int), err))
        return HK_ERR_NOMEM;
    /* Each strand's points in pair order, the order the impulses' changes are added to
     * its dv in (apply_to_strand, finish_strand), as one pass over the pairs would. */
    int *fill = cs->by_pair_fill.items, *by_pair = cs->by_pair.items;
    memcpy(fill, cs->slot_start, (size_t)g * sizeof(int));
    for (int k = 0; k < n; k++) {
        by_pair[fill[c->pairs[k].i]++] = 2 * k;
        by_pair[fill[c->pairs[k].j]++] = 2 * k + 1;
    }
    /* The points dealt by (strand, segment), a counting sort on the segment's global
     * index (offset[strand] + segment): strand by strand as slot_start has them, and
     * each strand's nearly sorted by s for hk_hc_sort_keys (only the points on one
     * segment can be out of order). qsort took 0.87 million instructions a step, an
     * insertion sort of the points in pair order 0.61, of the points so 0.17, the
     * dealing 0.08 more (examples/guides200 shaking). */
    long segments = 0;
    for (int s = 0; s < g; s++) segments += c->views[s].count - 1;
    if (!reserve(&cs->segment_place, (size_t)(segments + g + 1), sizeof(int), err)) return HK_ERR_NOMEM;
    int *offset = cs->segment_place.items, *place = offset + g;
    long acc = 0;
    for (int s = 0; s < g; s++) offset[s] = (int)acc, acc += c->views[s].count - 1;
    memset(place, 0, (size_t)(segments + 1) * sizeof(int));
    for (int k = 0; k < n; k++) {
        place[offset[c->pairs[k].i] + c->pairs[k].a + 1]++;
        place[offset[c->pairs[k].j] + c->pairs[k].b + 1]++;
    }
    for (long x = 0; x < segments; x++) place[x + 1] += place[x];
    Slot *slot = cs->slots.items;
    for (int k = 0; k < n; k++) {
        const hk_HcPair *hp = &c->pairs[k];
        const int at[2] = {offset[hp->i] + hp->a, offset[hp->j] + hp->b};
        for (int side = 0; side < 2; side++) {
            Slot *sl = &slot[place[at[side]]++];
            sl->at = c->contacts[k].s[side];
            sl->index = 2 * k + side;
        }
    }
    cs->contacts = c;
    /* (the strands' predictions may go on meanwhile: their bit is kept) */
    for (int s = 0; s < g; s++) atomic_fetch_and_explicit(&cs->stage[s], PREDICTED, memory_order_relaxed);
    return HK_OK;
}

/* Strand s's points sorted by s (the order its Jacobians are walked in and its forces
 * listed in), each pair told where its point on s went: the strand's share of the
 * layout, done with its Jacobians (predict_points) by whichever thread takes the
 * strand. A pair's slot[0] and slot[1] are set by its two strands. */
static void sort_points(hk_ContactSolve *cs, int s)
{
    Slot *slot = cs->slots.items;
    PairState *pairs = cs->pairs.items;
    const int begin = cs->slot_start[s], count = cs->slot_start[s + 1] - begin;
    hk_hc_sort_keys(slot + begin, count);
    for (int x = begin; x < begin + count; x++) {
        pairs[slot[x].index / 2].slot[slot[x].index % 2] = x;
        ((double *)cs->at.items)[x] = slot[x].at;
    }
}

/* Unit vectors t1, t2 completing n = basis[0] to a right-handed orthonormal basis,
 * always the same for the same n. */
static void complete_basis(hk_Vec3 basis[3])
{
    const hk_Vec3 n = basis[0];
    const hk_Vec3 axis = fabs(n.x) <= fabs(n.y) && fabs(n.x) <= fabs(n.z) ? hk_v3_unit(0)
                         : fabs(n.y) <= fabs(n.z)                         ? hk_v3_unit(1)
                                                                          : hk_v3_unit(2);
    basis[1] = hk_v3_normalize(hk_v3_cross(n, axis));
    basis[2] = hk_v3_cross(n, basis[1]);
}

/* The sum of rows_dot_lanes's four lanes, lo (lanes 0 and 1) and hi (2 and 3), with the
 * odd entry i < n of a . x. */
static inline __attribute__((always_inline)) double lanes_sum(Pair lo, Pair hi, const double *a, const double *x,
                                                              size_t i, size_t n)
{
    const Pair s = lo + hi;
    double r = s[0];
    if (i < n) r = a[i] * x[i] + r;
    return r + s[1];
}

/* lo += row[i..i+1] x[i..i+1], hi += row[i+2..i+3] x[i+2..i+3] (xl, xh): four lanes as two
 * Pairs (the baseline's path). */
#define ADD_PRODUCTS_PAIRS(lo, hi, row)                                                                                \
    do {                                                                                                               \
        lo += load_pair((row) + i) * xl;                                                                               \
        hi += load_pair((row) + i + 2) * xh;                                                                           \
    } while (0)

/* out[r] = sum over i < n of a[r stride + i] x[i] for the rows r < rows (1 to 3), each in
 * four lanes: lane l adds the products of the entries i = l mod 4 below the last multiple
 * of 4 in order, then a pair left over goes to lanes 0 and 1 and an odd last entry to
 * lane 0's sum (lanes_sum): (lane 0 + lane 2) + (lane 1 + lane 3). With wide (the AVX
 * path) the four lanes are one Quad, a product and a sum each four entries, else two
 * Pairs: the same operations, the same bits. The two lanes before (each Quad's products
 * added to a Pair two by two, in the order GCC had vectorised the `omp simd` reductions
 * in) waited on two sums in a row each four entries and took two instructions more
 * (docs/dynamics.md, "Speed", dyn19). */
static inline __attribute__((always_inline)) void rows_dot_lanes(const double *a, size_t stride, int rows,
                                                                 const double *x, size_t n, double *out, int wide)
{
    const double *a1 = a + stride, *a2 = a + 2 * stride; /* (read only when rows > 1, > 2) */
    Pair lo0 = splat(0.0), lo1 = lo0, lo2 = lo0, hi0 = lo0, hi1 = lo0, hi2 = lo0;
    size_t i = 0;
    if (wide) {
        Quad q0 = splat4(0.0), q1 = q0, q2 = q0;
        for (; i + 4 <= n; i += 4) {
            const Quad xq = load_quad(x + i);
            q0 += load_quad(a + i) * xq;
            if (rows > 1) q1 += load_quad(a1 + i) * xq;
            if (rows > 2) q2 += load_quad(a2 + i) * xq;
        }
        lo0 = LOW_PAIR(q0), hi0 = HIGH_PAIR(q0);
        if (rows > 1) lo1 = LOW_PAIR(q1), hi1 = HIGH_PAIR(q1);
        if (rows > 2) lo2 = LOW_PAIR(q2), hi2 = HIGH_PAIR(q2);
    } else
        for (; i + 4 <= n; i += 4) {
            const Pair xl = load_pair(x + i), xh = load_pair(x + i + 2);
            ADD_PRODUCTS_PAIRS(lo0, hi0, a);
            if (rows > 1) ADD_PRODUCTS_PAIRS(lo1, hi1, a1);
            if (rows > 2) ADD_PRODUCTS_PAIRS(lo2, hi2, a2);
        }
    if (i + 2 <= n) {
        const Pair xp = load_pair(x + i);
        lo0 += load_pair(a + i) * xp;
        if (rows > 1) lo1 += load_pair(a1 + i) * xp;
        if (rows > 2) lo2 += load_pair(a2 + i) * xp;
        i += 2;
    }
    out[0] = lanes_sum(lo0, hi0, a, x, i, n);
    if (rows > 1) out[1] = lanes_sum(lo1, hi1, a1, x, i, n);
    if (rows > 2) out[2] = lanes_sum(lo2, hi2, a2, x, i, n);
}

/* Where point x's 3 rows (of stride its support) start in jac and yt. */
static size_t block_of(const hk_ContactSolve *cs, int x) { return ((const size_t *)cs->block.items)[x]; }

static size_t support_of(const hk_ContactSolve *cs, int x) { return (size_t)((const int *)cs->support.items)[x]; }

/* Strand s's linearly implicit step without the guide-guide contacts: its free
 * velocity and, for the dense solver, its matrix factored as U U^T (reversed). A
 * strand whose matrix does not answer (not positive definite) is held immovable for
 * the contacts (Y = 0, its velocity as it is); its own step then decides. This needs
 * the strand alone, not the pairs: hair_sim.c runs it while one thread finds the pairs
 * (hk_contact_solve_predict). */
static void predict_free(hk_ContactSolve *cs, hk_StrandDynamics *d, int s, const hk_RigidState *head_end, double h)
{
    const size_t dim = dim_of(cs, s);
    double *vfree = (double *)cs->vfree.items + cs->dim_start[s];
    const double *v = hk_strand_dynamics_velocity(d);
    const long before = d->stats.iterations;
    cs->movable[s] = hk_dynamics_euler_delta(d, head_end, NULL, 0, h);
    cs->evaluations[s] = (int)(d->stats.iterations - before);
    cs->factor[s] = cs->movable[s] ? hk_dynamics_reversed_factor(d) : NULL;
    cs->reversed[s] = cs->factor[s] != NULL;
    for (size_t k = 0; k < dim; k++) vfree[k] = v[k] + (cs->movable[s] ? d->delta[k] : 0.0);
    memset((double *)cs->dv.items + cs->dim_start[s], 0, dim * sizeof(double));
    atomic_fetch_or_explicit(&cs->stage[s], PREDICTED, memory_order_release);
}

/* Waits until strand s has reached stage bit. */
static void wait_for_stage(hk_ContactSolve *cs, int s, int bit)
{
    long spins = 0;
    while (!(atomic_load_explicit(&cs->stage[s], memory_order_acquire) & bit)) hk_spin_pause(&spins);
}

/* Strand s's points' rows of J turned into their pairs' bases (n the contact's normal,
 * completed by complete_basis; each pair's kept by its point a's strand for
 * prepare_pairs and the sweeps): right after the Jacobians wrote them, while they are
 * in the caches, rather than when the answers are solved for (answer_points), after
 * every strand's points (beyond the support J stays zero). */
static void rows_in_bases(hk_ContactSolve *cs, int s)
{
    const Slot *slot = cs->slots.items;
    PairState *pairs = cs->pairs.items;
    double *all = cs->reversed[s] ? cs->yt.items : cs->jac.items;
    for (int x = cs->slot_start[s]; x < cs->slot_start[s + 1]; x++) {
        const int k = slot[x].index / 2;
        hk_Vec3 basis[3] = {cs->contacts->contacts[k].normal};
        complete_basis(basis);
        if (slot[x].index % 2 == 0) memcpy(pairs[k].basis, basis, sizeof basis);
        const size_t m = support_of(cs, x);
        hk_contact_rows_in_basis(all + block_of(cs, x), m, m, basis);
    }
}

/* The reciprocals of reversed strand s's U_ii, made by its factorisation after U
 * (hk_upper_cholesky): its back substitutions (hk_contact_back_substitute) multiply by
 * them instead of dividing, so that the chain of its unknowns, each waiting for the
 * last, takes a multiplication (4 cycles) a link instead of a division (13 and more): a
 * third less time a call (a loop of one support of 18 on its own, one row or three).
 * z_i = z_i (1 / U_ii) differs from z_i / U_ii by rounding (docs/dynamics.md, "Speed",
 * 7 December 2026, afternoon). */
static const double *inverse_of(const hk_ContactSolve *cs, int s)
{
    const size_t dim = dim_of(cs, s);
    return cs->factor[s] + dim * dim;
}

/* Row 0 of Z^T = (U^-1 J^T)^T of every point of reversed strand s, in place of its
 * normal row of J (what a pair that does not push needs to read its normal velocity,
 * J dv = Z^T w: every pair's idle check), up to three consecutive points of the same
 * support solved side by side: a back substitution is a chain, each unknown waiting
 * for the last, and one row alone took as long as three. Each row gets the bits
 * it gets alone (hk_contact_back_substitute). Rows 1 and 2 stay in the basis until the
 * pair may push (answer_points, answer_lazily). Solved with the Jacobians, while their
 * rows are in the caches. */
static void normal_rows(hk_ContactSolve *cs, int s)
{
    const int end = cs->slot_start[s + 1];
    const int *support = cs->support.items;
    for (int x = cs->slot_start[s]; x < end;) {
        const int m = support[x];
        double *z[3] = {NULL, NULL, NULL};
        int rows = 0;
        for (; x < end && rows < 3 && support[x] == m; x++) z[rows++] = (double *)cs->yt.items + block_of(cs, x);
        hk_contact_back_substitute(cs->factor[s], inverse_of(cs, s), dim_of(cs, s), m, z[0], z[1], z[2], rows);
    }
}

/* The Jacobians J of strand s's points (at the step's start) in their pairs' bases and
 * their velocities with v^free, once the pairs are known (layout), and a reversed
 * strand's normal rows of Z^T. How the strand answers an impulse at a point, Y^T =
 * (A^-1 J^T)^T, is found later and only for the points of pairs that may push
 * (answer_points, answer_lazily). */
static void point_strand(hk_ContactSolve *cs, hk_StrandDynamics *d, int s, const hk_RigidState *head_end)
{
    sort_points(cs, s);
    const int begin = cs->slot_start[s], count = cs->slot_start[s + 1] - begin;
    if (count == 0) return;
    const size_t dim = dim_of(cs, s);
    const double *vfree = (const double *)cs->vfree.items + cs->dim_start[s];
    /* A reversed strand's rows of J go to yt, where its rows of Z^T are solved for in
     * place (answer_points): one array less to write and read. Its points' blocks are
     * packed, 3 rows of their support each (the columns of the elements up to their
     * own; beyond it J and Z are zero), each after the last: 18.3 of 30 columns on
     * average (examples/guides200 shaking), so that a point's rows of Z^T take 440
     * bytes, not 720 spread over 3 rows and, with J apart, 1,440. */
    const int reversed = cs->reversed[s];
    double *rows = (double *)(reversed ? cs->yt.items : cs->jac.items) + cs->jac_start[s];
    int *support = (int *)cs->support.items + begin;
    hk_dynamics_point_jacobians(d, head_end, vfree, (const double *)cs->at.items + begin, count,
                                (double *)cs->screws.items + 6 * cs->dim_start[s], rows, reversed, NULL,
                                (hk_Vec3 *)cs->vel.items + begin, support);
    size_t *block = (size_t *)cs->block.items + begin, at = cs->jac_start[s];
    for (int x = 0; x < count; x++) {
        support[x] = reversed ? 3 * (support[x] + 1) : (int)dim;
        block[x] = at;
        at += 3 * (size_t)support[x];
    }
    memset((char *)cs->answered.items + begin, 0, (size_t)count);
    rows_in_bases(cs, s);
    if (reversed) normal_rows(cs, s);
}

/* point_strand once per strand and layout, by whichever thread claims it first, after
 * the strand's prediction (waited for when another thread has it under way); then the
 * strand is POINTED. */
static void predict_points(hk_ContactSolve *cs, hk_StrandDynamics *d, int s, const hk_RigidState *head_end)
{
    if (atomic_fetch_or_explicit(&cs->stage[s], POINTS_CLAIMED, memory_order_acq_rel) & POINTS_CLAIMED) return;
    wait_for_stage(cs, s, PREDICTED);
    point_strand(cs, d, s, head_end);
    atomic_fetch_or_explicit(&cs->stage[s], POINTED, memory_order_release);
}

/* Rows first..2 of Z^T = (U^-1 J^T)^T of point x of reversed strand s, in place of its
 * rows of J in the basis (in yt): U z = j by back substitution from the point's support
 * down (z is zero beyond it, as j is), by columns: once z_i is known, column i of U
 * (row i of the lower part, hk_dynamics_reversed_factor) times z_i leaves the rows above
 * it, the right-hand sides side by side. No sum runs along a row, so the loop over the rows
 * above is vectorised: answer_points took 4.0-4.2 ms a step by rows (each z_i the end
 * of a chain of dependent additions), 2.9-3.2 ms so (examples/guides200 shaking, one
 * thread, CPU time). The sums' order differs from the rows' by rounding. */
static void reversed_rows(hk_ContactSolve *cs, int s, int x, int first)
{
    const int m = ((const int *)cs->support.items)[x];
    const size_t sm = (size_t)m;
    const double *u = cs->factor[s];
    double *z = (double *)cs->yt.items + block_of(cs, x);
    hk_contact_back_substitute(u, inverse_of(cs, s), dim_of(cs, s), m, z + (size_t)first * sm,
                               z + (size_t)(first + 1) * sm, z + 2 * sm, 3 - first);
}

/* Pair ps has an impulse from the last step (its warm start, set by prepare_pairs). */
static int has_impulse(const PairState *ps) { return hk_v3_norm2(ps->hot.lambda) > 0.0; }

/* Every component of v is zero (visit's test of an idle pair: no impulse). */
static int is_zero(hk_Vec3 v) { return v.x == 0.0 && v.y == 0.0 && v.z == 0.0; }

/* Y^T of strand s's points marked wanted (answered == WANTED), a run of consecutive
 * points solved at once; rows 1 and 2 of Z^T of a reversed strand's points of the pairs
 * with an impulse from the last step (a triangular solve over the point's support; row
 * 0 of every point is solved with its Jacobian, normal_rows), the others' left in the
 * basis (what a pair that does not push needs is its normal velocity: J dv = Z^T w; the
 * rest when a sweep finds it pushing, answer_lazily: on examples/guides200 shaking, of
 * 3,700 wanted points a step 2,200 had an impulse, and 730 more came to push). A strand whose
 * matrix does not answer becomes immovable: all its points answer zero (nothing has
 * used them yet). */
static void answer_points(hk_ContactSolve *cs, hk_StrandDynamics *d, int s)
{
    const int begin = cs->slot_start[s], end = cs->slot_start[s + 1];
    char *answered = cs->answered.items;
    int ok = cs->movable[s];
    if (cs->reversed[s]) { /* every point: its rows of Z^T also read its velocity change */
        const PairState *pairs = cs->pairs.items;
        const Slot *slot = cs->slots.items;
        /* Row 0 is solved (normal_rows). Only the warm-started pairs' impulses act before
         * a sweep finds them pushing (apply_to_strand); the others' rows 1 and 2 wait for
         * that. */
        for (int x = begin; x < end; x++)
            if (answered[x] == WANTED && has_impulse(&pairs[slot[x].index / 2])) {
                reversed_rows(cs, s, x, 1);
                answered[x] = ANSWERED;
            } else {
                answered[x] = NORMAL_ONLY;
            }
        return;
    }
    for (int x = begin; ok && x < end;) {
        if (answered[x] != WANTED) {
            x++;
            continue;
        }
        int run = x;
        while (run < end && answered[run] == WANTED) answered[run++] = ANSWERED;
        const size_t at = block_of(cs, x); /* rows of 3N, the run's blocks one after another */
        ok =
            hk_dynamics_resolve_rows(d, (const double *)cs->jac.items + at, 3 * (run - x), (double *)cs->yt.items + at);
        x = run;
    }
    if (!ok && end > begin) {
        cs->movable[s] = 0;
        memset((double *)cs->yt.items + cs->jac_start[s], 0,
               (cs->jac_start[s + 1] - cs->jac_start[s]) * sizeof(double));
        memset(answered + begin, ANSWERED, (size_t)(end - begin));
    }
}

/* Y^T of one point found during the sweeps, for a pair that came to push only then.
 * Should the solve fail there (the O(N) solver's matrix found not positive definite,
 * which answer_points would have seen first), the point answers zero: held still. */
static void answer_lazily(hk_ContactSolve *cs, int s, int x)
{
    char *answered = cs->answered.items;
    if (answered[x] == ANSWERED) return;
    if (answered[x] == NORMAL_ONLY) { /* a reversed strand's: its rows 1 and 2 of Z^T */
        reversed_rows(cs, s, x, 1);
        answered[x] = ANSWERED;
        return;
    }
    answered[x] = ANSWERED;
    const size_t at = block_of(cs, x);
    double *yt = (double *)cs->yt.items + at;
    if (!cs->movable[s] || !hk_dynamics_resolve_rows(cs->dyn[s], (const double *)cs->jac.items + at, 3, yt))
        memset(yt, 0, 3 * dim_of(cs, s) * sizeof(double));
}

static hk_Vec3 in_basis(const hk_Vec3 basis[3], hk_Vec3 x)
{
    return hk_v3(hk_v3_dot(basis[0], x), hk_v3_dot(basis[1], x), hk_v3_dot(basis[2], x));
}

static hk_Vec3 from_basis(const hk_Vec3 basis[3], hk_Vec3 x)
{
    return hk_v3_madd(hk_v3_madd(hk_v3_scale(basis[0], x.x), basis[1], x.y), basis[2], x.z);
}

/* v += sign * Y lam for the point whose Y^T rows are yt (3 rows of its support m,
 * packed). */
static inline __attribute__((always_inline)) void add_response_lanes(double *v, const double *yt, size_t m, hk_Vec3 lam,
                                                                     double sign)
{
    const double l0 = sign * lam.x, l1 = sign * lam.y, l2 = sign * lam.z;
    const double *y1 = yt + m, *y2 = yt + 2 * m;
#pragma omp simd
    for (size_t k = 0; k < m; k++) v[k] += yt[k] * l0 + y1[k] * l1 + y2[k] * l2;
}

/* Four entries a vector where the CPU has AVX: each entry's products and sums are its
 * own, in the same order, and there is no FMA (target "avx" only), so the bits are the
 * baseline's (core/linalg.h, hk_avx_path). */
__attribute__((target("avx"))) static void add_response_avx(double *v, const double *yt, size_t m, hk_Vec3 lam,
                                                            double sign)
{
    add_response_lanes(v, yt, m, lam, sign);
}

static void add_response_sse2(double *v, const double *yt, size_t m, hk_Vec3 lam, double sign)
{
    add_response_lanes(v, yt, m, lam, sign);
}

static void add_response(double *v, const double *yt, size_t m, hk_Vec3 lam, double sign)
{
    if (hk_avx_path())
        add_response_avx(v, yt, m, lam, sign);
    else
        add_response_sse2(v, yt, m, lam, sign);
}

/* J dv for the point whose J rows are jac (3 rows of its support m, packed); the three
 * sums side by side (rows_dot_lanes). */
static inline __attribute__((always_inline)) hk_Vec3 point_change(const double *jac, size_t m, const double *dv,
                                                                  int wide)
{
    double a[3];
    rows_dot_lanes(jac, m, 3, dv, m, a, wide);
    return hk_v3(a[0], a[1], a[2]);
}

static int key_cmp(const int a[4], const int b[4])
{
    for (int k = 0; k < 4; k++)
        if (a[k] != b[k]) return a[k] < b[k] ? -1 : 1;
    return 0;
}

/* The first of the count pairs (sorted by key_cmp) whose key is not less than key. */
static int first_not_less(const PairState *pairs, int count, const int key[4])
{
    int lo = 0, hi = count; /* it lies in [lo, hi] */
    while (lo < hi) {
        const int mid = lo + (hi - lo) / 2;
        if (key_cmp(pairs[mid].key, key) < 0)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* Pair ph's Delassus block in its basis, J_a Y_a + J_b Y_b (or Z_a^T Z_a + Z_b^T Z_b)
 * with both points' rows of J (and so their answers) in that basis. Column q of a
 * point's block, row r of J times row q of Y^T, in one pass over the rows (each sum
 * rows_dot_lanes's own, the bits it has alone), inlined into the sweep's twins (wide:
 * its AVX path) instead of a call that chose its path at each of the nine sums. */
static inline __attribute__((always_inline)) void pair_block(hk_ContactSolve *cs, PairHot *ph, int wide)
{
    memset(ph->w, 0, sizeof ph->w);
    for (int side = 0; side < 2; side++) {
        const PointRows *pr = &ph->point[side];
        const size_t m = (size_t)pr->m;
        const double *rows = pr->rows, *yt = pr->resp;
        /* Z^T Z is symmetric to the bit (a product's factors commute, the sums run in
         * one order): rows q to 2 of column q are summed, the rest copied. */
        const int symmetric = rows == yt;
        double e[3][3], column[3];
        for (int q = 0; q < 3; q++) {
            const int first = symmetric ? q : 0;
            rows_dot_lanes(rows + (size_t)first * m, m, 3 - first, yt + (size_t)q * m, m, column, wide);
            for (int r = 0; r < 3; r++) e[r][q] = r < first ? e[q][r] : column[r - first];
        }
        for (int r = 0; r < 3; r++)
            for (int q = 0; q < 3; q++) ph->w[r][q] += e[r][q];
    }
    law_parts(ph->w, ph->gamma, cs->mu, cs->viscous, &ph->law);
    ph->ready = 1;
}

/* Pair ps's normal law pushes at the free velocities (its free set by prepare_pairs). */
static int pushes_free(const PairState *ps) { return ps->hot.beta - ps->hot.gamma * ps->hot.free.x > 0.0; }

/* A pair that may push this step: with an impulse from the last step, or whose normal
 * law pushes at the free velocities. */
static int may_push(const PairState *ps) { return pushes_free(ps) || has_impulse(ps); }

/* What the sweeps of a step spend on pair ps, in instructions, from what prepare_pairs
 * knows of it: with an impulse from the last step it pushes on nearly every sweep (19 of
 * 20 visits) and makes its Delassus block once; pushing at the free velocities alone,
 * it comes to push on 2.5 visits of 20 (the others' impulses hold it off) and is
 * checked idle on 5.5; else it is checked idle on every fourth sweep and the last (6)
 * and pushes on 0.3. A visit that pushes costs about 700 + 15 (m_a + m_b)
 * instructions (its law, then its relative velocity and both strands' changes over
 * its points' supports m), an idle check 40 + 4.6 (m_a + m_b), a block 1,400 and, for
 * a pair that was not expected to push, its points' answers 5,200 more (callgrind and
 * the visits counted over 105 steps of examples/guides200 shaking, 6 December 2026).
 * The weights before, 16 for a pair that may push and 1 otherwise, weighed the second
 * kind as the first: the first stage's two groups then cost 1,695 and 1,872 million
 * instructions over those steps, by this model on the visits counted; now 1,777 and
 * 1,761 (docs/dynamics.md, "Weights from the sweeps' costs"). Counted again with 21
 * sweeps and the idle checks on 3 of them, the three kinds cost about 15,050 + 294 m,
 * 2,460 + 58 m and 620 + 19 m; weighed so, the slower group of each stage summed over a
 * solve is 52.38 % of the work instead of 52.44 %, too little to change the order for
 * (docs/dynamics.md, "The sweeps' balance counted"). */
static double sweep_cost(const PairState *ps)
{
    const double m = ps->hot.point[0].m + ps->hot.point[1].m;
    if (has_impulse(ps)) return 14400.0 + 280.0 * m;
    if (pushes_free(ps)) return 3500.0 + 63.0 * m;
    return 700.0 + 32.0 * m;
}

/* Each pair's basis and normal law, and its impulse of the last step when the same
 * segment pair was tracked then (pairs and old pairs are both sorted by (i, a, j, b):
 * each chunk of pairs finds its first pair's place among the old ones by bisection,
 * then walks along both in step): resting contacts start where they ended.
 * The points of the pairs that may push, those with an impulse or whose normal law
 * pushes at the free velocities, are marked wanted: their answers are solved for in
 * parallel before the sweeps. The pair's weight in the split (sweep_cost) and its
 * share of the warm start (its impulse, or zero) are set with the rest: both read only
 * the pair itself, and so need no pass of their own. */
static void prepare_pairs(hk_ContactSolve *cs, const hk_HairContacts *c, double h)
{
    PairState *pairs = cs->pairs.items;
    const PairState *old = cs->old_pairs.items;
    const hk_Vec3 *old_impulse = cs->old_impulses.items;
    const hk_HairContactDef *p = &c->p;
    const hk_Vec3 *vel = cs->vel.items;
    char *answered = cs->answered.items;
    double *weight = cs->weight.items; /* the split's (split_pairs) */
    hk_Vec3 *delta = cs->delta.items;  /* the warm start's (apply_to_strand) */
    /* To be called by every thread of a team (or by one thread alone): the pairs are
     * shared among them, in chunks taken in turn, so that a thread that comes late from
     * the points (or is slowed) leaves more of them to the other: in two halves, one
     * per thread, the two waited 0.12 ms a step together at the barrier that ends the
     * loop (docs/dynamics.md, "Where the 2-thread step loses"). */
    {
        int o = 0, next = -1; /* this thread's place among the old pairs, for pair next */
        int pointed_i = -1;   /* the last strand i waited for (the pairs are sorted by i) */
#pragma omp for schedule(dynamic, 32)
        for (int k = 0; k < c->pair_count; k++) {
            PairState *ps = &pairs[k];
            const hk_HcPair *hp = &c->pairs[k];
            const hk_HcContact *ct = &c->contacts[k];
            /* Its two strands' points done (their slots, velocities and rows). */
            if (hp->i != pointed_i) wait_for_stage(cs, pointed_i = hp->i, POINTED);
            wait_for_stage(cs, hp->j, POINTED);
            ps->key[0] = hp->i, ps->key[1] = hp->a, ps->key[2] = hp->j, ps->key[3] = hp->b;
            /* (its basis set with its point a's rows, rows_in_bases) */
            ps->hot.beta = h * p->stiffness * (p->distance - ct->distance);
            ps->hot.gamma = h * h * p->stiffness + h * p->damping;
            ps->hot.lambda = hk_v3_zero();
            ps->hot.ready = 0;
            ps->hot.nu = 0.0;
            ps->hot.free = in_basis(ps->basis, hk_v3_sub(vel[ps->slot[0]], vel[ps->slot[1]]));
            ps->strand[0] = hp->i, ps->strand[1] = hp->j;
            if (k != next) o = first_not_less(old, cs->old_count, ps->key);
            while (o < cs->old_count && key_cmp(old[o].key, ps->key) < 0) o++;
            if (o < cs->old_count && key_cmp(old[o].key, ps->key) == 0)
                ps->hot.lambda = in_basis(ps->basis, old_impulse[o]);
            next = k + 1;
            for (int side = 0; side < 2; side++) {
                const int strand = ps->strand[side], x = ps->slot[side];
                const size_t at = block_of(cs, x);
                PointRows *pr = &ps->hot.point[side];
                pr->resp = (const double *)cs->yt.items + at;
                pr->rows = cs->reversed[strand] ? pr->resp : (const double *)cs->jac.items + at;
                pr->dv = (double *)cs->dv.items + cs->dim_start[strand];
                pr->m = (int)support_of(cs, x);
            }
            /* (a point belongs to one pair: no other iteration writes these) */
            if (may_push(ps)) answered[ps->slot[0]] = answered[ps->slot[1]] = WANTED;
            weight[k] = sweep_cost(ps);
            delta[k] = has_impulse(ps) ? ps->hot.lambda : hk_v3_zero();
            ((char *)cs->pushed.items)[k] = !is_zero(ps->hot.lambda);
        }
    }
}

/* Relative velocity in the basis at the step's end of pair ph with the impulses so far. */
static inline __attribute__((always_inline)) hk_Vec3 relative_velocity(const PairHot *ph, int wide)
{
    hk_Vec3 u = ph->free;
    for (int side = 0; side < 2; side++) {
        const PointRows *pr = &ph->point[side];
        const hk_Vec3 du = point_change(pr->rows, (size_t)pr->m, pr->dv, wide);
        u = side == 0 ? hk_v3_add(u, du) : hk_v3_sub(u, du);
    }
    return u;
}

/* Its normal part alone. */
static inline __attribute__((always_inline)) double normal_velocity(const PairHot *ph, int wide)
{
    double u = ph->free.x;
    for (int side = 0; side < 2; side++) {
        const PointRows *pr = &ph->point[side];
        double du;
        rows_dot_lanes(pr->rows, 0, 1, pr->dv, (size_t)pr->m, &du, wide);
        u += side == 0 ? du : -du;
    }
    return u;
}

/* The changes delta[k] of the impulses of strand s's pairs added to its dv, in pair
 * order (by_pair): the order one pass of apply_change over all pairs adds them in, so
 * that the strand's dv is the same bits whichever thread takes it and whatever the
 * others do meanwhile. Zero changes are skipped. */
static void apply_to_strand(hk_ContactSolve *cs, int s, const hk_Vec3 *delta)
{
    const PairState *pairs = cs->pairs.items;
    const int *by_pair = cs->by_pair.items;
    for (int r = cs->slot_start[s]; r < cs->slot_start[s + 1]; r++) {
        const int k = by_pair[r] / 2, side = by_pair[r] % 2;
        if (delta[k].x == 0.0 && delta[k].y == 0.0 && delta[k].z == 0.0) continue;
        const PointRows *pr = &pairs[k].hot.point[side];
        add_response(pr->dv, pr->resp, (size_t)pr->m, delta[k], side == 0 ? 1.0 : -1.0);
    }
}

/* Changes pair ph's impulse by delta (in its basis), updating both strands' dv. */
static inline __attribute__((always_inline)) void apply_change(const PairHot *ph, hk_Vec3 delta)
{
    for (int side = 0; side < 2; side++) {
        const PointRows *pr = &ph->point[side];
        add_response_lanes(pr->dv, pr->resp, (size_t)pr->m, delta, side == 0 ? 1.0 : -1.0);
    }
}

/* One Gauss-Seidel visit of pair k (ph: its fields, in the pair or in its record of the
 * pushing pairs' stream, PushRecord): its law given the other impulses, the strands'
 * dv updated. *change is raised to the size of the impulse's change, *size receives the
 * new impulse's size; returns the law's verdict (contact_law). wide: the AVX path's
 * sums (rows_dot_lanes). Inlined into the sweep's loop (gcc left it a call): 2.6
 * million fewer instructions in the head driver's 8 frames, the same bits
 * (docs/dynamics.md, "Two visits in flight"); so are the law, its solve and its disc
 * (always_inline since the loop has two twins, which gcc left them calls from: 20
 * million). */
static inline __attribute__((always_inline)) int visit(hk_ContactSolve *cs, PairHot *ph, int k, double mu,
                                                       double viscous, double *change, double *size, int wide)
{
    const int idle = is_zero(ph->lambda);
    /* No impulse and a normal law that does not push: zero stays the pair's answer
     * (with no push there is no friction either), whatever w. */
    if (idle && !(ph->beta - ph->gamma * normal_velocity(ph, wide) > 0.0)) {
        *size = 0.0;
        return 0;
    }
    if (!ph->ready) { /* (a record's pair pushed: it is ready, ph is its own) */
        const PairState *ps = (const PairState *)cs->pairs.items + k;
        for (int side = 0; side < 2; side++) answer_lazily(cs, ps->strand[side], ps->slot[side]);
        pair_block(cs, ph, wide);
    }
    const hk_Vec3 u = relative_velocity(ph, wide);
    const double lo[3] = {ph->lambda.x, ph->lambda.y, ph->lambda.z};
    double u0[3] = {u.x, u.y, u.z}, lam[3] = {lo[0], lo[1], lo[2]};
    for (int r = 0; r < 3; r++) u0[r] -= ph->w[r][0] * lo[0] + ph->w[r][1] * lo[1] + ph->w[r][2] * lo[2];
    const int law = contact_law(ph->w, &ph->law, u0, ph->beta, ph->gamma, mu, viscous, mu * (lo[0] > 0.0 ? lo[0] : 0.0),
                                lam, &ph->nu);
    const hk_Vec3 next = hk_v3(lam[0], lam[1], lam[2]);
    const hk_Vec3 delta = hk_v3_sub(next, ph->lambda);
    ph->lambda = next;
    ((char *)cs->pushed.items)[k] = !is_zero(next);
    const double dl = hk_v3_norm(delta);
    if (dl > 0.0) apply_change(ph, delta);
    if (dl > *change) *change = dl;
    *size = hk_v3_norm(next);
    return law;
}

/* A group of pairs in the sweeps: order[begin, end) are its pairs, active[begin, begin
 * + active_count) those that pushed at its last full sweep (visited on every sweep). */
typedef struct SweepGroup {
    int begin, end, active_count;
    int pushing, sticking;  /* at its last full sweep */
    double change, largest; /* the largest impulse change and impulse of its last sweep */
} SweepGroup;

/* Asks for the bytes [0, n) from p in the caches ahead of their use (a hint: nothing
 * is read, nothing changes but the time). */
static void prefetch_bytes(const void *p, size_t n)
{
    const char *c = p;
    for (size_t b = 0; b < n; b += 64) __builtin_prefetch(c + b);
    if (n > 0) __builtin_prefetch(c + n - 1);
}

/* What a visit of pair ps reads from memory (visit): its own fields up to those the
 * sweeps do not read (PairState), and its points' three rows; of a pair with no impulse
 * (idle: pushed, a byte apart), whose visit starts with the idle test, only what the test
 * reads (and write_check copies): the fields before w and row 0 of each point. The
 * solve's first sweep visits every pair in place, three in four of them idle: asked for
 * whole, their rows 1 and 2 and the rest of their fields took the memory's time for
 * nothing (docs/dynamics.md, "Speed", dyn19). */
static void prefetch_pair(const PairState *ps, int idle)
{
    prefetch_bytes(ps, idle ? offsetof(PairState, hot.w) : offsetof(PairState, strand));
}
static void prefetch_rows(const PairState *ps, int idle)
{
    const size_t rows = idle ? 1 : 3;
    for (int side = 0; side < 2; side++)
        prefetch_bytes(ps->hot.point[side].rows, rows * (size_t)ps->hot.point[side].m * sizeof(double));
}

/* The kinds of sweep: over the pairs that pushed at the last full sweep; the solve's
 * first full sweep, which also writes each pair's idle check (IdleCheck); a later full
 * sweep, which checks the idle pairs from those; or visits them all, when the tests
 * turned the records off (hk_contact_solve_idle_records_allow). */
enum { SWEEP_PUSHING = 0, SWEEP_FIRST_FULL = 1, SWEEP_FULL = 2, SWEEP_FULL_VISITS = 3 };

/* What a sweep does with the pushing pairs' records (PushRecord): every sweep after the
 * first visits the pairs listed at the last full sweep from their records (PUSH_READ),
 * and every full sweep but the last writes those of the pairs it lists (PUSH_WRITE).
 * Off when the tests turned the records off (hk_contact_solve_push_records_allow):
 * every pair is visited in place. */
enum { PUSH_WRITE = 1, PUSH_READ = 2 };

static int idle_records_allowed = 1, push_records_allowed = 1;

void hk_contact_solve_idle_records_allow(int allow) { idle_records_allowed = allow; }

void hk_contact_solve_push_records_allow(int allow) { push_records_allowed = allow; }

/* What visit's test of an idle pair reads (normal_velocity), in one record followed by
 * row 0 of point a, then of point b: the records of a group's pairs one after another
 * in its order, so that a full sweep's checks read one stream instead of a pair's
 * fields and two points' rows from three places (with the caches' neighbouring lines:
 * its other rows, which an idle pair does not read). An idle check stalled on those
 * loads, prefetched or not: 0.85-1.4 ms a full sweep against 0.55 for a sweep of the
 * pushing pairs alone (thread CPU time, one thread, examples/guides200 shaking;
 * docs/dynamics.md, "The idle checks' stream"). Row 0 of a point stays as it is
 * through the solve (answer_lazily solves rows 1 and 2 only), and so do the rest. */
typedef struct IdleCheck {
    double beta, gamma, free_n; /* the pair's normal law, its normal velocity at the free velocities */
    double *dv[2];              /* its strands' dv (or w) */
    int m[2];                   /* its points' supports */
} IdleCheck;
#define CHECK_HEAD (sizeof(IdleCheck) / sizeof(double))

/* Pair ps's record at record (IdleCheck); returns the end of the record. */
static double *write_check(const PairState *ps, double *record)
{
    IdleCheck *ic = (IdleCheck *)record;
    double *row = record + CHECK_HEAD;
    ic->beta = ps->hot.beta, ic->gamma = ps->hot.gamma, ic->free_n = ps->hot.free.x;
    for (int side = 0; side < 2; side++) {
        const PointRows *pr = &ps->hot.point[side];
        ic->dv[side] = pr->dv, ic->m[side] = pr->m;
        memcpy(row, pr->rows, (size_t)pr->m * sizeof(double));
        row += pr->m;
    }
    return row;
}

/* The normal law of the pair recorded in ic (its rows at row) pushes at the strands'
 * dv so far: visit's test of an idle pair, by normal_velocity's operations in its
 * order (the same bits). */
static inline __attribute__((always_inline)) int check_pushes(const IdleCheck *ic, const double *row, int wide)
{
    double u = ic->free_n, du0, du1;
    rows_dot_lanes(row, 0, 1, ic->dv[0], (size_t)ic->m[0], &du0, wide);
    u += du0;
    rows_dot_lanes(row + ic->m[0], 0, 1, ic->dv[1], (size_t)ic->m[1], &du1, wide);
    u += -du1;
    return ic->beta - ic->gamma * u > 0.0;
}

/* A pushing pair's record in the stream the sweeps read it from: its fields (PairHot),
 * then the rows of point a, then of point b (its 3 rows of J or Z^T, then, when they
 * differ, its 3 rows of Y^T), the records of a group's active pairs one after another
 * in its active list's order. Visited in place, a pushing pair's fields and its points'
 * rows lie in three scattered places, about 1.4 MB a sweep on examples/guides200
 * shaking, more than the 512 KiB second level: a pushing visit's rows and fields were
 * 3.9 of the sweeps' 5.3 million first-level read misses (docs/dynamics.md, "The idle
 * checks' stream"). Each full sweep but the last writes the records of the pairs its
 * visits find pushing (their rows just read, in the caches) into one of two buffers;
 * the sweeps over the pushing pairs that follow visit them from there, front to back,
 * and so does the next full sweep, which meets them in its order (an active list is a
 * part of its group's order, in that order), writes their impulses back to the pairs
 * (lambda, nu: where the idle checks, the later sweeps and the solve's tail read them)
 * and the next records into the other buffer. A record's visit is the pair's: the same
 * operations on the same values (a pair that pushed at a full sweep has its block:
 * ready), the same bits. */
typedef struct PushRecord {
    PairHot hot; /* the pair's, its points' rows and resp pointing into the record */
    int pair;    /* its index */
    int size;    /* the record's doubles, its rows with it */
} PushRecord;
#define PUSH_HEAD (sizeof(PushRecord) / sizeof(double))

/* The record of pair k (its fields ph) at record (PushRecord); returns its end. */
static double *write_push(const PairHot *ph, int k, double *record)
{
    PushRecord *pr = (PushRecord *)record;
    double *row = record + PUSH_HEAD;
    pr->hot = *ph;
    pr->pair = k;
    for (int side = 0; side < 2; side++) {
        const PointRows *from = &ph->point[side];
        PointRows *to = &pr->hot.point[side];
        const size_t n = 3 * (size_t)from->m;
        memcpy(row, from->rows, n * sizeof(double));
        to->rows = to->resp = row;
        row += n;
        if (from->resp != from->rows) {
            memcpy(row, from->resp, n * sizeof(double));
            to->resp = row;
            row += n;
        }
    }
    pr->size = (int)(row - record);
    return row;
}

/* One sweep over a group's pairs: every pair on a full sweep (then its active pairs
 * are listed again, and with PUSH_WRITE their records written into buffer 1 - from),
 * else its active pairs; with PUSH_READ the pairs listed at the last full sweep are
 * visited from their records in buffer from (PushRecord). A visit is a chain (the
 * strands' dv, the relative velocity, the law, the new dv) that waits on its loads: in
 * place, the pair two ahead is asked for, and the rows of the next one, whose fields
 * came with the last ask (the sweeps' CPU time on one thread about 15 % less on
 * examples/guides200 shaking, measured beside other jobs: docs/dynamics.md, "The
 * sweeps' balance counted"); the records are read in order, as the hardware's
 * prefetcher follows. On a later full sweep an idle pair is checked from its record
 * (IdleCheck) and left as visit would leave it when its law does not push. One loop
 * for every kind, so that visit is inlined once: as two copies, gcc left the law and
 * the rows' sums calls (4.7 million more instructions in the head driver's 8 frames).
 * wide: the AVX path's sums (sweep_group_avx). */
static inline __attribute__((always_inline)) void
sweep_group_lanes(hk_ContactSolve *cs, const int *order, SweepGroup *gr, int kind, int push, int from, int wide)
{
    const int full = kind != SWEEP_PUSHING;
    int *active = (int *)cs->active.items + gr->begin;
    const int count = full ? gr->end - gr->begin : gr->active_count;
    const int *list = full ? order + gr->begin : active; /* (active is rewritten behind x) */
    PairState *pairs = cs->pairs.items;
    const char *pushed = cs->pushed.items;
    double *record = (double *)cs->checks.items + (size_t)gr->begin * cs->check_stride;
    const size_t at = (size_t)gr->begin * cs->push_stride;
    double *in = (double *)cs->pushes[from].items + at, *out = (double *)cs->pushes[1 - from].items + at;
    int unread = push & PUSH_READ ? gr->active_count : 0; /* records left in */
    double change = 0.0, largest = 0.0;
    if (full) gr->pushing = gr->sticking = gr->active_count = 0;
    for (int x = 0; x < count; x++) {
        int k, recorded = 0;
        PairHot *ph;
        if (unread > 0 && (!full || ((const PushRecord *)in)->pair == list[x])) {
            PushRecord *pr = (PushRecord *)in;
            k = pr->pair, ph = &pr->hot, recorded = 1;
            in += pr->size;
            unread--;
        } else {
            k = list[x], ph = &pairs[k].hot;
        }
        if (kind == SWEEP_FULL) {
            const IdleCheck *ic = (const IdleCheck *)record;
            const double *row = record + CHECK_HEAD;
            record += CHECK_HEAD + (size_t)ic->m[0] + (size_t)ic->m[1];
            if (!pushed[k] && !check_pushes(ic, row, wide)) { /* (visit: no push, size 0) */
                if (recorded) pairs[k].hot.lambda = ph->lambda, pairs[k].hot.nu = ph->nu;
                continue;
            }
        }
        if (!recorded) {
            if (x + 2 < count) prefetch_pair(&pairs[list[x + 2]], !pushed[list[x + 2]]);
            if (x + 1 < count) prefetch_rows(&pairs[list[x + 1]], !pushed[list[x + 1]]);
        }
        if (kind == SWEEP_FIRST_FULL) record = write_check(&pairs[k], record);
        double l;
        const int law = visit(cs, ph, k, cs->mu, cs->viscous, &change, &l, wide);
        if (l > largest) largest = l;
        if (full && recorded) pairs[k].hot.lambda = ph->lambda, pairs[k].hot.nu = ph->nu;
        if (full && law > 0) {
            active[gr->active_count++] = k;
            if (push & PUSH_WRITE) out = write_push(ph, k, out);
        }
        if (full) gr->pushing += law > 0, gr->sticking += law == 2;
    }
    gr->change = change, gr->largest = largest;
}

/* The sweeps on AVX where the CPU has it: the rows' sums and responses four entries a
 * vector (rows_dot_lanes, add_response_lanes), the rest the same operations (no FMA):
 * the same bits (core/linalg.h, hk_avx_path), chosen once a group instead of at each
 * of a visit's calls. */
__attribute__((target("avx"))) static void sweep_group_avx(hk_ContactSolve *cs, const int *order, SweepGroup *gr,
                                                           int kind, int push, int from)
{
    sweep_group_lanes(cs, order, gr, kind, push, from, 1);
}

static void sweep_group_sse2(hk_ContactSolve *cs, const int *order, SweepGroup *gr, int kind, int push, int from)
{
    sweep_group_lanes(cs, order, gr, kind, push, from, 0);
}

static void sweep_group(hk_ContactSolve *cs, const int *order, SweepGroup *gr, int kind, int push, int from)
{
    if (hk_avx_path())
        sweep_group_avx(cs, order, gr, kind, push, from);
    else
        sweep_group_sse2(cs, order, gr, kind, push, from);
}

/* What the two threads of the sweeps share: a group is claimed by whichever thread
 * comes first, so that a thread the system has not scheduled delays nothing (with a
 * parallel region or barrier per sweep, 20 a step, a loaded machine's sweeps took
 * several times longer: docs/dynamics.md). A sweep has three stages of two groups
 * that share no strand: groups 0 and 1, 2 and 3, 4 and 5 (hk_contact_split). */
typedef struct SweepShare {
    atomic_int claim;    /* stage * 4 + the groups of the two claimed so far; -1: the sweeps are over */
    atomic_int finished; /* stage * 4 + the groups of the two done */
    int kind;            /* the sweep's kind (SWEEP_PUSHING, ...; set before its claims open) */
    int push;            /* and what it does with the pushing pairs' records (PUSH_WRITE, ...) */
    int from;            /* the buffer of those it reads (pushes[from]) */
} SweepShare;

/* Claims one of the two groups of the open stage (stage 3 sweep + p: groups 2p and
 * 2p + 1) and sweeps it. Returns 1 when it did, 0 when both are claimed, -1 when the
 * sweeps are over. */
static int claim_group(hk_ContactSolve *cs, const int *order, SweepGroup group[HK_SPLIT_GROUPS], SweepShare *sh)
{
    int word = atomic_load_explicit(&sh->claim, memory_order_acquire);
    while (word >= 0 && (word & 3) < 2)
        if (atomic_compare_exchange_weak_explicit(&sh->claim, &word, word + 1, memory_order_acq_rel,
                                                  memory_order_acquire)) {
            sweep_group(cs, order, &group[2 * ((word >> 2) % 3) + (word & 3)], sh->kind, sh->push, sh->from);
            atomic_fetch_add_explicit(&sh->finished, 1, memory_order_release);
            return 1;
        }
    return word < 0 ? -1 : 0;
}

/* The sweeps over the six groups: each of the three stages (groups 0 and 1, 2 and 3, 4
 * and 5, each two on disjoint strands) by this thread and one more when side_by_side;
 * the same bits either way. Pairs that do not push (most of those between d0 and 2 d0)
 * are visited on every HK_PGS_FULL_EVERY-th sweep and the last one only; the others on
 * every sweep. */
static void run_sweeps(hk_ContactSolve *cs, const int *order, SweepGroup group[HK_SPLIT_GROUPS], int side_by_side,
                       hk_ContactSolveStats *local)
{
    SweepShare share; /* closed (both groups of stage 0 taken) until the first sweep opens */
    atomic_init(&share.claim, 2);
    atomic_init(&share.finished, 0);
    share.kind = SWEEP_FIRST_FULL;
    share.push = share.from = 0;
#pragma omp parallel num_threads(side_by_side ? 2 : 1)
    {
        if (omp_get_thread_num() != 0) { /* the helper: claims what it finds open */
            long spins = 0;
            for (int r; (r = claim_group(cs, order, group, &share)) >= 0;)
                if (r == 0) hk_spin_pause(&spins);
        } else {
            for (int sweep = 0; sweep < HK_PGS_SWEEPS; sweep++) {
                const int full = sweep % HK_PGS_FULL_EVERY == 0 || sweep == HK_PGS_SWEEPS - 1;
                share.kind = sweep == 0                     ? SWEEP_FIRST_FULL
                             : full && idle_records_allowed ? SWEEP_FULL
                             : full                         ? SWEEP_FULL_VISITS
                                                            : SWEEP_PUSHING;
                share.push = !push_records_allowed
                                 ? 0
                                 : (sweep > 0 ? PUSH_READ : 0) | (full && sweep + 1 < HK_PGS_SWEEPS ? PUSH_WRITE : 0);
                for (int stage = 3 * sweep; stage < 3 * sweep + 3; stage++) {
                    atomic_store_explicit(&share.finished, 4 * stage, memory_order_relaxed);
                    atomic_store_explicit(&share.claim, 4 * stage, memory_order_release);
                    while (claim_group(cs, order, group, &share) == 1) {}
                    long spins = 0;
                    while (atomic_load_explicit(&share.finished, memory_order_acquire) != 4 * stage + 2)
                        hk_spin_pause(&spins);
                }
                if (share.push & PUSH_WRITE) share.from = 1 - share.from; /* (read by the next claims) */
                double change = 0.0, largest = 0.0;
                if (full) local->pushing = local->sticking = 0;
                for (int x = 0; x < HK_SPLIT_GROUPS; x++) {
                    change = fmax(change, group[x].change), largest = fmax(largest, group[x].largest);
                    if (full) local->pushing += group[x].pushing, local->sticking += group[x].sticking;
                }
                local->sweeps = sweep + 1;
                local->residual = largest > 0.0 ? change / largest : 0.0;
                if (full && change <= HK_PGS_TOLERANCE * largest) break;
            }
            atomic_store_explicit(&share.claim, -1, memory_order_release);
        }
    }
}

hk_Status hk_contact_solve_open(hk_ContactSolve *cs, hk_StrandDynamics **dyn, int strand_count, hk_Error *err)
{
    cs->opened = 0;
    if (strand_count != cs->strand_count)
        return hk_error_set(err, HK_ERR_INVALID, "contact solve: %d strands, expected %d", strand_count,
                            cs->strand_count);
    cs->dim_start[0] = 0;
    cs->check_stride = CHECK_HEAD;
    cs->push_stride = PUSH_HEAD;
    for (int s = 0; s < strand_count; s++) {
        const size_t dim = (size_t)(3 * dyn[s]->sh->n);
        if (CHECK_HEAD + 2 * dim > cs->check_stride) cs->check_stride = CHECK_HEAD + 2 * dim;
        if (PUSH_HEAD + 12 * dim > cs->push_stride) cs->push_stride = PUSH_HEAD + 12 * dim;
        cs->dim_start[s + 1] = cs->dim_start[s] + dim;
    }
    const size_t dims = cs->dim_start[strand_count];
    if (!reserve(&cs->dv, dims, sizeof(double), err) || !reserve(&cs->vfree, dims, sizeof(double), err) ||
        !reserve(&cs->screws, 6 * dims, sizeof(double), err))
        return HK_ERR_NOMEM;
    memset(cs->movable, 0, (size_t)strand_count * sizeof(int));
    memset(cs->evaluations, 0, (size_t)strand_count * sizeof(int));
    memset(cs->reversed, 0, (size_t)strand_count * sizeof(int));
    for (int s = 0; s < strand_count; s++) atomic_store_explicit(&cs->stage[s], 0, memory_order_relaxed);
    cs->opened = 1;
    return HK_OK;
}

void hk_contact_solve_predict(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end,
                              double dt)
{
    if (cs->opened && strand >= 0 && strand < cs->strand_count) predict_free(cs, d, strand, head_end, dt);
}

/* Nothing of a solve under way is kept: no strand to commit, the next solve starts
 * afresh. */
static void drop_solve(hk_ContactSolve *cs)
{
    cs->opened = cs->laid_out = cs->prepared = 0;
    memset(cs->movable, 0, (size_t)cs->strand_count * sizeof(int));
}

/* HK_OK when a solve of strand_count strands over dt with these contacts can be made,
 * else the error (and the solve under way dropped). */
static hk_Status check_solve(hk_ContactSolve *cs, const hk_HairContacts *contacts, int strand_count, double dt,
                             hk_Error *err)
{
    const int bad_count = strand_count != cs->strand_count || contacts->strand_count != strand_count;
    if (!bad_count && dt > 0.0 && isfinite(dt)) return HK_OK;
    drop_solve(cs);
    if (bad_count)
        return hk_error_set(err, HK_ERR_INVALID, "contact solve: %d strands, expected %d", strand_count,
                            cs->strand_count);
    return hk_error_set(err, HK_ERR_INVALID, "contact solve: step %g s", dt);
}

hk_Status hk_contact_solve_layout(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                                  int strand_count, double dt, hk_Error *err)
{
    hk_Status st = check_solve(cs, contacts, strand_count, dt, err);
    if (st == HK_OK && !cs->opened) st = hk_error_set(err, HK_ERR_INVALID, "contact solve: laid out before opened");
    if (st == HK_OK) st = layout(cs, contacts, err);
    if (st != HK_OK) {
        memset(cs->slot_start, 0, (size_t)(cs->strand_count + 1) * sizeof(int));
        drop_solve(cs);
        cs->old_count = 0;
        return st;
    }
    cs->dyn = dyn;
    cs->mu = contacts->p.friction_coefficient, cs->viscous = dt * contacts->p.friction;
    cs->laid_out = 1;
    cs->prepared = 0;
    return HK_OK;
}

void hk_contact_solve_points(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end)
{
    if (strand >= 0 && strand < cs->strand_count) predict_points(cs, d, strand, head_end);
}

/* The pairs dealt to the groups of the sweeps (weighted by what the sweeps spend on
 * them, set by prepare_pairs) into order and cs->bounds: it reads only the pairs'
 * strands, the weights and the strands' roots, so that one thread makes it while the
 * others start on the answers. */
static void split_pairs(hk_ContactSolve *cs, const hk_HairContacts *contacts)
{
    const int strand_count = cs->strand_count;
    hk_Vec3 *roots = cs->roots.items;
    for (int s = 0; s < strand_count; s++) roots[s] = contacts->views[s].pos[0];
    hk_contact_split(&cs->split, strand_count, roots, contacts->pair_count, contacts->pairs, cs->weight.items,
                     cs->order.items, cs->bounds);
}

/* To be called by every thread of a team (or by one thread alone), every strand's
 * points done: the pairs' laws, the split of the pairs beside the answers, then the
 * warm start (the last step's impulses added to the strands' dv, which needs their
 * points' answers). In the caller's parallel region, so that the step opens no region
 * of its own for the split and the answers, nor for the warm start (each a fork and a
 * join the threads wait on each other at). */
void hk_contact_solve_prepare(hk_ContactSolve *cs, const hk_HairContacts *contacts, double dt)
{
    prepare_pairs(cs, contacts, dt); /* (its loop's barrier: the pairs are set) */
#pragma omp single nowait
    split_pairs(cs, contacts);
    /* A strand's warm start needs its own points' answers alone: no barrier between.
     * The pairs' Delassus blocks are made when a sweep first finds them pushing
     * (visit), side by side with the other group's. */
#pragma omp for schedule(dynamic, 2) nowait
    for (int s = 0; s < cs->strand_count; s++) {
        answer_points(cs, cs->dyn[s], s);
        apply_to_strand(cs, s, cs->delta.items);
    }
#pragma omp single nowait
    cs->prepared = 1; /* read after the team's end */
}

hk_Status hk_contact_solve_sweep(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                                 int strand_count, const hk_RigidState *head_end, double dt,
                                 hk_ContactSolveStats *stats, hk_Error *err)
{
    hk_ContactSolveStats local = {0, 0, 0, 0.0, 0};
    hk_Status st = check_solve(cs, contacts, strand_count, dt, err);
    if (st != HK_OK) return st;
    const int threads = hk_hc_threads(contacts);
    /* What the caller has not staged before (hk_contact_solve_open to _prepare): */
    if (!cs->laid_out && !cs->opened) {
        st = hk_contact_solve_open(cs, dyn, strand_count, err);
        if (st != HK_OK) return st;
#pragma omp parallel for schedule(dynamic, 2) num_threads(threads)
        for (int s = 0; s < strand_count; s++) predict_free(cs, dyn[s], s, head_end, dt);
    }
    if (!cs->laid_out) st = hk_contact_solve_layout(cs, contacts, dyn, strand_count, dt, err);
    if (st != HK_OK) return st;
    if (!cs->prepared) {
#pragma omp parallel num_threads(threads)
        {
#pragma omp for schedule(dynamic, 2)
            for (int s = 0; s < strand_count; s++) predict_points(cs, dyn[s], s, head_end);
            hk_contact_solve_prepare(cs, contacts, dt);
        }
    }
    cs->opened = cs->laid_out = cs->prepared = 0;
    const int n = contacts->pair_count;
    SweepGroup group[HK_SPLIT_GROUPS];
    const int *bounds = cs->bounds, *order = cs->order.items;
    for (int x = 0; x < HK_SPLIT_GROUPS; x++) group[x] = (SweepGroup){bounds[x], bounds[x + 1], 0, 0, 0, 0.0, 0.0};
    /* Groups 0 and 1 share no strand, nor do 2 and 3, nor 4 and 5: their visits touch
     * disjoint pairs and strands, and give the same bits side by side or one after the
     * other. */
    int side_by_side = 0;
    for (int x = 0; x < HK_SPLIT_GROUPS; x += 2)
        side_by_side |= threads > 1 && bounds[x + 1] > bounds[x] && bounds[x + 2] > bounds[x + 1];
    run_sweeps(cs, order, group, side_by_side, &local);
    for (int s = 0; s < strand_count; s++) local.evaluations += cs->evaluations[s];
    cs->solved_count = n;
    cs->dt = dt;
    atomic_store_explicit(&cs->finished, 0, memory_order_relaxed);
    if (stats) *stats = local;
    return HK_OK;
}

/* Pair ps's impulse brought into Coulomb's cone in *out: the bound of the last sweep's
 * Tresca problems lags the normal impulses by a sweep, and what exceeds the cone is
 * taken back. Returns 1 when it did (else *out is the impulse). */
static int within_cone(const PairState *ps, double mu, hk_Vec3 *out)
{
    const hk_Vec3 l = ps->hot.lambda;
    const double t = sqrt(l.y * l.y + l.z * l.z), limit = mu * (l.x > 0.0 ? l.x : 0.0);
    *out = l;
    if (!(mu > 0.0 && t > limit)) return 0;
    const double f = t > 0.0 ? limit / t : 0.0;
    *out = hk_v3(l.x, f * l.y, f * l.z);
    return 1;
}

/* Strand s's share of the solve's tail: its pairs' impulses within the cone, what was
 * taken back taken from its dv too (in pair order, as apply_to_strand), its velocity
 * change from w = U^T dv when reversed, its points' forces, and the impulses of the
 * pairs it is side 0 of in world space (the next step's warm start). It reads the
 * pairs and writes the strand's own arrays only, so that the strands are finished by
 * any threads, each just before its commit, with no barrier between (the pair's
 * impulse in the cone is found by both of its strands, by the same operations). */
static void finish_strand(hk_ContactSolve *cs, int s)
{
    const PairState *pairs = cs->pairs.items;
    const int *by_pair = cs->by_pair.items;
    const Slot *slot = cs->slots.items;
    hk_PointForce *forces = cs->forces.items;
    hk_Vec3 *impulse = cs->impulses.items;
    for (int r = cs->slot_start[s]; r < cs->slot_start[s + 1]; r++) {
        const int k = by_pair[r] / 2, side = by_pair[r] % 2;
        const PairState *ps = &pairs[k];
        hk_Vec3 l;
        if (within_cone(ps, cs->mu, &l)) {
            const hk_Vec3 delta = hk_v3_sub(l, ps->hot.lambda);
            const PointRows *pr = &ps->hot.point[side];
            if (!(delta.x == 0.0 && delta.y == 0.0 && delta.z == 0.0))
                add_response(pr->dv, pr->resp, (size_t)pr->m, delta, side == 0 ? 1.0 : -1.0);
        }
        /* The impulse in world space, as a force held over the step. */
        const hk_Vec3 world = from_basis(ps->basis, l);
        const int x = ps->slot[side];
        forces[x].s = slot[x].at;
        forces[x].force = hk_v3_scale(world, (side == 0 ? 1.0 : -1.0) / cs->dt);
        forces[x].stiffness = forces[x].damping = hk_m3_zero();
        if (side == 0) impulse[k] = world;
    }
    /* The reversed strand's velocity change from w = U^T dv: U^T dv = w, forward, by
     * U's rows (each unknown known leaves all those below it side by side, instead of
     * each unknown's chain of subtractions down U's column: the same operations in the
     * same order for each entry). */
    if (cs->reversed[s])
        hk_upper_transpose_solve((int)dim_of(cs, s), cs->factor[s], (double *)cs->dv.items + cs->dim_start[s]);
    /* The last strand finished keeps the impulses for the next step's warm start. */
    if (atomic_fetch_add_explicit(&cs->finished, 1, memory_order_acq_rel) + 1 == cs->strand_count)
        cs->last_count = cs->solved_count;
}

void hk_contact_solve_finish(hk_ContactSolve *cs)
{
    /* To be called by every thread of a team (or by one thread alone). */
#pragma omp for schedule(dynamic, 4)
    for (int s = 0; s < cs->strand_count; s++) finish_strand(cs, s);
}

void hk_contact_solve_finish_strand(hk_ContactSolve *cs, int strand)
{
    if (strand >= 0 && strand < cs->strand_count) finish_strand(cs, strand);
}

hk_Status hk_contact_solve(hk_ContactSolve *cs, const hk_HairContacts *contacts, hk_StrandDynamics **dyn,
                           int strand_count, const hk_RigidState *head_end, double dt, hk_ContactSolveStats *stats,
                           hk_Error *err)
{
    const hk_Status st = hk_contact_solve_sweep(cs, contacts, dyn, strand_count, head_end, dt, stats, err);
    if (st != HK_OK) return st;
#pragma omp parallel num_threads(hk_hc_threads(contacts))
    hk_contact_solve_finish(cs);
    return HK_OK;
}

const hk_PointForce *hk_contact_solve_forces(const hk_ContactSolve *cs, int strand, int *count)
{
    int n = 0;
    const hk_PointForce *f = NULL;
    if (cs && strand >= 0 && strand < cs->strand_count) {
        n = cs->slot_start[strand + 1] - cs->slot_start[strand];
        if (n > 0) f = (const hk_PointForce *)cs->forces.items + cs->slot_start[strand];
    }
    if (count) *count = n;
    return f;
}

int hk_contact_solve_commit(hk_ContactSolve *cs, hk_StrandDynamics *d, int strand, const hk_RigidState *head_end,
                            double dt)
{
    if (strand < 0 || strand >= cs->strand_count || cs->movable[strand] != 1 ||
        d->params.integrator != HK_INTEGRATOR_LINEAR_EULER)
        return 0;
    const size_t dim = dim_of(cs, strand);
    double *v = (double *)cs->vfree.items + cs->dim_start[strand];
    const double *dv = (const double *)cs->dv.items + cs->dim_start[strand];
    for (size_t k = 0; k < dim; k++) v[k] += dv[k];
    return hk_dynamics_euler_commit(d, v, dt, head_end);
}
