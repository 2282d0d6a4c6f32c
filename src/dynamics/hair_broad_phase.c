/* Broad phase of the hair-hair contacts: the search that discovers new pairs every
 * few updates, between which pairs are only tracked (paper 000 §4.1, after
 * Raghupathi et al. 2003). Segment boxes grown by d0 go into a uniform grid hashed
 * into buckets by a counting sort (linear time, and the order of the entries is that
 * of the segments by their low x, so the result does not depend on anything but the
 * input), where a sweep along x meets the boxes that may overlap; two
 * segments sharing a cell are measured once, in the cell holding the low corner of
 * the overlap of their boxes. A segment pair within 2 d0 that is a local minimum of
 * the distance becomes a pair: its neighbours within 2 d0 are candidates too, so the
 * test is a look-up, not more measuring. */
#include <omp.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <stdint.h>
#include <string.h>

#include "hair_contacts_internal.h"

/* One cell covered by a segment's box, written in bucket order so that the pair loop
 * reads memory in sequence, two entries a cache line (the array aligned to 64 bytes).
 * The box [lo, hi] as high = (hi, -lo) in floats (rounded to nearest); its low = (lo,
 * -hi) is high negated and reordered (see entry_low), made once a sweep for the entry
 * it starts from: two boxes overlap when a's low is at most b's high everywhere (a.lo
 * <= b.hi and b.lo <= a.hi), six comparisons in two. Rounding to nearest is monotonic
 * and symmetric (float(-x) = -float(x)), so a.lo <= b.hi in doubles gives float(a.lo)
 * <= float(b.hi): the floats' boxes overlap wherever the doubles' do, and the few pairs
 * more they let through (apart by less than a float's rounding) are dropped by
 * surely_apart or the measure, which take the doubles: the same candidates. The
 * entries were 64 bytes with the box in doubles (and 128 before, its low beside it):
 * the pair loop reads half the memory, and the entries' writes to their scattered
 * places (~26,000 entries a rescan of examples/guides200 shaking) touch half the
 * lines. The strand shares a word with the start bits: key = strand << 8 | 1 << s, s
 * with bit a set where the box starts in this cell along axis a. */
typedef struct Entry {
    float high[6]; /* hi.x, hi.y, hi.z, -lo.x, -lo.y, -lo.z */
    int32_t x_lo;  /* slab of the box's low x (see slab_of) */
    uint32_t key;
} Entry;
_Static_assert(sizeof(Entry) == 32, "two entries are meant to share a cache line");

/* What the pair loop's later stages need of an entry (at the entry's place). */
typedef struct EntryTag {
    uint64_t cell; /* the cell's coordinates packed (cell_key): equal keys, the same cell */
    int seg;       /* eligible segment index e */
    int32_t x_hi;  /* slab of the box's high x, where a sweep from the entry ends */
} EntryTag;

#ifdef __SSE2__
/* The low corner of an entry's box as (lo, -hi), from its high (hi, -lo): low4 = (lo.x,
 * lo.y, lo.z, -hi.x) and low2 = (-hi.y, -hi.z, -0, -0) (see boxes_overlap), the
 * high's lanes reordered and negated (exact). */
static void entry_low(const Entry *e, __m128 *low4, __m128 *low2)
{
    const __m128 sign = _mm_set1_ps(-0.0f);
    const __m128 high4 = _mm_load_ps(e->high);
    const __m128 high2 = _mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)&e->high[4]));
    const __m128 mixed = _mm_shuffle_ps(high4, high2, _MM_SHUFFLE(1, 0, 0, 3)); /* (h3, h0, h4, h5) */
    *low4 = _mm_xor_ps(sign, _mm_shuffle_ps(mixed, mixed, _MM_SHUFFLE(1, 3, 2, 0)));
    *low2 = _mm_xor_ps(sign, _mm_shuffle_ps(high4, _mm_setzero_ps(), _MM_SHUFFLE(0, 0, 2, 1)));
}
#else
/* The low corner of an entry's box as (lo, -hi): low4 = (lo.x, lo.y, lo.z, -hi.x),
 * low2 = (-hi.y, -hi.z), from its high (hi, -lo). */
static void entry_low(const Entry *e, float low4[4], float low2[2])
{
    low4[0] = -e->high[3], low4[1] = -e->high[4], low4[2] = -e->high[5], low4[3] = -e->high[0];
    low2[0] = -e->high[1], low2[1] = -e->high[2];
}
#endif

/* Candidates found by one thread, and its list of the entry pairs of one bucket
 * that pass the pair loop's tests (see the pair loop), as places in sorted, x then
 * y. */
typedef struct Found {
    hk_HcPair *pairs;
    int count, cap;
    uint64_t *passed;  /* place of x << 32 | place of y (y's in the low half: the next y is one more) */
    size_t passed_cap; /* entry pairs */
} Found;

/* What the pair loop's list reads of a segment, one cache line (the array aligned to
 * 64 bytes): surely_apart's midpoint, half-vector and reach, and the segment's index
 * on its strand for the candidate. Four arrays before: the list's pairs, scattered,
 * missed the first-level cache on up to seven lines a pair (0.57 million read misses
 * in surely_apart, 23 rescans of examples/guides200 shaking, cachegrind). */
typedef struct SegBound {
    hk_Vec3 mid;  /* its midpoint */
    hk_Vec3 half; /* half of it, (p1 - p0) / 2 */
    double reach; /* half its length plus d0, grown a little for rounding */
    int index;    /* its index on its strand */
} SegBound;
_Static_assert(sizeof(SegBound) == 64, "SegBound is meant to be one cache line");

