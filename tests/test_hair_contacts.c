/* Guide-guide contacts (src/dynamics/hair_*.c, paper 000 §4.1): closest points of
 * segments against dense sampling, the broad phase and the tracked pairs against
 * brute-force O(n^2) searches, the penalty forces (equal and opposite, never
 * pulling, dissipative, linearisations against finite differences), determinism
 * across thread counts and with or without the AVX twins, linear cost, and bad input. */
#include "hk_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/linalg.h"
#include "dynamics/hair_contacts_internal.h"
#include "hairkit/hair_contacts.h"

/* ---- random strand sets ---------------------------------------------------------- */

/* The tests' own stream (xorshift64), reseeded where a test needs the same strands
 * again. */
static unsigned long long rng_state = 0x2545F4914F6CDD1DULL;

static void rng_seed(unsigned long long seed) { rng_state = seed ? seed : 1; }

static double uniform(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

typedef struct Strands {
    int g, n;
    double *s;
    hk_Vec3 *pos, *vel;
    hk_StrandSamples *ss;
} Strands;

static hk_Vec3 random_unit(void)
{
    for (;;) {
        hk_Vec3 u = hk_v3(2 * uniform() - 1, 2 * uniform() - 1, 2 * uniform() - 1);
        double n2 = hk_v3_norm2(u);
        if (n2 > 1e-4 && n2 <= 1.0) return hk_v3_scale(u, 1.0 / sqrt(n2));
    }
}

static Strands strands_alloc(int g, int n)
{
    Strands st = {g, n, NULL, NULL, NULL, NULL};
    st.s = calloc((size_t)g * n, sizeof *st.s);
    st.pos = calloc((size_t)g * n, sizeof *st.pos);
    st.vel = calloc((size_t)g * n, sizeof *st.vel);
    st.ss = calloc((size_t)g, sizeof *st.ss);
    assert_non_null(st.s);
    assert_non_null(st.pos);
    assert_non_null(st.vel);
    assert_non_null(st.ss);
    for (int i = 0; i < g; i++) {
        st.ss[i].count = n;
        st.ss[i].s = st.s + (size_t)i * n;
        st.ss[i].pos = st.pos + (size_t)i * n;
        st.ss[i].vel = st.vel + (size_t)i * n;
    }
    return st;
}

static void strands_free(Strands *st) { free(st->s), free(st->pos), free(st->vel), free(st->ss); }

static hk_Vec3 *P(Strands *st, int i, int k) { return &st->pos[(size_t)i * st->n + k]; }
static hk_Vec3 *V(Strands *st, int i, int k) { return &st->vel[(size_t)i * st->n + k]; }

/* g wavy strands of n samples spaced `step`, roots in a cube of side `box`: many
 * crossings at every angle, as in a swinging head of guides. `curl` is how much the
 * direction turns per sample (0.4 wavy, 1.5 a tangle). */
static Strands random_strands_curl(int g, int n, double step, double box, double curl)
{
    Strands st = strands_alloc(g, n);
    for (int i = 0; i < g; i++) {
        hk_Vec3 p = hk_v3(box * uniform(), box * uniform(), box * uniform());
        hk_Vec3 dir = random_unit();
        for (int k = 0; k < n; k++) {
            st.s[(size_t)i * n + k] = k * step;
            *P(&st, i, k) = p;
            *V(&st, i, k) = hk_v3_scale(random_unit(), 0.2 * uniform());
            dir = hk_v3_normalize(hk_v3_madd(dir, random_unit(), curl));
            p = hk_v3_madd(p, dir, step);
        }
    }
    return st;
}

static Strands random_strands(int g, int n, double step, double box)
{
    return random_strands_curl(g, n, step, box, 0.4);
}

/* ---- closest points of segments -------------------------------------------------- */

static double seg_dist_at(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double u, double v)
{
    hk_Vec3 a = hk_v3_madd(p0, hk_v3_sub(p1, p0), u), b = hk_v3_madd(q0, hk_v3_sub(q1, q0), v);
    return hk_v3_dist(a, b);
}

/* The function's answer against the minimum over an (m+1)^2 grid of (u, v): it is
 * never worse than the grid, and never better than the grid's bound allows. */
static void check_against_grid(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, int m)
{
    double u, v;
    const double d = sqrt(hk_segment_closest(p0, p1, q0, q1, &u, &v));
    assert_true(u >= 0.0 && u <= 1.0 && v >= 0.0 && v <= 1.0);
    hk_assert_near(seg_dist_at(p0, p1, q0, q1, u, v), d, 1e-14);
    double grid = HUGE_VAL;
    for (int x = 0; x <= m; x++)
        for (int y = 0; y <= m; y++) grid = fmin(grid, seg_dist_at(p0, p1, q0, q1, (double)x / m, (double)y / m));
    const double slack = (hk_v3_dist(p0, p1) + hk_v3_dist(q0, q1)) / (2.0 * m);
    assert_true(d <= grid + 1e-14);
    assert_true(d >= grid - slack - 1e-14);
}

static void test_segment_closest_known(void **state)
{
    (void)state;
    double u, v;
    /* Perpendicular skew segments, crossing at their middles h apart. */
    double d2 = hk_segment_closest(hk_v3(-1, 0, 0), hk_v3(1, 0, 0), hk_v3(0, -1, 0.3), hk_v3(0, 1, 0.3), &u, &v);
    hk_assert_near(d2, 0.09, 1e-15);
    hk_assert_near(u, 0.5, 1e-15);
    hk_assert_near(v, 0.5, 1e-15);
    /* Crossing exactly: distance 0. */
    d2 = hk_segment_closest(hk_v3(0, 0, 0), hk_v3(2, 2, 0), hk_v3(0, 2, 0), hk_v3(2, 0, 0), &u, &v);
    hk_assert_near(d2, 0.0, 1e-30);
    /* Parallel, overlapping along x: distance 1 (the pair of points is not unique). */
    d2 = hk_segment_closest(hk_v3(0, 0, 0), hk_v3(1, 0, 0), hk_v3(0.5, 1, 0), hk_v3(2, 1, 0), &u, &v);
    hk_assert_near(d2, 1.0, 1e-15);
    hk_assert_near(seg_dist_at(hk_v3(0, 0, 0), hk_v3(1, 0, 0), hk_v3(0.5, 1, 0), hk_v3(2, 1, 0), u, v), 1.0, 1e-15);
    /* Collinear and apart: end to end. */
    d2 = hk_segment_closest(hk_v3(0, 0, 0), hk_v3(1, 0, 0), hk_v3(3, 0, 0), hk_v3(2, 0, 0), &u, &v);
    hk_assert_near(d2, 1.0, 1e-15);
    hk_assert_near(u, 1.0, 0.0);
    hk_assert_near(v, 1.0, 0.0);
    /* Zero-length segments: point-segment and point-point. */
    d2 = hk_segment_closest(hk_v3(0.5, 2, 0), hk_v3(0.5, 2, 0), hk_v3(0, 0, 0), hk_v3(1, 0, 0), &u, &v);
    hk_assert_near(d2, 4.0, 1e-15);
    hk_assert_near(v, 0.5, 1e-15);
    d2 = hk_segment_closest(hk_v3(1, 2, 3), hk_v3(1, 2, 3), hk_v3(1, 2, 5), hk_v3(1, 2, 5), &u, &v);
    hk_assert_near(d2, 4.0, 1e-15);
}

static void test_segment_closest_reference(void **state)
{
    (void)state;
    /* Special configurations, finely sampled. */
    const hk_Vec3 cases[][4] = {
        {{0, 0, 0}, {1, 0, 0}, {0.3, 0.2, 0}, {0.8, 0.2, 0}},                 /* parallel, one inside the other */
        {{0, 0, 0}, {1, 0, 0}, {1.5, 0.1, 0}, {2.5, 0.1, 0}},                 /* parallel, disjoint */
        {{0, 0, 0}, {1, 0, 0}, {1, 0.5, 0.2}, {0, 0.5, 0.2}},                 /* anti-parallel */
        {{0, 0, 0}, {1, 0, 0}, {0.2, 0.1, 0}, {0.9, 0.1, 1e-9}},              /* nearly parallel */
        {{0, 0, 0}, {1, 0, 0}, {0.5, -1, 0.4}, {0.5, 1, 0.4}},                /* skew, crossing */
        {{0, 0, 0}, {1, 0, 0}, {1.2, -1, 0.4}, {1.4, 1, 0.4}},                /* skew, beyond an end */
        {{0, 0, 0}, {1, 1, 1}, {1, 0, 0}, {0, 1, 1}},                         /* intersecting */
        {{0.2, 0.2, 0.2}, {0.2, 0.2, 0.2}, {0, 0, 0}, {1, 0, 1}},             /* zero-length first */
        {{0, 0, 0}, {1, 2, 0}, {3, 1, 1}, {3, 1, 1}},                         /* zero-length second */
        {{0.5, 0.5, 0.5}, {0.5, 0.5, 0.5}, {0.1, 0.2, 0.3}, {0.1, 0.2, 0.3}}, /* both */
        {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}, {1, 1, 0}},                         /* sharing an end */
    };
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        check_against_grid(cases[k][0], cases[k][1], cases[k][2], cases[k][3], 1000);
        check_against_grid(cases[k][2], cases[k][3], cases[k][0], cases[k][1], 1000); /* swapped */
    }
    /* Random segments of all lengths, and random nearly parallel ones. */
    for (int t = 0; t < 300; t++) {
        hk_Vec3 p0 = random_unit(), q0 = hk_v3_scale(random_unit(), 0.5);
        hk_Vec3 d1 = hk_v3_scale(random_unit(), 2.0 * uniform());
        hk_Vec3 d2 = t % 3 == 0 ? hk_v3_madd(hk_v3_scale(d1, 0.5 + uniform()), random_unit(), 1e-7)
                                : hk_v3_scale(random_unit(), 2.0 * uniform());
        check_against_grid(p0, hk_v3_add(p0, d1), q0, hk_v3_add(q0, d2), 300);
    }
}

