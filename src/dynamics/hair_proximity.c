/* Pairs of closest points between guide strands, tracked over time (paper 000 §4.1,
 * after Raghupathi et al. 2003): a pair is a local minimum of the segment-segment
 * distance over the grid of segment pairs (a, b) of two strands; between updates the
 * strands move a little, so each pair is walked to the neighbouring minimum instead
 * of searching all segment pairs again. Two pairs reaching the same minimum merge. */
#include <string.h>

#include "hair_contacts_internal.h"

hk_HcStrand hk_hc_strand_view(const hk_StrandSamples *in, double root_exclusion)
{
    hk_HcStrand st = {in->count, 0, in->s, in->pos, in->vel};
    /* A segment takes part when some of it lies beyond the exclusion; s is sorted, so
     * they are the segments from the first one whose end passes it. */
    if (root_exclusion > 0.0) {
        int lo = 0, hi = in->count - 1; /* answer in [lo, hi]; hi = count - 1 means none */
        while (lo < hi) {
            int mid = lo + (hi - lo) / 2;
            if (in->s[mid + 1] > root_exclusion)
                hi = mid;
            else
                lo = mid + 1;
        }
        st.first = lo;
    }
    return st;
}

void hk_hc_segment_ends(const hk_HcStrand *st, int k, double root_exclusion, hk_Vec3 *p0, hk_Vec3 *p1, double *t0)
{
    const hk_Vec3 a = st->pos[k], b = st->pos[k + 1];
    double t = 0.0;
    /* Only the first taking part can straddle the exclusion; then s[k] < r < s[k+1],
     * so the division is safe. */
    if (root_exclusion > 0.0 && st->s[k] < root_exclusion) t = (root_exclusion - st->s[k]) / (st->s[k + 1] - st->s[k]);
    *p0 = t > 0.0 ? hk_v3_madd(a, hk_v3_sub(b, a), t) : a;
    *p1 = b;
    *t0 = t;
}

double hk_hc_pair_distance2(const hk_HcStrand *si, int a, const hk_HcStrand *sj, int b, double root_exclusion,
                            double *u, double *v)
{
    hk_HcEnds x, y;
    hk_hc_segment_ends(si, a, root_exclusion, &x.p0, &x.p1, &x.t0);
    hk_hc_segment_ends(sj, b, root_exclusion, &y.p0, &y.p1, &y.t0);
    return hk_hc_ends_distance2(&x, &y, u, v);
}

hk_HcMetric hk_hc_metric(const hk_HairContactDef *p)
{
    hk_HcMetric m = {p->root_exclusion, ldexp(p->distance * p->distance, -40)};
    return m;
}

long long hk_hc_rank(double d2, double quantum)
{
    const double r = d2 / quantum;
    return r < 0x1p62 ? (long long)r : (1LL << 62); /* also catches inf */
}

/* (d, a, b) < (e, c, f) in the order pairs are compared by: rank of the distance
 * first, then the segment indices, so that equal distances (parallel strands,
 * crossings at a sample) still have a single minimum and walks cannot cycle. */
static int pair_less(long long d, int a, int b, long long e, int c, int f)
{
    if (d != e) return d < e;
    if (a != c) return a < c;
    return b < f;
}

static int in_range(const hk_HcStrand *st, int k) { return k >= st->first && k <= st->count - 2; }

int hk_hc_is_local_min(const hk_HcStrand *si, int a, const hk_HcStrand *sj, int b, double d2, const hk_HcMetric *m)
{
    const long long rank = hk_hc_rank(d2, m->quantum);
    for (int da = -1; da <= 1; da++)
        for (int db = -1; db <= 1; db++) {
            if ((da == 0 && db == 0) || !in_range(si, a + da) || !in_range(sj, b + db)) continue;
            double u, v, e = hk_hc_pair_distance2(si, a + da, sj, b + db, m->root_exclusion, &u, &v);
            if (pair_less(hk_hc_rank(e, m->quantum), a + da, b + db, rank, a, b)) return 0;
        }
    return 1;
}