/* Scratch kept between rescans. */
typedef struct Grid {
    int seg_cap;
    int *seg_strand;   /* eligible segment e is segment bound[e].index of seg_strand[e] */
    hk_Vec3 *lo, *hi;  /* its box grown by d0 */
    void *bound_block; /* allocated; bound is it aligned to 64 bytes */
    SegBound *bound;
    hk_HcEnds *ends;   /* the part of it that takes part */
    size_t *seg_entry; /* n + 1: segment e's entries are [seg_entry[e], seg_entry[e + 1]) */
    size_t entry_cap;
    uint32_t *entry_bucket;
    void *sorted_block; /* allocated; sorted is it aligned to 64 bytes */
    Entry *sorted;      /* entries by bucket */
    EntryTag *tags;     /* theirs, at the same places */
    int *place;         /* per entry (segment by segment, cells in order): its place in sorted */
    size_t table_cap;
    size_t *bucket_start; /* 2 table size + 1: per bucket, its two runs (see the pair loop) */
    uint32_t *crowded;    /* 2 per bucket where the pair loop has work: where its two runs begin in sorted */
    int found_count;
    Found *found; /* per thread */
    int flag_cap;
    unsigned char *is_min; /* per candidate */
    int strand_cap;
    int *strand_seg;    /* strand_count + 1: strand s's eligible segments start at strand_seg[s] */
    int *seg_order;     /* the segments by the slab of their box's low x, then by index */
    int32_t *seg_cells; /* 6 per segment: the cells of its box's low and high corners */
    int32_t *seg_slab;  /* 2 per segment: the slabs of its box's low and high x */
    size_t slab_cap;
    int *slab_start; /* slabs + 1 */
} Grid;

void hk_hc_grid_free(hk_HairContacts *c)
{
    Grid *g = c->grid;
    if (!g) return;
    hk_free(g->seg_strand), hk_free(g->bound_block), hk_free(g->lo), hk_free(g->hi);
    hk_free(g->ends), hk_free(g->seg_entry), hk_free(g->place);
    hk_free(g->entry_bucket), hk_free(g->sorted_block), hk_free(g->tags);
    hk_free(g->bucket_start), hk_free(g->is_min), hk_free(g->strand_seg), hk_free(g->seg_order);
    hk_free(g->slab_start), hk_free(g->seg_cells), hk_free(g->seg_slab), hk_free(g->crowded);
    for (int t = 0; t < g->found_count; t++) hk_free(g->found[t].pairs), hk_free(g->found[t].passed);
    hk_free(g->found);
    hk_free(g);
    c->grid = NULL;
}

static hk_Status reserve_segments(Grid *g, int n, hk_Error *err)
{
    if (n <= g->seg_cap) return HK_OK;
    hk_free(g->seg_strand), hk_free(g->bound_block), hk_free(g->lo), hk_free(g->hi);
    hk_free(g->ends), hk_free(g->seg_entry), hk_free(g->seg_order), hk_free(g->seg_cells), hk_free(g->seg_slab);
    g->seg_cells = hk_alloc_array((size_t)n, 6 * sizeof(int32_t), err);
    g->seg_slab = hk_alloc_array((size_t)n, 2 * sizeof(int32_t), err);
    g->seg_order = hk_alloc_array((size_t)n, sizeof(int), err);
    g->seg_entry = hk_alloc_array((size_t)n + 1, sizeof(size_t), err);
    g->seg_strand = hk_alloc_array((size_t)n, sizeof(int), err);
    /* (one more for the alignment) */
    g->bound_block = hk_alloc_array((size_t)n + 1, sizeof(SegBound), err);
    g->bound = g->bound_block ? (SegBound *)(((uintptr_t)g->bound_block + 63) & ~(uintptr_t)63) : NULL;
    g->lo = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    g->hi = hk_alloc_array((size_t)n, sizeof(hk_Vec3), err);
    g->ends = hk_alloc_array((size_t)n, sizeof(hk_HcEnds), err);
    g->seg_cap = n;
    if (g->seg_strand && g->bound && g->lo && g->hi && g->ends && g->seg_entry && g->seg_cells && g->seg_slab &&
        g->seg_order)
        return HK_OK;
    g->seg_cap = 0;
    return HK_ERR_NOMEM;
}

static hk_Status reserve_entries(Grid *g, size_t n, size_t table, hk_Error *err)
{
    if (n > g->entry_cap) {
        hk_free(g->entry_bucket), hk_free(g->sorted_block), hk_free(g->tags), hk_free(g->place), hk_free(g->crowded);
        g->crowded = hk_alloc_array(n / 2 + 1, 2 * sizeof(uint32_t), err);
        g->place = hk_alloc_array(n, sizeof(int), err);
        g->entry_bucket = hk_alloc_array(n, sizeof(uint32_t), err);
        /* (and the crowded buckets' runs' ends, two a bucket of two entries or more;
         * one entry more for the alignment) */
        g->sorted_block = hk_alloc_array(2 * n + 2, sizeof(Entry), err);
        g->sorted = g->sorted_block ? (Entry *)(((uintptr_t)g->sorted_block + 63) & ~(uintptr_t)63) : NULL;
        g->tags = hk_alloc_array(2 * n + 1, sizeof(EntryTag), err);
        g->entry_cap = n;
        if (!g->entry_bucket || !g->sorted || !g->tags || !g->place || !g->crowded) {
            g->entry_cap = 0;
            return HK_ERR_NOMEM;
        }
    }
    if (2 * table + 1 > g->table_cap) {
        hk_free(g->bucket_start);
        g->bucket_start = hk_alloc_array(2 * table + 1, sizeof(size_t), err);
        g->table_cap = g->bucket_start ? 2 * table + 1 : 0;
        if (!g->bucket_start) return HK_ERR_NOMEM;
    }
    return HK_OK;
}