/* The measure as written without SSE2 (segment_distance.c's scalar code, copied):
 * the SSE2 code, whose lanes do the same operations in the same order, must give
 * the same bits (the interior test's (u, v) as two lanes and one division, the
 * edges two at a time). */
static double scalar_clamp01(double x) { return x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x); }

static double scalar_point_segment(hk_Vec3 p, hk_Vec3 q0, hk_Vec3 d, double dd)
{
    return dd > 0.0 ? scalar_clamp01(hk_v3_dot(hk_v3_sub(p, q0), d) / dd) : 0.0;
}

static double scalar_dist2_at(hk_Vec3 p0, hk_Vec3 d1, hk_Vec3 q0, hk_Vec3 d2, double u, double v)
{
    return hk_v3_norm2(hk_v3_sub(hk_v3_madd(p0, d1, u), hk_v3_madd(q0, d2, v)));
}

static double scalar_closest(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, double *u, double *v)
{
    const hk_Vec3 d1 = hk_v3_sub(p1, p0), d2 = hk_v3_sub(q1, q0), r = hk_v3_sub(p0, q0);
    const double a = hk_v3_dot(d1, d1), e = hk_v3_dot(d2, d2), b = hk_v3_dot(d1, d2);
    const double c = hk_v3_dot(d1, r), f = hk_v3_dot(d2, r);
    const double det = a * e - b * b;
    if (det > 1e-12 * a * e && det > 0.0) {
        const double uu = (b * f - c * e) / det, vv = (a * f - b * c) / det;
        if (uu >= 0.0 && uu <= 1.0 && vv >= 0.0 && vv <= 1.0) {
            *u = uu;
            *v = vv;
            return scalar_dist2_at(p0, d1, q0, d2, uu, vv);
        }
    }
    double cu[4], cv[4], dd[4];
    cu[0] = 0.0, cv[0] = scalar_point_segment(p0, q0, d2, e);
    cu[1] = 1.0, cv[1] = scalar_point_segment(p1, q0, d2, e);
    cv[2] = 0.0, cu[2] = scalar_point_segment(q0, p0, d1, a);
    cv[3] = 1.0, cu[3] = scalar_point_segment(q1, p0, d1, a);
    for (int k = 0; k < 4; k++) dd[k] = scalar_dist2_at(p0, d1, q0, d2, cu[k], cv[k]);
    int best = 0;
    for (int k = 1; k < 4; k++)
        if (dd[k] < dd[best]) best = k;
    *u = cu[best];
    *v = cv[best];
    return dd[best];
}

static void check_scalar_bits(hk_Vec3 p0, hk_Vec3 p1, hk_Vec3 q0, hk_Vec3 q1, int *inside)
{
    double u, v, su, sv;
    const double d2 = hk_segment_closest(p0, p1, q0, q1, &u, &v), sd2 = scalar_closest(p0, p1, q0, q1, &su, &sv);
    assert_memory_equal(&d2, &sd2, sizeof d2);
    assert_memory_equal(&u, &su, sizeof u);
    assert_memory_equal(&v, &sv, sizeof v);
    *inside += u > 0.0 && u < 1.0 && v > 0.0 && v < 1.0;
}

static void test_segment_closest_scalar_bits(void **state)
{
    (void)state;
    rng_seed(5);
    int inside = 0;
    /* Hair-sized segments (5 mm) near a head (10 cm from the origin, and 100 m for
     * rounding far from it), crossing at every angle, nearly parallel (the guides
     * side by side), zero-length, and sharing points. */
    for (int t = 0; t < 200000; t++) {
        const double far = t % 10 == 0 ? 100.0 : 0.1, len = 0.005;
        const hk_Vec3 p0 = hk_v3_scale(random_unit(), far), q0 = hk_v3_madd(p0, random_unit(), 0.01 * uniform());
        const hk_Vec3 d1 = hk_v3_scale(random_unit(), len * uniform());
        hk_Vec3 d2 = hk_v3_scale(random_unit(), len * uniform());
        if (t % 4 == 1) d2 = hk_v3_madd(hk_v3_scale(d1, 0.5 + uniform()), random_unit(), len * 1e-7);
        if (t % 50 == 2) d2 = hk_v3_zero();
        const hk_Vec3 p1 = t % 97 == 3 ? p0 : hk_v3_add(p0, d1), q1 = hk_v3_add(q0, d2);
        check_scalar_bits(p0, p1, q0, q1, &inside);
        check_scalar_bits(q0, q1, p0, p1, &inside);
        check_scalar_bits(p0, p1, p0, q1, &inside);
    }
    assert_true(inside > 10000); /* the interior critical point taken, not only the edges */
}

/* ---- brute-force references ------------------------------------------------------ */

typedef struct Quad {
    int i, a, j, b;
} Quad;

static int quad_cmp(const void *x, const void *y)
{
    const Quad *p = x, *q = y;
    if (p->i != q->i) return p->i - q->i;
    if (p->a != q->a) return p->a - q->a;
    if (p->j != q->j) return p->j - q->j;
    return p->b - q->b;
}

typedef struct QuadList {
    Quad *q;
    int count, cap;
} QuadList;

static void quad_push(QuadList *l, int i, int a, int j, int b)
{
    if (l->count == l->cap) {
        l->cap = l->cap ? 2 * l->cap : 256;
        l->q = realloc(l->q, (size_t)l->cap * sizeof *l->q);
        assert_non_null(l->q);
    }
    Quad q = {i, a, j, b};
    l->q[l->count++] = q;
}

static void views_of(const Strands *st, double root_exclusion, hk_HcStrand *views)
{
    for (int i = 0; i < st->g; i++) views[i] = hk_hc_strand_view(&st->ss[i], root_exclusion);
}

static int takes_part(const hk_HcStrand *v, int k) { return k >= v->first && k <= v->count - 2; }

/* Written out again, independently of hair_proximity.c: is (a, b) below its
 * neighbours in the order (rank, a, b)? */
static int brute_local_min(const hk_HcStrand *vi, int a, const hk_HcStrand *vj, int b, const hk_HcMetric *m)
{
    double u, v;
    const long long r = hk_hc_rank(hk_hc_pair_distance2(vi, a, vj, b, m->root_exclusion, &u, &v), m->quantum);
    for (int x = a - 1; x <= a + 1; x++)
        for (int y = b - 1; y <= b + 1; y++) {
            if ((x == a && y == b) || !takes_part(vi, x) || !takes_part(vj, y)) continue;
            long long e = hk_hc_rank(hk_hc_pair_distance2(vi, x, vj, y, m->root_exclusion, &u, &v), m->quantum);
            if (e < r || (e == r && (x < a || (x == a && y < b)))) return 0;
        }
    return 1;
}