long hk_hc_walk(const hk_HcStrand *si, const hk_HcStrand *sj, const hk_HcMetric *m, hk_HcPair *p, int max_steps)
{
    long evaluations = 1;
    /* A pair whose segment no longer takes part (the strand's sampling or s moved)
     * restarts from the nearest one that does. */
    int a = p->a < si->first ? si->first : (p->a > si->count - 2 ? si->count - 2 : p->a);
    int b = p->b < sj->first ? sj->first : (p->b > sj->count - 2 ? sj->count - 2 : p->b);
    double u, v, d2 = hk_hc_pair_distance2(si, a, sj, b, m->root_exclusion, &u, &v);
    long long rank = hk_hc_rank(d2, m->quantum);
    for (int step = 0; step < max_steps; step++) {
        int best_a = a, best_b = b;
        long long best_rank = rank;
        double best = d2, best_u = u, best_v = v;
        for (int da = -1; da <= 1; da++)
            for (int db = -1; db <= 1; db++) {
                const int na = a + da, nb = b + db;
                if ((da == 0 && db == 0) || !in_range(si, na) || !in_range(sj, nb)) continue;
                double nu, nv, e = hk_hc_pair_distance2(si, na, sj, nb, m->root_exclusion, &nu, &nv);
                const long long er = hk_hc_rank(e, m->quantum);
                evaluations++;
                if (pair_less(er, na, nb, best_rank, best_a, best_b))
                    best = e, best_rank = er, best_a = na, best_b = nb, best_u = nu, best_v = nv;
            }
        if (best_a == a && best_b == b) break;
        a = best_a, b = best_b, d2 = best, rank = best_rank, u = best_u, v = best_v;
    }
    p->a = a, p->b = b, p->d2 = d2, p->u = u, p->v = v;
    return evaluations;
}

void hk_hc_sort_keys(hk_HcKey *keys, int n)
{
    for (int x = 1; x < n; x++) {
        const hk_HcKey key = keys[x];
        int y = x - 1;
        while (y >= 0 && (key.at < keys[y].at || (key.at == keys[y].at && key.index < keys[y].index))) {
            keys[y + 1] = keys[y];
            y--;
        }
        keys[y + 1] = key;
    }
}

int hk_hc_append_pairs(hk_HcPair **array, int *count, int *cap, const hk_HcPair *p, int n, hk_Error *err)
{
    if (n > *cap - *count) {
        if (n > (1 << 29) - *count) {
            hk_error_set(err, HK_ERR_NOMEM, "more than %d hair-hair pairs", 1 << 29);
            return 0;
        }
        int new_cap = *cap < 64 ? 64 : 2 * *cap;
        while (new_cap - *count < n) new_cap *= 2;
        hk_HcPair *grown = hk_alloc_array((size_t)new_cap, sizeof *grown, err);
        if (!grown) return 0;
        if (*count > 0) memcpy(grown, *array, (size_t)*count * sizeof *grown);
        hk_free(*array);
        *array = grown;
        *cap = new_cap;
    }
    if (n > 0) memcpy(*array + *count, p, (size_t)n * sizeof *p);
    *count += n;
    return 1;
}


static int grow_ints(int **array, int *cap, int need, hk_Error *err)
{
    if (need <= *cap) return 1;
    int *grown = hk_alloc_array((size_t)need, sizeof *grown, err);
    if (!grown) return 0;
    hk_free(*array);
    *array = grown;
    *cap = need;
    return 1;
}