/* Per thread, its candidates and a list of passed entry pairs for `passed` of them. */
static hk_Status reserve_threads(Grid *g, int threads, size_t passed, hk_Error *err)
{
    if (threads > g->found_count) {
        Found *grown = hk_calloc_array((size_t)threads, sizeof *grown, err);
        if (!grown) return HK_ERR_NOMEM;
        if (g->found_count > 0) memcpy(grown, g->found, (size_t)g->found_count * sizeof *grown);
        hk_free(g->found);
        g->found = grown;
        g->found_count = threads;
    }
    for (int t = 0; t < threads; t++) {
        Found *f = &g->found[t];
        if (passed <= f->passed_cap) continue;
        hk_free(f->passed);
        f->passed = hk_alloc_array(passed, sizeof(uint64_t), err);
        f->passed_cap = f->passed ? passed : 0;
        if (!f->passed) return HK_ERR_NOMEM;
    }
    return HK_OK;
}

/* The smaller and larger of two finite numbers: fmin and fmax are calls at -O2 (their
 * NaN rules keep GCC from using minsd), 6.4 million a step's loops on
 * examples/guides200; the inputs here are finite (checked), and where the two differ
 * (only in the sign of a zero) every use gives the same bits (a box side, a gap of
 * zero). */
static double min2(double a, double b) { return a < b ? a : b; }
static double max2(double a, double b) { return a > b ? a : b; }

/* Integer cell coordinate of x along one axis (x >= origin, and (x - origin) / h
 * below 2^20 by the choice of h). The same expression serves boxes and corners. */
static int32_t cell_of(double x, double origin, double h) { return (int32_t)((x - origin) / h); }

/* The cell's coordinates (each in [0, 2^20]: see cell_of) packed 21 bits apiece, one
 * comparison for the pair loop's test of the same cell instead of three. */
static uint64_t cell_key(int32_t x, int32_t y, int32_t z)
{
    return (uint64_t)(uint32_t)x << 42 | (uint64_t)(uint32_t)y << 21 | (uint64_t)(uint32_t)z;
}

static uint32_t bucket_of(const int32_t cell[3], uint32_t mask)
{
    uint64_t k = (uint64_t)(uint32_t)cell[0] * 0x9E3779B97F4A7C15ULL;
    k ^= (uint64_t)(uint32_t)cell[1] * 0xC2B2AE3D27D4EB4FULL;
    k ^= (uint64_t)(uint32_t)cell[2] * 0x165667B19E3779F9ULL;
    k ^= k >> 29;
    return (uint32_t)k & mask;
}

/* Slab of x along the x axis for the slab width w: the same expression as cell_of,
 * nondecreasing in x, so that a slab above another holds only larger x. */
static int32_t slab_of(double x, double origin, double w) { return (int32_t)((x - origin) / w); }

/* Orders the segments by the slab of their box's low x (counting sort, stable: then
 * by index) into g->seg_order, for the sweep of the pair loop. Slabs are 1/16 of a
 * cell, widened while there would be more than 4 a segment (a slab of the extent
 * 2^-24 wide at worst: top - origin < 2^20 h); the width chosen goes to *width. */
static hk_Status order_segments(Grid *g, int n, double origin, double top, double h, double *width, hk_Error *err)
{
    double w = h / 16.0 > 0.0 ? h / 16.0 : h;
    size_t slabs = (size_t)slab_of(top, origin, w) + 1;
    while (slabs > 4 * (size_t)n + 1024) {
        w *= 2.0;
        slabs = (size_t)slab_of(top, origin, w) + 1;
    }
    if (slabs + 1 > g->slab_cap) {
        hk_free(g->slab_start);
        g->slab_start = hk_alloc_array(slabs + 1, sizeof(int), err);
        g->slab_cap = g->slab_start ? slabs + 1 : 0;
        if (!g->slab_start) return HK_ERR_NOMEM;
    }
    int *start = g->slab_start;
    memset(start, 0, (slabs + 1) * sizeof *start);
    for (int e = 0; e < n; e++) start[slab_of(g->lo[e].x, origin, w) + 1]++;
    for (size_t k = 0; k < slabs; k++) start[k + 1] += start[k];
    for (int e = 0; e < n; e++) {
        int32_t *slab = &g->seg_slab[2 * e];
        slab[0] = slab_of(g->lo[e].x, origin, w), slab[1] = slab_of(g->hi[e].x, origin, w);
        g->seg_order[start[slab[0]]++] = e;
    }
    *width = w;
    return HK_OK;
}

/* Cells covered by every box for the cell size h (as a double: it may be huge); the
 * cells of each box's corners go to g->seg_cells, for the last h tried. */
static double covered_cells(Grid *g, int n, hk_Vec3 origin, double h)
{
    double total = 0.0;
    /* (the axes written out: a loop over them with hk_v3_get took 82 instructions a
     * segment instead of 51) */
    for (int e = 0; e < n; e++) {
        int32_t *cells = &g->seg_cells[6 * e];
        const hk_Vec3 lo = g->lo[e], hi = g->hi[e];
        cells[0] = cell_of(lo.x, origin.x, h), cells[1] = cell_of(lo.y, origin.y, h);
        cells[2] = cell_of(lo.z, origin.z, h), cells[3] = cell_of(hi.x, origin.x, h);
        cells[4] = cell_of(hi.y, origin.y, h), cells[5] = cell_of(hi.z, origin.z, h);
        total +=
            (double)(cells[3] - cells[0] + 1) * (double)(cells[4] - cells[1] + 1) * (double)(cells[5] - cells[2] + 1);
    }
    return total;
}