/* Every segment pair of different strands closer than 2 d0 (candidates), those that
 * are local minima (pairs) and the pairs closer than d0 (contacts); any list may be
 * NULL. O(segments^2). */
static void brute_force(const Strands *st, const hk_HairContactDef *p, QuadList *candidates, QuadList *pairs,
                        QuadList *contacts)
{
    hk_HcStrand *views = calloc((size_t)st->g, sizeof *views);
    views_of(st, p->root_exclusion, views);
    const hk_HcMetric m = hk_hc_metric(p);
    const double band2 = 4.0 * p->distance * p->distance;
    for (int i = 0; i < st->g; i++)
        for (int j = i + 1; j < st->g; j++)
            for (int a = views[i].first; a <= views[i].count - 2; a++)
                for (int b = views[j].first; b <= views[j].count - 2; b++) {
                    double u, v;
                    const double d2 = hk_hc_pair_distance2(&views[i], a, &views[j], b, m.root_exclusion, &u, &v);
                    if (!(d2 < band2)) continue;
                    if (candidates) quad_push(candidates, i, a, j, b);
                    if ((pairs || contacts) && brute_local_min(&views[i], a, &views[j], b, &m)) {
                        if (pairs) quad_push(pairs, i, a, j, b);
                        /* A contact as the forces see it: the distance of the closest points. */
                        const hk_Vec3 pa =
                            hk_v3_madd(views[i].pos[a], hk_v3_sub(views[i].pos[a + 1], views[i].pos[a]), u);
                        const hk_Vec3 pb =
                            hk_v3_madd(views[j].pos[b], hk_v3_sub(views[j].pos[b + 1], views[j].pos[b]), v);
                        if (contacts && hk_v3_dist(pa, pb) < p->distance) quad_push(contacts, i, a, j, b);
                    }
                }
    free(views);
    if (candidates) qsort(candidates->q, (size_t)candidates->count, sizeof(Quad), quad_cmp);
    if (pairs) qsort(pairs->q, (size_t)pairs->count, sizeof(Quad), quad_cmp);
    if (contacts) qsort(contacts->q, (size_t)contacts->count, sizeof(Quad), quad_cmp);
}

/* The tracked pairs, optionally only the contacts (closer than d0). */
static void tracked_pairs(const hk_HairContacts *c, double below, QuadList *out)
{
    for (int k = 0; k < hk_hair_contacts_pair_count(c); k++) {
        hk_HairContactPair p;
        assert_true(hk_hair_contacts_pair(c, k, &p));
        if (p.distance < below) quad_push(out, p.strand[0], p.segment[0], p.strand[1], p.segment[1]);
    }
}

static int quad_find(const QuadList *l, const Quad *q)
{
    return bsearch(q, l->q, (size_t)l->count, sizeof(Quad), quad_cmp) != NULL;
}

static void assert_same_quads(const QuadList *x, const QuadList *y)
{
    if (x->count != y->count) print_error("sets differ: %d against %d\n", x->count, y->count);
    assert_int_equal(x->count, y->count);
    for (int k = 0; k < x->count; k++) assert_int_equal(quad_cmp(&x->q[k], &y->q[k]), 0);
}

static hk_HairContactDef test_params(void)
{
    hk_HairContactDef p = hk_default_hair_contact_def();
    p.root_exclusion = 0.006; /* cuts through a segment: exercises the clipping */
    return p;
}

static hk_HairContacts *make_contacts(int g, const hk_HairContactDef *p)
{
    hk_HairContacts *c = NULL;
    hk_Error err;
    assert_int_equal(hk_hair_contacts_create(g, p, &c, &err), HK_OK);
    return c;
}

static void update_ok(hk_HairContacts *c, const Strands *st)
{
    hk_Error err;
    hk_Status s = hk_hair_contacts_update(c, st->ss, st->g, &err);
    if (s != HK_OK) print_error("%s\n", err.message);
    assert_int_equal(s, HK_OK);
}

/* ---- detection ------------------------------------------------------------------- */

static void test_broad_phase_matches_brute_force(void **state)
{
    (void)state;
    const hk_HairContactDef p = test_params();
    /* Wavy guides, more of them, a tangle of curly strands (long walks), and a tight
     * bundle: starting within 4 mm, so that buckets hold a hundred entries and more,
     * whose passed entry pairs fill the pair loop's list many times within one bucket
     * (its flushes in the middle of a sweep's bucket). Last, wavy guides 100 km from
     * the origin, where floats are 7.8 mm apart: the pair loop's boxes in floats must
     * keep every pair whose boxes in doubles overlap, by a few um or by 7 mm. */
    const int sizes[][2] = {{40, 30}, {60, 25}, {8, 200}, {120, 12}, {40, 30}};
    const double curl[5] = {0.4, 0.4, 1.5, 0.4, 0.4}, box[5] = {0.04, 0.04, 0.04, 0.004, 0.04};
    const hk_Vec3 far = hk_v3(1e5, -7e4, 3e4);
    for (int t = 0; t < 5; t++) {
        Strands st = random_strands_curl(sizes[t][0], sizes[t][1], 0.004, box[t], curl[t]);
        if (t == 4)
            for (int i = 0; i < st.g; i++)
                for (int k = 0; k < st.n; k++) *P(&st, i, k) = hk_v3_add(*P(&st, i, k), far);
        hk_HairContacts *c = make_contacts(st.g, &p);
        update_ok(c, &st);
        /* Candidates: every segment pair closer than 2 d0, found once. */
        QuadList found = {0}, reference = {0}, pairs_ref = {0}, pairs = {0};
        for (int k = 0; k < c->candidate_count; k++)
            quad_push(&found, c->candidates[k].i, c->candidates[k].a, c->candidates[k].j, c->candidates[k].b);
        qsort(found.q, (size_t)found.count, sizeof(Quad), quad_cmp);
        QuadList contacts = {0}, contacts_ref = {0};
        brute_force(&st, &p, &reference, &pairs_ref, &contacts_ref);
        assert_true(reference.count > 100);
        assert_same_quads(&found, &reference);
        /* and measured as hk_hc_pair_distance2 measures them, to the bit (the update
         * takes the AVX twin where the CPU has AVX, the call below the baseline) */
        for (int k = 0; k < c->candidate_count; k++) {
            const hk_HcPair *q = &c->candidates[k];
            double u, v;
            const double d2 =
                hk_hc_pair_distance2(&c->views[q->i], q->a, &c->views[q->j], q->b, p.root_exclusion, &u, &v);
            assert_memory_equal(&d2, &q->d2, sizeof d2);
            assert_memory_equal(&u, &q->u, sizeof u);
            assert_memory_equal(&v, &q->v, sizeof v);
        }
        /* The baseline's path (the pair loop's box test by SSE without VEX) finds the
         * same candidates in the same order, to the bit. */
        hk_avx_paths_allow(0);
        hk_HairContacts *base = make_contacts(st.g, &p);
        update_ok(base, &st);
        hk_avx_paths_allow(1);
        assert_int_equal(base->candidate_count, c->candidate_count);
        assert_memory_equal(base->candidates, c->candidates, (size_t)c->candidate_count * sizeof(hk_HcPair));
        hk_hair_contacts_destroy(base);
        /* Pairs: exactly the local minima within 2 d0, and the contacts within d0. */
        tracked_pairs(c, HUGE_VAL, &pairs);
        assert_same_quads(&pairs, &pairs_ref);
        tracked_pairs(c, p.distance, &contacts);
        assert_same_quads(&contacts, &contacts_ref);
        assert_int_equal(hk_hair_contacts_contact_count(c), contacts.count);
        assert_true(contacts.count > 5);
        free(found.q), free(reference.q), free(pairs_ref.q), free(pairs.q), free(contacts.q), free(contacts_ref.q);
        hk_hair_contacts_destroy(c);
        strands_free(&st);
    }
}

/* Moves every strand rigidly by a small random translation and rotation about its
 * middle, plus a small random bend, with |displacement| <= about `amount`. */