hk_Status hk_hc_sort(hk_HairContacts *c, hk_HcPair **sorted, int *cap, int n, hk_Error *err)
{
    const hk_HcPair *pairs = *sorted;
    /* Global index of the segment (i, a): offsets of the strands' segments. */
    const int g = c->strand_count;
    long total = 0;
    for (int s = 0; s < g; s++) total += c->views[s].count - 1;
    if (!grow_ints(&c->bucket, &c->bucket_cap, (int)total + g + 1, err)) return HK_ERR_NOMEM;
    if (!grow_ints(&c->pair_order, &c->pair_order_cap, 2 * n, err)) return HK_ERR_NOMEM;
    if (!grow_ints(&c->pair_key, &c->pair_key_cap, 2 * n, err)) return HK_ERR_NOMEM;
    if (c->pairs_tmp_cap < n) {
        hk_HcPair *tmp = hk_alloc_array((size_t)n, sizeof *tmp, err);
        if (!tmp) return HK_ERR_NOMEM;
        hk_free(c->pairs_tmp);
        c->pairs_tmp = tmp;
        c->pairs_tmp_cap = n;
    }
    /* bucket[0..g) hold the strands' offsets, bucket[g..] the run of each segment:
     * counts, then starts, then (after the placement below) ends. */
    int *offset = c->bucket, *end = c->bucket + g;
    long acc = 0;
    for (int s = 0; s < g; s++) offset[s] = (int)acc, acc += c->views[s].count - 1;
    /* Two stable counting sorts, the second key last (radix order): the pairs by
     * (j, b), then that order by (i, a). An insertion sort of each (i, a) run by (j,
     * b) took the place of the first before: the runs come in the pair loop's order,
     * far from sorted: the sort took 30.1 million instructions in 8 frames of
     * examples/guides200 shaking with the settling's (15,000 candidates a rescan, 23
     * rescans), then 19.7. The sorts now order the pairs' places by their segments'
     * global indices, found once a pair (key), and the pairs are gathered once, in
     * their sorted order: the 40-byte pairs were read three times and written to
     * scattered places (1.10 million first-level read misses and 0.39 million write
     * misses in those 23 rescans, cachegrind, for 0.35 million pairs). */
    int *key_jb = c->pair_key, *key_ia = c->pair_key + n;
    int *by_jb = c->pair_order, *by_ia = c->pair_order + n;
    for (int k = 0; k < n; k++) {
        key_ia[k] = offset[pairs[k].i] + pairs[k].a;
        key_jb[k] = offset[pairs[k].j] + pairs[k].b;
    }
    memset(end, 0, (size_t)(total + 1) * sizeof *end);
    for (int k = 0; k < n; k++) end[key_jb[k] + 1]++;
    for (long k = 0; k < total; k++) end[k + 1] += end[k];
    for (int k = 0; k < n; k++) by_jb[end[key_jb[k]]++] = k;
    memset(end, 0, (size_t)(total + 1) * sizeof *end);
    for (int k = 0; k < n; k++) end[key_ia[k] + 1]++;
    for (long k = 0; k < total; k++) end[k + 1] += end[k];
    for (int q = 0; q < n; q++) {
        const int k = by_jb[q];
        by_ia[end[key_ia[k]]++] = k;
    }
    hk_HcPair *tmp = c->pairs_tmp;
    for (int q = 0; q < n; q++) tmp[q] = pairs[by_ia[q]];
    /* The buffers trade places instead of a copy back (13.9 million instructions of
     * memcpy in 8 frames of examples/guides200 shaking). */
    c->pairs_tmp = *sorted, *sorted = tmp;
    const int tmp_cap = c->pairs_tmp_cap;
    c->pairs_tmp_cap = *cap, *cap = tmp_cap;
    return HK_OK;
}

void hk_hc_run(const hk_HairContacts *c, int i, int a, int *begin, int *end)
{
    const int g = c->strand_count, gid = c->bucket[i] + a;
    *begin = gid == 0 ? 0 : c->bucket[g + gid - 1];
    *end = c->bucket[g + gid];
}

hk_Status hk_hc_sort_unique(hk_HairContacts *c, hk_Error *err)
{
    hk_Status st = hk_hc_sort(c, &c->pairs, &c->pair_cap, c->pair_count, err);
    if (st != HK_OK) return st;
    int out = 0;
    for (int k = 0; k < c->pair_count; k++) {
        const hk_HcPair *q = &c->pairs[k];
        if (out > 0 && c->pairs[out - 1].i == q->i && c->pairs[out - 1].a == q->a && c->pairs[out - 1].j == q->j &&
            c->pairs[out - 1].b == q->b)
            continue; /* two tracked pairs reached the same minimum */
        c->pairs[out++] = *q;
    }
    c->pair_count = out;
    return HK_OK;
}

hk_Status hk_hc_track(hk_HairContacts *c, hk_Error *err)
{
    const hk_HcMetric m = hk_hc_metric(&c->p);
    const double band2 = 4.0 * c->p.distance * c->p.distance;
    long evaluations = 0;
    const int n = c->pair_count;
    /* Each walk reads the strands and writes its own pair: the result does not depend
     * on which thread does it. */
#pragma omp parallel for schedule(static) reduction(+ : evaluations) num_threads(hk_hc_threads(c))
    for (int k = 0; k < n; k++) {
        hk_HcPair *p = &c->pairs[k];
        const hk_HcStrand *si = &c->views[p->i], *sj = &c->views[p->j];
        if (si->first > si->count - 2 || sj->first > sj->count - 2) {
            p->d2 = HUGE_VAL; /* a strand lost every segment: the pair goes */
            continue;
        }
        /* Between updates a minimum moves by a segment or two; a walk longer than the
         * two strands has lost its way and stops (the next rescan finds the pair). */
        evaluations += hk_hc_walk(si, sj, &m, p, 2 * (si->count + sj->count));
    }
    c->distance_evaluations += evaluations;
    int kept = 0;
    for (int k = 0; k < n; k++)
        if (c->pairs[k].d2 < band2) c->pairs[kept++] = c->pairs[k];
    c->pair_count = kept;
    return hk_hc_sort_unique(c, err);
}