/* partners[s]: the set (bit t for t) of the start bits t with s | t = 7, so that the
 * pair loop's first test, (s | t) == 7, is one AND with the other entry's 1 << t:
 * 3 instructions instead of 4. With the crowded buckets' sentinels, 6 instructions
 * an entry pair visited instead of 9 (5.04 million visits in 8 frames of
 * examples/guides200 shaking with the settling's: the pair loop's own 118.4 -> 93.9
 * million instructions). */
static const int partners[8] = {0x80, 0xC0, 0xA0, 0xF0, 0x88, 0xCC, 0xAA, 0xFF};

/* The boxes of two entries overlap, a's low corner given (low4, low2 of entry_low):
 * all combined without branches (see the pair loop). */
#ifdef __SSE2__
static int boxes_overlap(__m128 a_low4, __m128 a_low2, const Entry *b)
{
    /* SSE's own comparisons and the lanes' signs at once: b's first four coordinates
     * in one load (the entry is aligned to 32 bytes), its last two in the low half of
     * another whose high half is zero (a_low2's is -0, and -0 <= 0). */
    const __m128 high4 = _mm_load_ps(b->high);
    const __m128 high2 = _mm_castsi128_ps(_mm_loadl_epi64((const __m128i *)(const void *)&b->high[4]));
    return _mm_movemask_ps(_mm_and_ps(_mm_cmple_ps(a_low4, high4), _mm_cmple_ps(a_low2, high2))) == 15;
}
#else
static int boxes_overlap(const float a_low4[4], const float a_low2[2], const Entry *b)
{
    return (a_low4[0] <= b->high[0]) & (a_low4[1] <= b->high[1]) & (a_low4[2] <= b->high[2]) &
           (a_low4[3] <= b->high[3]) & (a_low2[0] <= b->high[4]) & (a_low2[1] <= b->high[5]);
}
#endif

/* Two segments (midpoints m, half-vectors h = (p1 - p0) / 2, lengths l) are apart by
 * at least the gap of their projections on any unit axis n, n.(m_x - m_y) - |n.h_x| -
 * |n.h_y| (a separating axis); beyond 2 d0 by such a bound they need not be measured.
 * First n along m_x - m_y with |n.h| <= l / 2, |m_x - m_y| - l_x / 2 - l_y / 2: reach
 * holds l / 2 + d0 grown by 1e-9 of itself, so that the bound's rounding cannot drop a
 * pair the measure would keep. Then the same n with |n.h| itself, the gap L / |m_x -
 * m_y| with L = |m_x - m_y|^2 - |(m_x - m_y).h_x| - |(m_x - m_y).h_y|: hair segments
 * side by side are nearly parallel and their offset nearly normal to both, so the
 * gap is nearly their distance (on examples/guides200 shaking, 62 % of the measures
 * that ended beyond 2 d0 are not made: 20,100 a rescan instead of 28,100, none of
 * those within 2 d0 lost; hk_hair_contacts_update 555.9 instead of 598.4 million
 * instructions in 8 frames and its settling, callgrind). L's rounding, a few ulps
 * of |m_x - m_y|^2 + |m_x - m_y| (l_x + l_y) / 2 <= 2 r^2 (r = reach_x + reach_y >=
 * |m_x - m_y| here), is taken off it a thousand times over (2e-12 r^2) and apart2 is
 * (2 d0)^2 grown by 4e-9 of itself, as reach is. */
static int surely_apart(const Grid *g, int x, int y, double apart2)
{
    const SegBound *bx = &g->bound[x], *by = &g->bound[y];
    const double r = bx->reach + by->reach;
    const hk_Vec3 dm = hk_v3_sub(bx->mid, by->mid);
    const double m2 = hk_v3_norm2(dm);
    const double l = m2 - fabs(hk_v3_dot(dm, bx->half)) - fabs(hk_v3_dot(dm, by->half)) - 2e-12 * (r * r);
    /* (both bounds always, combined without a branch: see the pair loop) */
    return (m2 > r * r) | ((l > 0.0) & (l * l > apart2 * m2));
}

/* Measures two segments of different strands whose boxes overlap and keeps them as a
 * candidate when they are closer than 2 d0. Returns 0 when out of memory. The lower
 * strand first and the candidate kept without a branch (the pair written, the count
 * advanced by d2 < band2): taken as branches, the order mispredicted 179,000 times in
 * 462,000 measures and the keeping 133,000 (cachegrind, examples/guides200 shaking, 23
 * rescans). GCC made swap ? y : x a branch again (175,000 mispredictions): the tags'
 * addresses are exchanged by a mask. The eligible segments are numbered strand by
 * strand, so of two strands' segments the lower strand's has the lower number. */
static int consider(const hk_HairContacts *c, const EntryTag *x, const EntryTag *y, double band2, Found *out)
{
    const Grid *g = c->grid;
    const uintptr_t swap = (uintptr_t)0 - (uintptr_t)(x->seg > y->seg);
    const uintptr_t flip = ((uintptr_t)x ^ (uintptr_t)y) & swap;
    const EntryTag *first = (const EntryTag *)((uintptr_t)x ^ flip), *second = (const EntryTag *)((uintptr_t)y ^ flip);
    hk_HcPair p = {g->seg_strand[first->seg],
                   g->bound[first->seg].index,
                   g->seg_strand[second->seg],
                   g->bound[second->seg].index,
                   0.0,
                   0.0,
                   0.0};
    /* (the same bits as hk_hc_pair_distance2: the ends are its) */
    p.d2 = hk_hc_ends_distance2(&g->ends[first->seg], &g->ends[second->seg], &p.u, &p.v);
    if (out->count >= out->cap) { /* room made by appending the pair, then taken back */
        if (!hk_hc_append_pairs(&out->pairs, &out->count, &out->cap, &p, 1, NULL)) return 0;
        out->count--;
    }
    out->pairs[out->count] = p;
    out->count += p.d2 < band2;
    return 1;
}