static void small_motion(Strands *st, double amount)
{
    for (int i = 0; i < st->g; i++) {
        const hk_Vec3 shift = hk_v3_scale(random_unit(), 0.5 * amount * uniform());
        const hk_Vec3 axis = random_unit();
        const hk_Vec3 mid = *P(st, i, st->n / 2);
        const double length = st->s[(size_t)i * st->n + st->n - 1];
        const double angle = 0.3 * amount / length * uniform();
        for (int k = 0; k < st->n; k++) {
            hk_Vec3 r = hk_v3_sub(*P(st, i, k), mid);
            hk_Vec3 turned = hk_v3_madd(r, hk_v3_cross(axis, r), angle); /* first order is enough */
            *P(st, i, k) = hk_v3_add(hk_v3_add(mid, turned), hk_v3_madd(shift, random_unit(), 0.2 * amount));
        }
    }
}

/* Between rescans the pairs are only walked: every tracked pair must be a true pair
 * (a local minimum within 2 d0 of the brute force), and every contact of the brute
 * force must be tracked, except a minimum newly split off a valley already tracked
 * (two strands lying along each other whose distance profile grows a second dip):
 * walks cannot see those, the next rescan does. */
/* The pairs' sort (two counting sorts, radix order) against a stable reference:
 * pairs ordered by (i, a, j, b), those with equal keys in their input order (they
 * carry their input place in d2), and hk_hc_run bounding each segment's run. */
typedef struct Ranked {
    hk_HcPair p;
    int place;
} Ranked;

static int ranked_cmp(const void *x, const void *y)
{
    const hk_HcPair *a = &((const Ranked *)x)->p, *b = &((const Ranked *)y)->p;
    const int ka[5] = {a->i, a->a, a->j, a->b, ((const Ranked *)x)->place};
    const int kb[5] = {b->i, b->a, b->j, b->b, ((const Ranked *)y)->place};
    for (int k = 0; k < 5; k++)
        if (ka[k] != kb[k]) return ka[k] < kb[k] ? -1 : 1;
    return 0;
}