/* Marks which candidates of segment a of strand i are pairs: local minima in the
 * order (rank, a, b). Every neighbour closer than 2 d0 is a candidate, and one that is
 * not is farther than the candidate itself, so the neighbours are looked up among
 * the candidates of segments a - 1, a and a + 1, runs sorted by (j, b) that one
 * forward scan each goes through. Only a candidate in the last quantum of rank below
 * 2 d0, which could tie with a neighbour that is not a candidate, is measured again. */
static void mark_minima(const hk_HairContacts *c, int i, int a, const hk_HcMetric *m, long long band_rank,
                        unsigned char *is_min)
{
    const hk_HcStrand *si = &c->views[i];
    const hk_HcPair *cand = c->candidates;
    int begin, end;
    hk_hc_run(c, i, a, &begin, &end);
    int run_end[3], next[3];
    for (int r = 0; r < 3; r++) {
        const int na = a + r - 1;
        if (na < si->first || na > si->count - 2)
            next[r] = run_end[r] = 0;
        else
            hk_hc_run(c, i, na, &next[r], &run_end[r]);
    }
    for (int k = begin; k < end; k++) {
        const hk_HcPair *p = &cand[k];
        const long long rank = hk_hc_rank(p->d2, m->quantum);
        if (rank >= band_rank) {
            is_min[k] = (unsigned char)hk_hc_is_local_min(si, a, &c->views[p->j], p->b, p->d2, m);
            continue;
        }
        int min = 1;
        for (int r = 0; r < 3 && min; r++) {
            /* Skip what sorts before (j, b - 1): the runs and the candidates go up together. */
            while (next[r] < run_end[r] &&
                   (cand[next[r]].j < p->j || (cand[next[r]].j == p->j && cand[next[r]].b < p->b - 1)))
                next[r]++;
            const int na = a + r - 1;
            for (int x = next[r]; x < run_end[r]; x++) {
                const hk_HcPair *q = &cand[x];
                if (q->j != p->j || q->b > p->b + 1) break;
                if (na == a && q->b == p->b) continue; /* itself */
                const long long e = hk_hc_rank(q->d2, m->quantum);
                if (e < rank || (e == rank && (na < a || (na == a && q->b < p->b)))) {
                    min = 0;
                    break;
                }
            }
        }
        is_min[k] = (unsigned char)min;
    }
}

hk_Status hk_hc_broad_phase(hk_HairContacts *c, hk_Error *err)
{
    c->pair_count = 0;
    c->candidate_count = 0;
    if (!c->grid) {
        c->grid = hk_calloc_array(1, sizeof(Grid), err);
        if (!c->grid) return HK_ERR_NOMEM;
    }
    Grid *g = c->grid;
    const double d0 = c->p.distance, band2 = 4.0 * d0 * d0, apart2 = band2 * (1.0 + 4e-9);

    /* Boxes of the segments taking part, grown by d0 each: two segments closer than
     * 2 d0 have overlapping boxes. */
    long n_long = 0;
    for (int s = 0; s < c->strand_count; s++)
        if (c->views[s].first <= c->views[s].count - 2) n_long += c->views[s].count - 1 - c->views[s].first;
    if (n_long == 0) return HK_OK;
    const int n = (int)n_long; /* the update bounded the total number of segments */
    if (reserve_segments(g, n, err) != HK_OK) return HK_ERR_NOMEM;
    const hk_Vec3 grow = hk_v3(d0, d0, d0);
    /* Each strand's segments in parallel (from its first one's index), then the
     * extent and the sum of the box sides in segment order, as before. */
    const int threads = hk_hc_threads(c);
    if (g->strand_cap < c->strand_count + 1) {
        hk_free(g->strand_seg);
        g->strand_seg = hk_alloc_array((size_t)c->strand_count + 1, sizeof(int), err);
        g->strand_cap = g->strand_seg ? c->strand_count + 1 : 0;
        if (!g->strand_seg) return HK_ERR_NOMEM;
    }
    int *first_seg = g->strand_seg;
    first_seg[0] = 0;
    for (int s = 0; s < c->strand_count; s++) {
        const int segs = c->views[s].count - 1 - c->views[s].first;
        first_seg[s + 1] = first_seg[s] + (segs > 0 ? segs : 0);
    }
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int s = 0; s < c->strand_count; s++)
        for (int k = c->views[s].first, e = first_seg[s]; k <= c->views[s].count - 2; k++, e++) {
            hk_Vec3 p0, p1;
            double t0;
            hk_hc_segment_ends(&c->views[s], k, c->p.root_exclusion, &p0, &p1, &t0);
            hk_Vec3 lo = hk_v3(min2(p0.x, p1.x), min2(p0.y, p1.y), min2(p0.z, p1.z));
            hk_Vec3 hi = hk_v3(max2(p0.x, p1.x), max2(p0.y, p1.y), max2(p0.z, p1.z));
            g->seg_strand[e] = s;
            g->ends[e] = (hk_HcEnds){p0, p1, t0};
            SegBound *b = &g->bound[e];
            b->index = k;
            b->mid = hk_v3_scale(hk_v3_add(p0, p1), 0.5);
            b->half = hk_v3_scale(hk_v3_sub(p1, p0), 0.5);
            b->reach = (0.5 * hk_v3_dist(p0, p1) + d0) * (1.0 + 1e-9);
            g->lo[e] = hk_v3_sub(lo, grow), g->hi[e] = hk_v3_add(hi, grow);
        }
    hk_Vec3 gmin = hk_v3(HUGE_VAL, HUGE_VAL, HUGE_VAL), gmax = hk_v3_neg(gmin);
    double side_sum = 0.0;
    int e = 0;
    for (e = 0; e < n; e++) {
        gmin = hk_v3(min2(gmin.x, g->lo[e].x), min2(gmin.y, g->lo[e].y), min2(gmin.z, g->lo[e].z));
        gmax = hk_v3(max2(gmax.x, g->hi[e].x), max2(gmax.y, g->hi[e].y), max2(gmax.z, g->hi[e].z));
        hk_Vec3 side = hk_v3_sub(g->hi[e], g->lo[e]);
        side_sum += max2(side.x, max2(side.y, side.z));
    }
    const hk_Vec3 extent = hk_v3_sub(gmax, gmin);
    const double max_extent = fmax(extent.x, fmax(extent.y, extent.z));
    if (!isfinite(max_extent) || !isfinite(side_sum))
        return hk_error_set(
            err, HK_ERR_INVALID,
            "hair contacts: strand positions (grown by the contact distance) span more than the range of doubles");

    /* Cell size: 1.5 times the mean box side, so that a typical segment covers up to 8
     * cells (on examples/guides200, 1.5 times gave 27,000 entries for 7,200 segments
     * against 41,000 with the mean side, and a pair loop a little faster: 4.5 against
     * 5.2 ms for the entries and the loop, 1 thread);
     * at least the extent / 2^20 so that cell coordinates fit; doubled while long
     * segments would make the entries more than 8 per segment on average. */
    double h = fmax(1.5 * side_sum / n, max_extent / 1048576.0);
    double entries_d = covered_cells(g, n, gmin, h);
    for (int tries = 0; tries < 64 && entries_d > 8.0 * n + 1024.0; tries++) {
        h *= 2.0;
        entries_d = covered_cells(g, n, gmin, h);
    }
    if (entries_d > 8.0 * n + 1024.0) /* cannot happen: h >= every box side gives <= 8 */
        return hk_error_set(err, HK_ERR_NUMERIC, "hair contacts: no usable grid for the broad phase");
    const size_t entries = (size_t)entries_d;
    /* Buckets: half the entries at least. The entries crowd into far fewer cells, and
     * the sweep meets another cell's entries only when in the same x slabs: 16,384
     * buckets for 27,000 entries gave the same pair loop as 65,536 (examples/guides200
     * shaking), for less clearing and scanning of the table (hk_hair_contacts_update
     * 204.5 against 211.1 million instructions, 8 frames). */
    size_t table = 1024;
    while (2 * table < entries) table *= 2;
    if (reserve_entries(g, entries, table, err) != HK_OK) return HK_ERR_NOMEM;

    /* The entries, segment by segment: each segment's count, then (in parallel, each
     * segment into its own places) the cells it covers. */
    g->seg_entry[0] = 0;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int s = 0; s < n; s++) {
        const int32_t *cells = &g->seg_cells[6 * s];
        g->seg_entry[s + 1] =
            (size_t)(cells[3] - cells[0] + 1) * (size_t)(cells[4] - cells[1] + 1) * (size_t)(cells[5] - cells[2] + 1);
    }
    for (e = 0; e < n; e++) g->seg_entry[e + 1] += g->seg_entry[e];
    const size_t m = g->seg_entry[n];
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int s = 0; s < n; s++) {
        const int32_t *lo = &g->seg_cells[6 * s], *hi = lo + 3;
        size_t at = g->seg_entry[s];
        for (int32_t x = lo[0]; x <= hi[0]; x++)
            for (int32_t y = lo[1]; y <= hi[1]; y++)
                for (int32_t z = lo[2]; z <= hi[2]; z++, at++) {
                    /* (the bucket, and whether the box starts in the cell along x) */
                    const int32_t cell[3] = {x, y, z};
                    g->entry_bucket[at] = bucket_of(cell, (uint32_t)(table - 1)) << 1 | (uint32_t)(x == lo[0]);
                }
    }
    /* Counting sort of the entries by bucket and, within a bucket, by whether their
     * box starts in their cell along x (after those that do not), stable; start[2 b
     * + 1] ends as the end of bucket b. The places are dealt in order, then the
     * entries written to them in parallel. */
    double slab;
    if (order_segments(g, n, gmin.x, gmax.x, h, &slab, err) != HK_OK) return HK_ERR_NOMEM;
    size_t *start = g->bucket_start;
    memset(start, 0, 2 * table * sizeof *start);
    for (size_t k = 0; k < m; k++) start[g->entry_bucket[k]]++;
    /* (and the buckets where the pair loop has work, listed: it went through every
     * bucket, then 65,536 for 27,000 entries, ~10 instructions each: two entries or
     * more, one of them starting along x). Each run of such a bucket ends with a
     * sentinel, an entry of low x slab INT32_MAX, which stops the pair loop's sweeps
     * without a test of the run's end: 2 of the 9 instructions an entry pair
     * visited. */
    long crowded = 0;
    size_t next = 0, most = 0; /* most: the largest bucket */
    for (size_t k = 0; k < table; k++) {
        const size_t behind = start[2 * k], starting = start[2 * k + 1], count = behind + starting;
        const int work = count >= 2 && starting >= 1;
        most = count > most ? count : most;
        start[2 * k] = next, next += behind;
        if (work) g->crowded[2 * crowded] = (uint32_t)start[2 * k], g->sorted[next++].x_lo = INT32_MAX;
        start[2 * k + 1] = next, next += starting;
        if (work) g->crowded[2 * crowded++ + 1] = (uint32_t)start[2 * k + 1], g->sorted[next++].x_lo = INT32_MAX;
    }
    /* The segments taken by their low x: each bucket then holds its entries in
     * nondecreasing slabs of low x, for the pair loop's sweep. */
    for (int q = 0; q < n; q++) {
        const int s = g->seg_order[q];
        for (size_t k = g->seg_entry[s]; k < g->seg_entry[s + 1]; k++) g->place[k] = (int)start[g->entry_bucket[k]]++;
    }
    /* Each segment's entries written to their places (in parallel, each place
     * written once): the box, strand and slabs set up once a segment, the cells and
     * start bits from the cells' loop. They were gathered place by place before,
     * each entry reading its cell, segment, box and corners back from arrays: 74
     * instructions an entry, 42.1 million in 8 frames of examples/guides200 shaking
     * with the settling's (23 rescans), and 22.1 for the cells' listing; now 52 an
     * entry with its segment's share, 29.8 and 16.9 million. */