static void test_pair_sort_stable(void **state)
{
    (void)state;
    rng_seed(11);
    Strands st = random_strands(12, 9, 0.004, 0.03);
    const hk_HairContactDef p = test_params();
    hk_HairContacts *c = make_contacts(st.g, &p);
    update_ok(c, &st); /* the views the sort indexes the segments by */
    const int n = 3000;
    hk_Error err;
    hk_HcPair *pairs = hk_alloc_array((size_t)n, sizeof *pairs, &err); /* the sort trades it for its own */
    Ranked *ref = malloc((size_t)n * sizeof *ref);
    assert_non_null(pairs);
    assert_non_null(ref);
    for (int k = 0; k < n; k++) {
        /* few strands and segments: many equal keys */
        const int i = (int)(uniform() * 4), j = i + 1 + (int)(uniform() * 3);
        const hk_HcPair q = {i, (int)(uniform() * 8), j, (int)(uniform() * 8), (double)k, uniform(), uniform()};
        pairs[k] = q;
        ref[k] = (Ranked){q, k};
    }
    qsort(ref, (size_t)n, sizeof *ref, ranked_cmp);
    int cap = n;
    assert_int_equal(hk_hc_sort(c, &pairs, &cap, n, &err), HK_OK);
    for (int k = 0; k < n; k++) assert_memory_equal(&pairs[k], &ref[k].p, sizeof pairs[k]);
    for (int k = 0; k < n; k++) {
        int begin, end;
        hk_hc_run(c, pairs[k].i, pairs[k].a, &begin, &end);
        assert_true(begin <= k && k < end);
        assert_true(pairs[begin].i == pairs[k].i && pairs[begin].a == pairs[k].a);
        assert_true(pairs[end - 1].i == pairs[k].i && pairs[end - 1].a == pairs[k].a);
        assert_true(begin == 0 || pairs[begin - 1].i != pairs[k].i || pairs[begin - 1].a != pairs[k].a);
        assert_true(end == n || pairs[end].i != pairs[k].i || pairs[end].a != pairs[k].a);
    }
    hk_free(pairs), free(ref);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

static void test_tracking_matches_brute_force(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.rescan_interval = 1000000; /* only the first update searches */
    rng_seed(11);
    Strands st = random_strands(50, 40, 0.004, 0.05);
    hk_HairContacts *c = make_contacts(st.g, &p);
    update_ok(c, &st);
    int moved = 0, checked = 0, split = 0;
    QuadList before = {0};
    tracked_pairs(c, HUGE_VAL, &before);
    for (int step = 0; step < 12; step++) {
        /* 1 mm per update: a relative approach of at most 2 mm, less than the band
         * between d0 and 2 d0, so no contact can come from an untracked valley. */
        small_motion(&st, 0.001);
        update_ok(c, &st);
        assert_false(c->last_update_rescanned);
        QuadList tracked = {0}, reference = {0}, contacts = {0}, contacts_ref = {0};
        tracked_pairs(c, HUGE_VAL, &tracked);
        brute_force(&st, &p, NULL, &reference, &contacts_ref);
        for (int k = 0; k < tracked.count; k++) assert_true(quad_find(&reference, &tracked.q[k]));
        tracked_pairs(c, p.distance, &contacts);
        for (int k = 0; k < contacts_ref.count; k++) {
            const Quad *q = &contacts_ref.q[k];
            if (quad_find(&contacts, q)) continue;
            int same_strands = 0;
            for (int t = 0; t < tracked.count; t++) same_strands |= tracked.q[t].i == q->i && tracked.q[t].j == q->j;
            assert_true(same_strands);
            split++;
        }
        checked += contacts_ref.count;
        for (int k = 0; k < tracked.count; k++) moved += !quad_find(&before, &tracked.q[k]);
        free(before.q);
        before = tracked;
        free(reference.q), free(contacts.q), free(contacts_ref.q);
    }
    assert_true(checked > 500);
    assert_true(moved > 20);            /* the walks did move pairs to other segments */
    assert_true(split * 25 <= checked); /* rare: at most 4% of the contacts */
    print_message("tracking: %d contacts checked over 12 updates, %d pairs walked to other segments, "
                  "%d split-off minima left to the next rescan\n",
                  checked, moved, split);
    /* A rescan finds them all again. */
    hk_hair_contacts_request_rescan(c);
    update_ok(c, &st);
    QuadList all = {0}, all_ref = {0};
    tracked_pairs(c, HUGE_VAL, &all);
    brute_force(&st, &p, NULL, &all_ref, NULL);
    assert_same_quads(&all, &all_ref);
    free(all.q), free(all_ref.q), free(before.q);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

/* Parallel strands sampled alike are equally close all along: one pair, not one per
 * segment pair (the ranked distances absorb the rounding noise). */
static void test_parallel_strands_one_pair(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.root_exclusion = 0.0;
    for (int t = 0; t < 20; t++) {
        Strands st = strands_alloc(2, 30);
        const hk_Vec3 dir = random_unit(), off = hk_v3_normalize(hk_v3_cross(dir, random_unit()));
        const hk_Vec3 origin = hk_v3_scale(random_unit(), 0.1);
        for (int k = 0; k < 30; k++) {
            st.s[k] = st.s[30 + k] = 0.005 * k;
            *P(&st, 0, k) = hk_v3_madd(origin, dir, 0.005 * k);
            *P(&st, 1, k) = hk_v3_madd(*P(&st, 0, k), off, 0.003);
        }
        hk_HairContacts *c = make_contacts(2, &p);
        update_ok(c, &st);
        assert_int_equal(hk_hair_contacts_pair_count(c), 1);
        hk_assert_near(c->contacts[0].distance, 0.003, 1e-12);
        hk_hair_contacts_destroy(c);
        strands_free(&st);
    }
}


/* along = 1: a pair per segment a of strand i and strand j > i, at the closest of j's
 * segments (the first among equals) when within 2 d0: brute force over all segment
 * pairs, written out independently of the broad phase. Parallel strands 3 mm apart get
 * a pair per segment instead of one. */
static void test_pairs_along_strands(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.along = 1;
    const int sizes[][2] = {{40, 30}, {8, 200}};
    const double curl[2] = {0.4, 1.5};
    for (int t = 0; t < 2; t++) {
        Strands st = random_strands_curl(sizes[t][0], sizes[t][1], 0.004, 0.04, curl[t]);
        hk_HairContacts *c = make_contacts(st.g, &p);
        for (int update = 0; update < 2; update++) { /* along rescans at every update */
            update_ok(c, &st);
            hk_HcStrand *views = calloc((size_t)st.g, sizeof *views);
            views_of(&st, p.root_exclusion, views);
            QuadList reference = {0}, pairs = {0};
            for (int i = 0; i < st.g; i++)
                for (int a = views[i].first; a <= views[i].count - 2; a++)
                    for (int j = i + 1; j < st.g; j++) {
                        double best = 4.0 * p.distance * p.distance;
                        int best_b = -1;
                        for (int b = views[j].first; b <= views[j].count - 2; b++) {
                            double u, v;
                            const double d2 =
                                hk_hc_pair_distance2(&views[i], a, &views[j], b, p.root_exclusion, &u, &v);
                            if (d2 < best) best = d2, best_b = b;
                        }
                        if (best_b >= 0) quad_push(&reference, i, a, j, best_b);
                    }
            tracked_pairs(c, HUGE_VAL, &pairs);
            assert_true(reference.count > 100);
            assert_same_quads(&pairs, &reference);
            free(views), free(reference.q), free(pairs.q);
            small_motion(&st, 0.0005);
        }
        hk_hair_contacts_destroy(c);
        strands_free(&st);
    }
    /* Two parallel strands 3 mm apart: one pair per segment of the first. */
    p.root_exclusion = 0.0;
    Strands st = strands_alloc(2, 30);
    for (int k = 0; k < 30; k++) {
        st.s[k] = st.s[30 + k] = 0.005 * k;
        *P(&st, 0, k) = hk_v3(0.0, -0.005 * k, 0.0);
        *P(&st, 1, k) = hk_v3(0.003, -0.005 * k, 0.0);
    }
    hk_HairContacts *c = make_contacts(2, &p);
    update_ok(c, &st);
    assert_int_equal(hk_hair_contacts_pair_count(c), 29);
    for (int k = 0; k < 29; k++) hk_assert_near(c->contacts[k].distance, 0.003, 1e-12);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

static void test_root_exclusion_and_self(void **state)
{
    (void)state;
    /* Two strands from the same root diverging slowly: with no exclusion they touch
     * near the root, with a 2 cm exclusion no force acts before s = 2 cm. */
    Strands st = strands_alloc(3, 21);
    for (int k = 0; k < 21; k++) {
        const double s = 0.005 * k;
        st.s[k] = st.s[21 + k] = st.s[42 + k] = s;
        *P(&st, 0, k) = hk_v3(0.0, -s, 0.0);
        *P(&st, 1, k) = hk_v3(0.1 * s, -s, 0.0);
        /* A hairpin: the strand folds back onto itself 2 mm apart, far from the
         * others. Its own segments never make a pair. */
        *P(&st, 2, k) = k <= 10 ? hk_v3(1.0, -s, 0.0) : hk_v3(1.002, -0.1 + s, 0.0);
    }
    hk_HairContactDef p = hk_default_hair_contact_def();
    p.root_exclusion = 0.0;
    hk_HairContacts *c = make_contacts(3, &p);
    update_ok(c, &st);
    assert_true(hk_hair_contacts_contact_count(c) >= 1);
    int count;
    const hk_PointForce *f = hk_hair_contacts_forces(c, 0, &count);
    assert_true(count >= 1 && f[0].s < 0.02);
    hk_assert_near(f[0].s, 0.0, 1e-12); /* the closest points are at the root */
    assert_null(hk_hair_contacts_forces(c, 2, &count));
    assert_int_equal(count, 0);
    for (int k = 0; k < hk_hair_contacts_pair_count(c); k++) {
        hk_HairContactPair pr;
        hk_hair_contacts_pair(c, k, &pr);
        assert_true(pr.strand[0] != 2 && pr.strand[1] != 2);
    }
    hk_hair_contacts_destroy(c);
    p.root_exclusion = 0.02;
    c = make_contacts(3, &p);
    update_ok(c, &st);
    for (int g = 0; g < 3; g++) {
        f = hk_hair_contacts_forces(c, g, &count);
        for (int k = 0; k < count; k++) assert_true(f[k].s >= 0.02 - 1e-15);
    }
    /* Strand 1 is 2 mm from strand 0 at s = 2 cm: still a contact, at the cut. */
    assert_int_equal(hk_hair_contacts_contact_count(c), 1);
    f = hk_hair_contacts_forces(c, 1, &count);
    assert_int_equal(count, 1);
    hk_assert_near(f[0].s, 0.02, 1e-15);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

/* ---- forces ---------------------------------------------------------------------- */

/* The force of a contact on its side's strand. */
static const hk_PointForce *pair_force(const hk_HairContacts *c, const hk_HairContactPair *pr, int side)
{
    int count;
    const hk_PointForce *f = hk_hair_contacts_forces(c, pr->strand[side], &count);
    assert_true(pr->force[side] >= 0 && pr->force[side] < count);
    assert_true(f[pr->force[side]].s == pr->s[side]);
    return &f[pr->force[side]];
}

/* The pair (i, a, j, b) of the last update, if tracked. */
static int find_pair(const hk_HairContacts *c, const hk_HairContactPair *like, hk_HairContactPair *out)
{
    for (int k = 0; k < hk_hair_contacts_pair_count(c); k++) {
        hk_hair_contacts_pair(c, k, out);
        if (out->strand[0] == like->strand[0] && out->segment[0] == like->segment[0] &&
            out->strand[1] == like->strand[1] && out->segment[1] == like->segment[1])
            return 1;
    }
    return 0;
}

static void test_crossing_force_values(void **state)
{
    (void)state;
    /* Strand 0 along x, strand 1 along z, h = 3 mm above it in y, crossing at the
     * middle of segments; strand 0 moves with velocity w, strand 1 is still. */
    const double h = 0.003;
    const hk_Vec3 w = hk_v3(0.02, 0.05, -0.01);
    Strands st = strands_alloc(2, 11);
    for (int k = 0; k < 11; k++) {
        st.s[k] = st.s[11 + k] = 0.01 * k;
        *P(&st, 0, k) = hk_v3(0.01 * k - 0.045, 0.0, 0.0);
        *P(&st, 1, k) = hk_v3(0.0, h, 0.01 * k - 0.055);
        *V(&st, 0, k) = w;
    }
    hk_HairContactDef p = hk_default_hair_contact_def();
    p.root_exclusion = 0.0;
    hk_HairContacts *c = make_contacts(2, &p);
    update_ok(c, &st);
    assert_int_equal(hk_hair_contacts_pair_count(c), 1);
    hk_HairContactPair pr;
    assert_true(hk_hair_contacts_pair(c, 0, &pr));
    hk_assert_near(pr.distance, h, 1e-15);
    hk_assert_near(pr.s[0], 0.045, 1e-15);
    hk_assert_near(pr.s[1], 0.055, 1e-15);
    /* n = -y (from strand 1 down to strand 0); w.n = -0.05: approaching. */
    const double fn = p.stiffness * (p.distance - h) + p.damping * 0.05;
    int count;
    const hk_PointForce *f = hk_hair_contacts_forces(c, 0, &count);
    assert_int_equal(count, 1);
    hk_assert_near(f->force.x, -p.friction * 0.02, 1e-18);
    hk_assert_near(f->force.y, -fn, 1e-15);
    hk_assert_near(f->force.z, p.friction * 0.01, 1e-18);
    const double kdiag[3] = {0, p.stiffness, 0};
    const double ddiag[3] = {p.friction, p.damping, p.friction};
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            hk_assert_near(f->stiffness.m[a][b], a == b ? kdiag[a] : 0.0, 1e-15);
            hk_assert_near(f->damping.m[a][b], a == b ? ddiag[a] : 0.0, 1e-18);
        }
    const hk_PointForce *g = hk_hair_contacts_forces(c, 1, &count);
    assert_int_equal(count, 1);
    assert_true(g->force.x == -f->force.x && g->force.y == -f->force.y && g->force.z == -f->force.z);
    /* Separating fast enough, the normal force is clamped at zero: no pull, and no
     * normal stiffness or damping; friction remains. */
    for (int k = 0; k < 11; k++) *V(&st, 0, k) = hk_v3(0.0, -10.0, 0.0);
    update_ok(c, &st);
    f = hk_hair_contacts_forces(c, 0, &count);
    assert_int_equal(count, 1);
    assert_true(f->force.y == 0.0);
    hk_assert_near(f->stiffness.m[1][1], 0.0, 0.0);
    hk_assert_near(f->damping.m[1][1], 0.0, 0.0);
    hk_assert_near(f->damping.m[0][0], p.friction, 1e-18);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

static void test_forces_opposite_never_pull(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.damping = 0.01; /* strong enough that some random velocities clamp the normal force */
    Strands st = random_strands(60, 30, 0.004, 0.04);
    hk_HairContacts *c = make_contacts(st.g, &p);
    update_ok(c, &st);
    hk_Vec3 total = hk_v3_zero();
    double scale = 0.0;
    int clamped = 0, pushing = 0;
    for (int k = 0; k < hk_hair_contacts_pair_count(c); k++) {
        hk_HairContactPair pr;
        hk_hair_contacts_pair(c, k, &pr);
        if (!(pr.distance < p.distance)) continue;
        const hk_PointForce *fa = pair_force(c, &pr, 0), *fb = pair_force(c, &pr, 1);
        assert_true(fb->force.x == -fa->force.x && fb->force.y == -fa->force.y && fb->force.z == -fa->force.z);
        const hk_Vec3 n = hk_v3_normalize(hk_v3_sub(pr.point[0], pr.point[1]));
        const double normal = hk_v3_dot(fa->force, n);
        /* Friction is tangential up to rounding; the normal part never pulls. */
        assert_true(normal >= -1e-13 * hk_v3_norm(fa->force));
        clamped += hk_m3_trace(&fa->stiffness) == 0.0;
        pushing += normal > 0.0;
    }
    for (int g = 0; g < st.g; g++) {
        int count;
        const hk_PointForce *f = hk_hair_contacts_forces(c, g, &count);
        for (int k = 0; k < count; k++) {
            total = hk_v3_add(total, f[k].force);
            scale += hk_v3_norm(f[k].force);
            if (k > 0) assert_true(f[k].s >= f[k - 1].s);
        }
    }
    assert_true(clamped > 0 && pushing > 0);
    hk_assert_near(hk_v3_norm(total), 0.0, 1e-14 * scale);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

static void translate_strand(Strands *st, int i, hk_Vec3 by)
{
    for (int k = 0; k < st->n; k++) *P(st, i, k) = hk_v3_add(*P(st, i, k), by);
}

static void add_velocity(Strands *st, int i, hk_Vec3 by)
{
    for (int k = 0; k < st->n; k++) *V(st, i, k) = hk_v3_add(*V(st, i, k), by);
}

static void test_linearisations_finite_differences(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.rescan_interval = 1;
    Strands st = random_strands(40, 30, 0.004, 0.04);
    hk_HairContacts *c = make_contacts(st.g, &p);
    update_ok(c, &st);
    const int pairs = hk_hair_contacts_pair_count(c);
    hk_HairContactPair *list = calloc((size_t)pairs, sizeof *list);
    for (int k = 0; k < pairs; k++) hk_hair_contacts_pair(c, k, &list[k]);
    int tested = 0;
    for (int k = 0; k < pairs && tested < 25; k++) {
        const hk_HairContactPair pr = list[k];
        if (!(pr.distance < 0.9 * p.distance && pr.distance > 0.1 * p.distance)) continue;
        const int i = pr.strand[0];
        hk_HairContactPair now;
        update_ok(c, &st);
        assert_true(find_pair(c, &pr, &now));
        const hk_PointForce f0 = *pair_force(c, &now, 0);
        if (hk_m3_trace(&f0.stiffness) == 0.0) continue; /* clamped: nothing to differentiate */
        const hk_Vec3 n = hk_v3_normalize(hk_v3_sub(pr.point[0], pr.point[1]));
        /* Position: move strand i along n (the closest points stay the same points). */
        const double eps = 1e-7;
        hk_Vec3 fp, fm;
        translate_strand(&st, i, hk_v3_scale(n, eps));
        update_ok(c, &st);
        assert_true(find_pair(c, &pr, &now));
        hk_assert_near(now.distance, pr.distance + eps, 1e-13);
        fp = pair_force(c, &now, 0)->force;
        translate_strand(&st, i, hk_v3_scale(n, -2 * eps));
        update_ok(c, &st);
        assert_true(find_pair(c, &pr, &now));
        fm = pair_force(c, &now, 0)->force;
        translate_strand(&st, i, hk_v3_scale(n, eps));
        const hk_Vec3 fd = hk_v3_scale(hk_v3_sub(fp, fm), -0.5 / eps);
        const hk_Vec3 kn = hk_m3_mul_v3(&f0.stiffness, n);
        hk_assert_near(hk_v3_dist(fd, kn), 0.0, 1e-6 * p.stiffness);
        /* Velocity: every direction (the force is linear in v while unclamped). */
        for (int ax = 0; ax < 3; ax++) {
            const double ev = 1e-6;
            add_velocity(&st, i, hk_v3_scale(hk_v3_unit(ax), ev));
            update_ok(c, &st);
            assert_true(find_pair(c, &pr, &now));
            fp = pair_force(c, &now, 0)->force;
            add_velocity(&st, i, hk_v3_scale(hk_v3_unit(ax), -2 * ev));
            update_ok(c, &st);
            assert_true(find_pair(c, &pr, &now));
            fm = pair_force(c, &now, 0)->force;
            add_velocity(&st, i, hk_v3_scale(hk_v3_unit(ax), ev));
            const hk_Vec3 dv = hk_v3_scale(hk_v3_sub(fp, fm), -0.5 / ev);
            const hk_Vec3 col = hk_m3_col(&f0.damping, ax);
            hk_assert_near(hk_v3_dist(dv, col), 0.0, 1e-6 * p.damping);
        }
        /* Symmetric, positive semi-definite. */
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) {
                assert_true(f0.stiffness.m[a][b] == f0.stiffness.m[b][a]);
                assert_true(f0.damping.m[a][b] == f0.damping.m[b][a]);
            }
        for (int t = 0; t < 10; t++) {
            hk_Vec3 x = random_unit();
            assert_true(hk_v3_dot(x, hk_m3_mul_v3(&f0.stiffness, x)) >= -1e-18);
            assert_true(hk_v3_dot(x, hk_m3_mul_v3(&f0.damping, x)) >= -1e-18);
        }
        tested++;
    }
    assert_true(tested >= 10);
    free(list);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

/* The damping part F(v) - F(0) of every contact does negative work on the relative
 * velocity (rigidly moving strands, so each contact's relative velocity is known). */
static void test_dissipation(void **state)
{
    (void)state;
    hk_HairContactDef p = test_params();
    p.damping = 0.01;
    Strands st = random_strands(60, 30, 0.004, 0.04);
    hk_Vec3 *strand_vel = calloc((size_t)st.g, sizeof *strand_vel);
    for (int i = 0; i < st.g; i++) {
        strand_vel[i] = hk_v3_scale(random_unit(), 0.3 * uniform());
        for (int k = 0; k < st.n; k++) *V(&st, i, k) = strand_vel[i];
    }
    hk_HairContacts *moving = make_contacts(st.g, &p), *still = make_contacts(st.g, &p);
    update_ok(moving, &st);
    for (int i = 0; i < st.g; i++) st.ss[i].vel = NULL;
    update_ok(still, &st);
    int checked = 0, clamped = 0;
    for (int k = 0; k < hk_hair_contacts_pair_count(moving); k++) {
        hk_HairContactPair pr;
        hk_hair_contacts_pair(moving, k, &pr);
        if (!(pr.distance < p.distance)) continue;
        hk_HairContactPair at_rest;
        assert_true(find_pair(still, &pr, &at_rest));
        const hk_PointForce *fv = pair_force(moving, &pr, 0), *f0 = pair_force(still, &at_rest, 0);
        const hk_Vec3 w = hk_v3_sub(strand_vel[pr.strand[0]], strand_vel[pr.strand[1]]);
        const double power = hk_v3_dot(hk_v3_sub(fv->force, f0->force), w);
        assert_true(power <= 1e-18);
        clamped += hk_m3_trace(&fv->stiffness) == 0.0;
        checked++;
    }
    assert_true(checked > 20 && clamped > 0);
    free(strand_vel);
    hk_hair_contacts_destroy(moving);
    hk_hair_contacts_destroy(still);
    strands_free(&st);
}

/* Solves the 3x3 system a x = b (Gaussian elimination with partial pivoting). */
static hk_Vec3 solve3(hk_Mat3 a, hk_Vec3 b)
{
    double m[3][4];
    for (int r = 0; r < 3; r++) {
        for (int k = 0; k < 3; k++) m[r][k] = a.m[r][k];
        m[r][3] = hk_v3_get(b, r);
    }
    for (int col = 0; col < 3; col++) {
        int piv = col;
        for (int r = col + 1; r < 3; r++)
            if (fabs(m[r][col]) > fabs(m[piv][col])) piv = r;
        for (int k = 0; k < 4; k++) {
            double t = m[col][k];
            m[col][k] = m[piv][k], m[piv][k] = t;
        }
        for (int r = col + 1; r < 3; r++) {
            const double f = m[r][col] / m[col][col];
            for (int k = col; k < 4; k++) m[r][k] -= f * m[col][k];
        }
    }
    double x[3];
    for (int r = 2; r >= 0; r--) {
        double acc = m[r][3];
        for (int k = r + 1; k < 3; k++) acc -= m[r][k] * x[k];
        x[r] = acc / m[r][r];
    }
    return hk_v3(x[0], x[1], x[2]);
}

/* The defaults with the implicit step the dynamics takes, at dt = 1/30 s, on a guide
 * (20 cm, one hair's mass, moving as a rigid body here) against another held still.
 * Resting on it under gravity, the guide settles at the penetration m g / k (0.5% of
 * d0) without oscillating; thrown at it at 10 cm/s (no gravity), it stops without
 * passing through and leaves again at less than a fifth of that speed (about 9 mm/s:
 * hair clumps collide inelastically). (In free fall the
 * guide would move dt^2 g = 1.1 cm in one step, more than 2 d0, and pass through:
 * the limit of detection at discrete times, which a real guide, held by its root and
 * its stiffness, does not reach.) */
static void test_implicit_step_with_defaults(void **state)
{
    (void)state;
    hk_HairContactDef p = hk_default_hair_contact_def();
    p.root_exclusion = 0.0;
    const double dt = 1.0 / 30.0, mass_per_length = 6.5e-6, length = 0.2;
    const int n = 41;
    for (int trial = 0; trial < 4; trial++) {
        /* The whole guide's mass, or a third of it (what a contact point feels). */
        const double m = mass_per_length * length / (trial % 2 == 0 ? 1.0 : 3.0);
        const int resting = trial < 2;
        const double g = resting ? 9.81 : 0.0;
        Strands st = strands_alloc(2, n);
        hk_Vec3 x = resting ? hk_v3(0.0, p.distance - 1e-4, 0.0) : hk_v3(0.0, 0.008, 0.0);
        hk_Vec3 v = resting ? hk_v3_zero() : hk_v3(0.0, -0.1, 0.0);
        hk_HairContacts *c = make_contacts(2, &p);
        double max_rebound = 0.0, lowest = HUGE_VAL;
        int turns = 0;
        for (int step = 0; step < 90; step++) {
            for (int k = 0; k < n; k++) {
                st.s[k] = st.s[n + k] = length * k / (n - 1);
                *P(&st, 0, k) = hk_v3_add(x, hk_v3(length * k / (n - 1) - 0.5 * length, 0.0, 0.0));
                *V(&st, 0, k) = v;
                *P(&st, 1, k) = hk_v3(0.0, 0.0, length * k / (n - 1) - 0.5 * length);
                *V(&st, 1, k) = hk_v3_zero();
            }
            update_ok(c, &st);
            int count;
            const hk_PointForce *f = hk_hair_contacts_forces(c, 0, &count);
            hk_Vec3 force = hk_v3(0.0, -m * g, 0.0);
            hk_Mat3 k_sum = hk_m3_zero(), d_sum = hk_m3_zero();
            for (int q = 0; q < count; q++) {
                force = hk_v3_add(force, f[q].force);
                k_sum = hk_m3_add(&k_sum, &f[q].stiffness);
                d_sum = hk_m3_add(&d_sum, &f[q].damping);
            }
            /* m (v' - v) = dt (F - K dt v' - D (v' - v)): linearly implicit Euler. */
            hk_Mat3 a = hk_m3_scale(&d_sum, dt), kk = hk_m3_scale(&k_sum, dt * dt), id = hk_m3_identity();
            a = hk_m3_add(&a, &kk);
            id = hk_m3_scale(&id, m);
            a = hk_m3_add(&a, &id);
            const hk_Vec3 rhs =
                hk_v3_add(hk_v3_madd(hk_v3_scale(v, m), force, dt), hk_v3_scale(hk_m3_mul_v3(&d_sum, v), dt));
            const hk_Vec3 v_new = solve3(a, rhs);
            turns += v_new.y * v.y < 0.0 && fabs(v_new.y) > 1e-6 && fabs(v.y) > 1e-6; /* above rounding */
            v = v_new;
            x = hk_v3_madd(x, v, dt);
            assert_true(hk_v3_isfinite(x));
            lowest = fmin(lowest, x.y);
            max_rebound = fmax(max_rebound, v.y);
        }
        assert_true(lowest > 0.5 * p.distance); /* never through the other guide, nor deep in it */
        assert_true(max_rebound < 0.1);         /* dissipative: no faster than it came */
        if (resting) {
            hk_assert_near(x.y, p.distance - m * g / p.stiffness, 1e-9);
            hk_assert_near(hk_v3_norm(v), 0.0, 1e-9);
            assert_true(turns <= 1); /* settles, does not ring */
        } else {
            assert_true(x.y >= p.distance - 1e-9); /* pushed back out of contact */
            assert_true(max_rebound < 0.02);       /* nearly inelastic: restitution below 0.2 */
        }
        hk_hair_contacts_destroy(c);
        strands_free(&st);
    }
}

/* ---- determinism and cost -------------------------------------------------------- */

/* All forces of all strands after `updates` updates with small motions in between,
 * as one byte string (caller frees). */
static unsigned char *run_bytes(int threads, size_t *size)
{
    hk_HairContactDef p = test_params();
    p.rescan_interval = 3;
    Strands st = random_strands(120, 40, 0.004, 0.06);
    p.threads = threads;
    hk_HairContacts *c = make_contacts(st.g, &p);
    unsigned char *bytes = NULL;
    size_t used = 0;
    for (int u = 0; u < 7; u++) {
        update_ok(c, &st);
        for (int g = 0; g < st.g; g++) {
            int count;
            const hk_PointForce *f = hk_hair_contacts_forces(c, g, &count);
            bytes = realloc(bytes, used + sizeof(int) + (size_t)count * sizeof *f);
            assert_non_null(bytes);
            memcpy(bytes + used, &count, sizeof count);
            used += sizeof count;
            if (count) memcpy(bytes + used, f, (size_t)count * sizeof *f);
            used += (size_t)count * sizeof *f;
        }
        small_motion(&st, 0.001);
    }
    hk_hair_contacts_destroy(c);
    strands_free(&st);
    *size = used;
    return bytes;
}

static void test_determinism(void **state)
{
    (void)state;
    const int threads[4] = {1, 1, 2, 4};
    size_t ref_size = 0;
    rng_seed(7);
    unsigned char *ref = run_bytes(threads[0], &ref_size);
    assert_true(ref_size > 100000); /* there were forces to compare */
    for (int t = 1; t < 4; t++) {
        size_t size;
        rng_seed(7);
        unsigned char *bytes = run_bytes(threads[t], &size);
        assert_int_equal(size, ref_size);
        assert_memory_equal(bytes, ref, size);
        free(bytes);
    }
    /* the baseline's code gives the AVX twins' bytes (core/avx_twins.h) */
    const int had_avx = hk_avx_paths_allow(0);
    size_t size;
    rng_seed(7);
    unsigned char *bytes = run_bytes(2, &size);
    hk_avx_paths_allow(1);
    if (!had_avx) print_message("no AVX on this machine: the baseline compared with itself\n");
    assert_int_equal(size, ref_size);
    assert_memory_equal(bytes, ref, size);
    free(bytes);
    free(ref);
}

static void test_linear_cost(void **state)
{
    (void)state;
    /* The same hair twice, the copy far away: twice the segments, twice the work of
     * the tracking (exactly) and of the broad phase (about), not four times. */
    hk_HairContactDef p = test_params();
    p.rescan_interval = 1000000;
    Strands one = random_strands(80, 40, 0.004, 0.05);
    Strands two = strands_alloc(160, 40);
    for (int copy = 0; copy < 2; copy++)
        for (int i = 0; i < 80; i++)
            for (int k = 0; k < 40; k++) {
                two.s[((size_t)copy * 80 + i) * 40 + k] = one.s[(size_t)i * 40 + k];
                *P(&two, copy * 80 + i, k) = hk_v3_add(*P(&one, i, k), hk_v3(copy * 10.0, 0, 0));
                *V(&two, copy * 80 + i, k) = *V(&one, i, k);
            }
    hk_HairContacts *c1 = make_contacts(80, &p), *c2 = make_contacts(160, &p);
    update_ok(c1, &one);
    update_ok(c2, &two);
    const long scan1 = c1->distance_evaluations, scan2 = c2->distance_evaluations;
    assert_int_equal(hk_hair_contacts_pair_count(c2), 2 * hk_hair_contacts_pair_count(c1));
    assert_true(scan2 <= 3 * scan1);
    /* Brute force would measure every segment pair: (80 * 39)^2 / 2, about 5e6. */
    assert_true(scan1 < 80L * 39 * 80 * 39 / 20);
    update_ok(c1, &one);
    update_ok(c2, &two);
    assert_int_equal(c2->distance_evaluations, 2 * c1->distance_evaluations);
    assert_true(c1->distance_evaluations <= 9L * 20 * hk_hair_contacts_pair_count(c1));
    hk_hair_contacts_destroy(c1);
    hk_hair_contacts_destroy(c2);
    strands_free(&one);
    strands_free(&two);
}

/* ---- bad input ------------------------------------------------------------------- */

static void test_bad_input(void **state)
{
    (void)state;
    hk_Error err;
    hk_HairContacts *c = (hk_HairContacts *)&err; /* must be reset to NULL on failure */
    hk_HairContactDef p = hk_default_hair_contact_def();
    assert_int_equal(hk_hair_contacts_create(0, &p, &c, &err), HK_ERR_INVALID);
    assert_null(c);
    assert_int_equal(hk_hair_contacts_create(-3, &p, &c, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_contacts_create(2, &p, NULL, &err), HK_ERR_INVALID);
    hk_HairContactDef bad = p;
    bad.distance = NAN;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "distance");
    bad = p, bad.distance = 0.0;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    bad = p, bad.stiffness = -1.0;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    bad = p, bad.damping = INFINITY;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    bad = p, bad.friction = -1e-9;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    bad = p, bad.root_exclusion = NAN;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    bad = p, bad.rescan_interval = 0;
    assert_int_equal(hk_hair_contacts_create(2, &bad, &c, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_contacts_create(2, NULL, &c, &err), HK_OK); /* NULL: defaults */
    hk_hair_contacts_destroy(c);
    hk_hair_contacts_destroy(NULL);

    p.root_exclusion = 0.0;
    Strands st = strands_alloc(2, 10); /* two strands crossing 2 mm apart */
    for (int k = 0; k < 10; k++) {
        st.s[k] = st.s[10 + k] = 0.004 * k;
        *P(&st, 0, k) = hk_v3(0.004 * k - 0.018, 0.0, 0.0);
        *P(&st, 1, k) = hk_v3(0.0, 0.002, 0.004 * k - 0.018);
    }
    c = make_contacts(2, &p);
    update_ok(c, &st);
    const int good_pairs = hk_hair_contacts_pair_count(c);
    assert_true(hk_hair_contacts_contact_count(c) > 0);
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 3, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 0, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_contacts_update(c, NULL, 2, &err), HK_ERR_INVALID);
    assert_int_equal(hk_hair_contacts_update(NULL, st.ss, 2, &err), HK_ERR_INVALID);
    const int counts[] = {1, 0, -5, 1 << 30};
    for (int k = 0; k < 4; k++) {
        st.ss[1].count = counts[k];
        assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
        hk_assert_contains(err.message, "samples");
    }
    st.ss[1].count = 10;
    /* After a failed update there are no forces, and the pairs are kept. */
    int count = -1;
    assert_null(hk_hair_contacts_forces(c, 0, &count));
    assert_int_equal(count, 0);
    assert_int_equal(hk_hair_contacts_contact_count(c), 0);
    assert_int_equal(hk_hair_contacts_pair_count(c), good_pairs);
    hk_HairContactPair kept;
    assert_true(hk_hair_contacts_pair(c, 0, &kept));
    assert_true(kept.force[0] == -1 && kept.force[1] == -1);
    const double nan = NAN;
    P(&st, 1, 4)->y = nan;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "position");
    P(&st, 1, 4)->y = 0.0;
    V(&st, 0, 9)->z = INFINITY;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "velocity");
    V(&st, 0, 9)->z = 0.0;
    st.s[3] = 1.0; /* s decreases after it */
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "arc length");
    st.s[3] = nan;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    st.s[3] = 3 * 0.004;
    const double *s_saved = st.ss[0].s;
    st.ss[0].s = NULL;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    st.ss[0].s = s_saved;
    st.ss[0].pos = NULL;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    st.ss[0].pos = st.pos;
    /* Positions spanning more than doubles can: an error from the broad phase (the
     * tracking just loses the pairs), not a crash. */
    hk_hair_contacts_request_rescan(c);
    P(&st, 0, 0)->x = 1.7e308;
    P(&st, 1, 0)->x = -1.7e308;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_ERR_INVALID);
    hk_assert_contains(err.message, "range");
    /* Huge but representable: no contacts, no error. */
    P(&st, 0, 0)->x = 1e150;
    P(&st, 1, 0)->x = -1e150;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_OK);
    /* Out-of-range queries. */
    hk_HairContactPair pr;
    assert_int_equal(hk_hair_contacts_pair(c, -1, &pr), 0);
    assert_int_equal(hk_hair_contacts_pair(c, 1 << 30, &pr), 0);
    assert_null(hk_hair_contacts_forces(c, -1, &count));
    assert_null(hk_hair_contacts_forces(c, 2, &count));
    assert_int_equal(hk_hair_contacts_pair_count(NULL), 0);
    /* Degenerate strands: every sample at one point, and a changing sample count. */
    for (int k = 0; k < 20; k++) *P(&st, k / 10, k % 10) = hk_v3(0.01, 0.02, 0.03);
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_OK);
    assert_true(hk_hair_contacts_contact_count(c) == hk_hair_contacts_pair_count(c));
    for (int g = 0; g < 2; g++) {
        const hk_PointForce *f = hk_hair_contacts_forces(c, g, &count);
        for (int k = 0; k < count; k++) assert_true(hk_v3_isfinite(f[k].force));
    }
    st.ss[1].count = 4;
    assert_int_equal(hk_hair_contacts_update(c, st.ss, 2, &err), HK_OK);
    assert_true(c->last_update_rescanned);
    hk_hair_contacts_destroy(c);
    strands_free(&st);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_segment_closest_known),
        cmocka_unit_test(test_segment_closest_reference),
        cmocka_unit_test(test_segment_closest_scalar_bits),
        cmocka_unit_test(test_broad_phase_matches_brute_force),
        cmocka_unit_test(test_tracking_matches_brute_force),
        cmocka_unit_test(test_pair_sort_stable),
        cmocka_unit_test(test_parallel_strands_one_pair),
        cmocka_unit_test(test_root_exclusion_and_self),
        cmocka_unit_test(test_crossing_force_values),
        cmocka_unit_test(test_forces_opposite_never_pull),
        cmocka_unit_test(test_linearisations_finite_differences),
        cmocka_unit_test(test_dissipation),
        cmocka_unit_test(test_implicit_step_with_defaults),
        cmocka_unit_test(test_pairs_along_strands),
        cmocka_unit_test(test_determinism),
        cmocka_unit_test(test_linear_cost),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