#pragma omp parallel for schedule(static) num_threads(threads)
    for (int s = 0; s < n; s++) {
        /* (the corners' cells as locals: the entries written could alias them) */
        const int32_t *cells = &g->seg_cells[6 * s];
        const int32_t x0 = cells[0], y0 = cells[1], z0 = cells[2], y1 = cells[4], z1 = cells[5];
        const hk_Vec3 lo = g->lo[s], hi = g->hi[s];
        Entry proto;
        proto.high[0] = (float)hi.x, proto.high[1] = (float)hi.y, proto.high[2] = (float)hi.z;
        proto.high[3] = (float)-lo.x, proto.high[4] = (float)-lo.y, proto.high[5] = (float)-lo.z;
        proto.x_lo = g->seg_slab[2 * s];
        const uint32_t strand_key = (uint32_t)g->seg_strand[s] << 8; /* (strands < 2^24: hair_contacts.c) */
        const int32_t x_hi = g->seg_slab[2 * s + 1];
        /* (one loop over the cells, z fastest as in the count: a box is often one
         * cell thick, and three nested loops cost more in their bounds than the
         * entries' writes) */
        int32_t x = x0, y = y0, z = z0;
        int starts = 7; /* the start bits of (x, y, z), kept along */
        for (size_t at = g->seg_entry[s]; at < g->seg_entry[s + 1]; at++) {
            const int place = g->place[at];
            Entry *en = &g->sorted[place];
            *en = proto;
            en->key = strand_key | 1u << starts;
            g->tags[place] = (EntryTag){cell_key(x, y, z), s, x_hi};
            if (z < z1) {
                z++, starts &= 3;
            } else if (y < y1) {
                z = z0, y++, starts = (starts & 1) | 4;
            } else {
                z = z0, y = y0, x++, starts = 6;
            }
        }
    }

    /* Pairs of entries sharing a cell, buckets in parallel: each thread keeps its own
     * candidates; they are sorted into one order afterwards, so what a thread found
     * does not matter, only what all found. A sweep from one entry meets fewer than
     * `most` others, so a list of passed pairs flushed when `most` might not fit
     * holds every sweep. */
    const size_t passed_cap = 2 * most + 1024;
    if (reserve_threads(g, threads, passed_cap, err) != HK_OK) return HK_ERR_NOMEM;
    for (int t = 0; t < threads; t++) g->found[t].count = 0;
    int failed = 0;
    long evaluations = 0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : evaluations) reduction(| : failed) num_threads(threads)
    for (long q = 0; q < crowded; q++) {
        Found *out = &g->found[omp_get_thread_num()];
        uint64_t *passed = out->passed;
        size_t count = 0;
        /* A bucket's two runs: the entries whose box starts before their cell along
         * x, then those starting in it. Two entries of the first run never pass the
         * start bits' test (neither starts in the cell along x) and are not visited:
         * a sweep from the first run goes through the second, one from the second
         * through the rest of it (954,000 of the 5.04 million entry pairs visited
         * before in 23 rescans of examples/guides200 shaking). */
        const Entry *const starting = g->sorted + g->crowded[2 * q + 1];
        for (const Entry *ex = g->sorted + g->crowded[2 * q]; ex->x_lo != INT32_MAX || ex + 1 == starting; ex++) {
            if (ex + 1 == starting) continue; /* the first run's end */
            /* Sweep: the entries after x in its run, or those of the second run, have
             * no lower low x slab than x in its cell, and once above x's high x slab
             * their boxes start beyond x's (slab_of is nondecreasing) and none
             * overlaps it. It visits 218,000 entry pairs a step instead of all
             * 316,000 sharing a bucket (examples/guides200 shaking). x's own fields
             * are read once (the compiler reloads them otherwise, as the list written
             * may alias them). */
            const Entry *const first_y = ex < starting ? starting : ex + 1;
            const uint64_t x_place = (uint64_t)(ex - g->sorted);
            const int32_t x_hi = g->tags[x_place].x_hi;
            const uint32_t x_key = ex->key;
            /* (the start bits s of x: its key's lowest bit set is 1 << s) */
            const uint32_t x_partners = (uint32_t)partners[__builtin_ctz(x_key)], x_strand = x_key >> 8;
#ifdef __SSE2__
            __m128 low4, low2;
            entry_low(ex, &low4, &low2);
#else
            float low4[4], low2[2];
            entry_low(ex, low4, low2);
#endif
            /* the pair (x, y) as the list keeps it */
            uint64_t xy = x_place << 32 | (uint64_t)(first_y - g->sorted);
            for (const Entry *ey = first_y; ey->x_lo <= x_hi; ey++, xy++) {
                /* Two segments are measured in one of the cells both boxes cover only:
                 * the one holding the low corner of their overlap, whose cell is the
                 * larger of their low cells on each axis, i.e. (both boxes covering the
                 * cell) the cell where one of the boxes starts, on every axis. Then boxes
                 * that overlap and not a self-contact (out of scope); not a hash
                 * collision (the same cell, 0.3 % of the pairs visited) is tested on the
                 * list. Every entry pair is written to the list and kept (the count
                 * advanced) when it passes the three tests, without a branch: one pair
                 * visited in five passes, and the tests taken one by one as branches
                 * mispredicted 2.4 million times in 5.04 million entry pairs (23
                 * rescans of examples/guides200 shaking, cachegrind), which cost more
                 * time than making every test for every pair (18 more instructions a
                 * pair visited; the broad phase's thread time 5.40 against 5.81 ms a
                 * rescan with the tests as branches, ten alternated runs). */
                const uint32_t y_key = ey->key;
                const int pass = ((y_key & x_partners) != 0) & boxes_overlap(low4, low2, ey) & (x_strand != y_key >> 8);
                passed[count] = xy;
                count += (size_t)pass;
            }
            if (count + most > passed_cap || ex[1].x_lo == INT32_MAX) {
                /* The passed pairs in their order: those surely apart dropped from the
                 * list (again without a branch), then the rest measured. (a tighter
                 * bound, the gap of the two segments' own boxes, dropped 4,000 more of
                 * the 31,000 pairs left here a step, but cost more than the measures
                 * it saved: 7.6 million instructions in 8 frames; surely_apart's
                 * second axis drops 8,000 of the 28,100 measured a step, for 42
                 * million fewer instructions in 8 frames) */
                size_t near = 0;
                for (size_t k = 0; k < count; k++) {
                    const uint64_t pair = passed[k];
                    const EntryTag *x = &g->tags[pair >> 32], *y = &g->tags[(uint32_t)pair];
                    passed[near] = pair;
                    near += (size_t)((x->cell == y->cell) & !surely_apart(g, x->seg, y->seg, apart2));
                }
                evaluations += (long)near;
                for (size_t k = 0; k < near && !failed; k++)
                    if (!consider(c, &g->tags[passed[k] >> 32], &g->tags[(uint32_t)passed[k]], band2, out)) failed = 1;
                count = 0;
            }
            if (failed) break;
        }
    }
    c->distance_evaluations += evaluations;
    if (failed) return hk_error_set(err, HK_ERR_NOMEM, "hair contacts: out of memory in the broad phase");
    /* The first thread's candidates take the place of c->candidates (empty) instead
     * of a copy, the others' are appended: the same order (15.6 million instructions
     * of memcpy in 8 frames of examples/guides200 shaking on one thread). */
    hk_HcPair *const emptied = c->candidates;
    const int emptied_cap = c->candidate_cap;
    c->candidates = g->found[0].pairs, c->candidate_count = g->found[0].count, c->candidate_cap = g->found[0].cap;
    g->found[0].pairs = emptied, g->found[0].count = 0, g->found[0].cap = emptied_cap;
    for (int t = 1; t < threads; t++)
        if (!hk_hc_append_pairs(&c->candidates, &c->candidate_count, &c->candidate_cap, g->found[t].pairs,
                                g->found[t].count, err))
            return HK_ERR_NOMEM;

    /* Pairs: the candidates that are local minima, found by looking their neighbours
     * up among the candidates (sorted, so the pairs come out sorted too). */
    hk_Status st = hk_hc_sort(c, &c->candidates, &c->candidate_cap, c->candidate_count, err);
    if (st != HK_OK) return st;
    if (c->p.along) {
        /* Per segment a of strand i and strand j, the closest of its candidates (the
         * smallest b among equals): runs of (i, a, j) are consecutive in sorted order. */
        for (int k = 0; k < c->candidate_count;) {
            const hk_HcPair *first = &c->candidates[k];
            int best = k, end = k + 1;
            while (end < c->candidate_count && c->candidates[end].i == first->i && c->candidates[end].a == first->a &&
                   c->candidates[end].j == first->j) {
                if (c->candidates[end].d2 < c->candidates[best].d2) best = end;
                end++;
            }
            if (!hk_hc_push_pair(&c->pairs, &c->pair_count, &c->pair_cap, &c->candidates[best], err))
                return HK_ERR_NOMEM;
            k = end;
        }
        return HK_OK;
    }
    if (c->candidate_count > g->flag_cap) {
        hk_free(g->is_min);
        g->is_min = hk_alloc_array((size_t)c->candidate_count, 1, err);
        g->flag_cap = g->is_min ? c->candidate_count : 0;
        if (!g->is_min) return HK_ERR_NOMEM;
    }
    const hk_HcMetric metric = hk_hc_metric(&c->p);
    const long long band_rank = hk_hc_rank(band2, metric.quantum);
    const int count = c->candidate_count;
    const int strands = c->strand_count;
#pragma omp parallel for schedule(dynamic, 8) num_threads(threads)
    for (int i = 0; i < strands; i++)
        for (int a = c->views[i].first; a <= c->views[i].count - 2; a++)
            mark_minima(c, i, a, &metric, band_rank, g->is_min);
    for (int k = 0; k < count; k++)
        if (g->is_min[k] && !hk_hc_push_pair(&c->pairs, &c->pair_count, &c->pair_cap, &c->candidates[k], err))
            return HK_ERR_NOMEM;
    return HK_OK;
}
