/* The hair of one tile of the picture, with exact transparency: every fragment of the
 * tile's segments in front of the head is kept, each pixel's fragments are sorted by
 * depth and composited front to back (an A-buffer).
 *
 * Early saturation keeps this fast without changing the result beyond a bound: the
 * tile's segments are drawn nearest first (by the depth of their nearer end), so when
 * a segment of nearest depth D begins, no later fragment can lie in front of D. The
 * fragments in front of D are then final; once their transmittance in a pixel drops
 * below 1/1024, that pixel takes no more fragments: anything behind could change it
 * by less than 1/1024 of the brightest hair, a quarter of an 8-bit step. */
#include <stdlib.h>
#include <string.h>

#include "raster_inline.h"
#include "render_internal.h"

#define NPX          (HK_TILE * HK_TILE)
#define SATURATED    (1.0f / 1024.0f)
#define SETTLE_BATCH 64 /* segments between two saturation checks */

/* Each pixel keeps its fragments in drawing order in chunks of FRAG_CHUNK, side by
 * side in a pool of the tile, and those not final yet in a block of a second pool
 * (moved to a block twice as large when full: the old one is left until the next
 * tile). Settling reads a pixel's pending block, a few cache lines: walked as a list
 * through the tile's fragments, every step waited on memory, and settling takes 3.5
 * steps a fragment (38.8 million for f5's 11.0 million fragments, a pending fragment
 * being walked again until it is final). Compositing reads a pixel's chunks: sorted by
 * pixel from the tile's array of fragments, each fragment was read once in order and
 * stored far away twice (its key, its colour). Chunks, not blocks that double: copying
 * the blocks was 2.8 % of a picture's time (perf). */
#define FRAG_CHUNK 16
typedef struct Fragment {
    float z, a, r, g, b;
} Fragment;
typedef struct Pending {
    float z, a;
} Pending;
typedef struct Pixel {
    uint32_t frag_count, frag_first, frag_last;         /* chunks: pool positions */
    uint32_t pend_at, pend_first, pend_count, pend_cap; /* pend[at + first .. at + count) */
    float near;                                         /* nearest pending fragment (+inf: none) */
    float through;                                      /* light through the final fragments */
} Pixel;

/* The segment being drawn. */
typedef struct Segment {
    hk_RasterPoint a, b;
    uint32_t first;     /* index of its first point */
    float ca[3], cb[3]; /* colours, fetched at its first fragment kept */
} Segment;

struct hk_TileHair {
    hk_Rect r;
    const hk_TileBase *head;
    const hk_HairFile *hair;
    /* The tile's segments in depth order. Only their first points and nearer depths
     * (in the bins) are read to sort them: on a full head two thirds of a tile's
     * segments lie behind pixels that are all opaque by the time their turn comes, and
     * the rest is read when a segment is drawn. */
    uint32_t *order, *sort_work;
    size_t seg_cap;
    Segment segment;
    Segment *current;
    int coloured; /* whether current's colours are fetched */
    hk_HairShader *shader;
    float lod; /* the level of detail's k (1: every strand drawn) */
    /* fragments */
    Pixel pixel[NPX];
    Fragment *frag;
    uint32_t *chunk_next; /* chunk at FRAG_CHUNK * c: position of the pixel's next chunk */
    Pending *pend;
    size_t frag_used, frag_cap, pend_used, pend_cap;
    size_t count;
    int failed;
    uint64_t *keys, *keys_tmp; /* a pixel's, for sorting */
    size_t keys_cap;
    /* saturation */
    uint8_t saturated[NPX], touched[NPX];
    uint16_t touched_list[NPX];
    int touched_count;
    /* Saturation per row too: bit x of open_row[y] is set while pixel (x, y) of the
     * tile takes fragments. A segment whose box covers no open pixel is not drawn (on
     * a full head half the segments drawn kept no fragment when this was tracked per
     * block of 8 x 8 pixels); open counts the open pixels. */
    uint32_t open_row[HK_TILE];
    int open;
    /* pixels behind the head: closed once the segments start behind it */
    uint64_t head_order[NPX]; /* cutoff depth bits above the pixel, increasing */
    uint64_t head_tmp[NPX];
    int head_count, head_next;
};

hk_TileHair *hk_tile_hair_create(void) { return calloc(1, sizeof(hk_TileHair)); }

void hk_tile_hair_destroy(hk_TileHair *w)
{
    if (!w) return;
    free(w->order);
    free(w->sort_work);
    free(w->frag);
    free(w->chunk_next);
    free(w->pend);
    free(w->keys);
    free(w->keys_tmp);
    free(w);
}

static int reserve_segments(hk_TileHair *w, size_t n)
{
    if (n <= w->seg_cap) return 1;
    size_t cap = n + n / 2 + 64;
    uint32_t *o = realloc(w->order, cap * sizeof *o);
    if (o) w->order = o;
    uint32_t *sw = realloc(w->sort_work, 3 * cap * sizeof *sw);
    if (sw) w->sort_work = sw;
    if (!o || !sw) return 0;
    w->seg_cap = cap;
    return 1;
}

/* A new chunk for pixel px's fragments; 0 when out of memory. */
static __attribute__((noinline)) int new_chunk(hk_TileHair *w, Pixel *px)
{
    if (w->frag_used + FRAG_CHUNK > w->frag_cap) {
        size_t cap = w->frag_cap;
        Fragment *f = hk_grow_fragments(w->frag, &cap, sizeof *f); /* a multiple of FRAG_CHUNK */
        if (!f) return 0;
        w->frag = f;
        uint32_t *next = realloc(w->chunk_next, cap / FRAG_CHUNK * sizeof *next);
        if (!next) return 0;
        w->chunk_next = next, w->frag_cap = cap;
    }
    if (w->frag_used + FRAG_CHUNK > UINT32_MAX) return 0;
    const uint32_t at = (uint32_t)w->frag_used;
    w->frag_used += FRAG_CHUNK;
    if (px->frag_count)
        w->chunk_next[px->frag_last / FRAG_CHUNK] = at;
    else
        px->frag_first = at;
    px->frag_last = at;
    return 1;
}

/* Pixel px's pending block full: its fragments moved to its start if they do not
 * begin there, else to a new block twice as large at the end of the pool; 0 when out
 * of memory. */
static __attribute__((noinline)) int grow_pending(hk_TileHair *w, Pixel *px)
{
    const uint32_t n = px->pend_count - px->pend_first;
    if (px->pend_first) { /* (then the pool exists: w->pend may be NULL before a first block) */
        const Pending *from = w->pend + px->pend_at + px->pend_first;
        for (uint32_t i = 0; i < n; i++) w->pend[px->pend_at + i] = from[i]; /* a few: no call */
        px->pend_first = 0, px->pend_count = n;
        return 1;
    }
    const uint32_t room = px->pend_cap ? 2 * px->pend_cap : 8;
    while (w->pend_used + room > w->pend_cap) {
        Pending *grown = hk_grow_fragments(w->pend, &w->pend_cap, sizeof *grown);
        if (!grown) return 0;
        w->pend = grown;
    }
    if (w->pend_used + room > UINT32_MAX) return 0;
    if (n) memcpy(w->pend + w->pend_used, w->pend + px->pend_at, n * sizeof *w->pend);
    px->pend_at = (uint32_t)w->pend_used, px->pend_cap = room;
    w->pend_used += room;
    return 1;
}

/* The colours of the segment being drawn, at its first fragment kept: half the segments
 * drawn in a full head's tiles keep none (they fall on opaque pixels or behind the
 * head), and shading their ends was a tenth of a picture. */
static __attribute__((noinline)) void fetch_colours(hk_TileHair *w)
{
    hk_hair_shader_get(w->shader, w->current->first, w->current->ca);
    hk_hair_shader_get(w->shader, w->current->first + 1, w->current->cb);
    w->coloured = 1;
}

/* A strand drawn for k (the level of detail, k times as wide: alpha the coverage of
 * all k) lets through what the k it stands for would, one behind the other:
 * 1 - alpha' = (1 - alpha / k)^k, rather than 1 - alpha (which made the hair of a
 * thumbnail more opaque than drawn in full: 0.75 % darker on average in
 * test_render's sheet of 20,000 strands). The light's maps add opacities and need
 * no such change. */
static __attribute__((noinline)) void lod_alpha(float *alpha, float k)
{
    const float a = *alpha > 1.0f ? 1.0f : *alpha;
    *alpha = 1.0f - powf(1.0f - a / k, k);
}

HK_FRAGMENT_INLINE void hair_fragment(void *user, int x, int y, float t, float alpha)
{
    hk_TileHair *w = user;
    const uint32_t p = (uint32_t)((y - w->r.y0) * HK_TILE + (x - w->r.x0));
    if (w->saturated[p]) return;
    const Segment *s = w->current;
    const float z = 1.0f / ((1.0f - t) / s->a.z + t / s->b.z); /* perspective-correct */
    if (z >= w->head->cutoff[p]) return;
    Pixel *px = &w->pixel[p];
    if ((px->frag_count % FRAG_CHUNK == 0 && !new_chunk(w, px)) ||
        (px->pend_count == px->pend_cap && !grow_pending(w, px))) {
        w->failed = 1;
        return;
    }
    if (!w->coloured) fetch_colours(w);
    const hk_HairFile *h = w->hair;
    if (h->transparency) alpha *= 1.0f - ((1.0f - t) * h->transparency[s->first] + t * h->transparency[s->first + 1]);
    if (w->lod > 1.0f) lod_alpha(&alpha, w->lod);
    Fragment *f = &w->frag[px->frag_last + px->frag_count++ % FRAG_CHUNK];
    f->z = z, f->a = alpha > 1.0f ? 1.0f : alpha;
    f->r = s->ca[0] + t * (s->cb[0] - s->ca[0]);
    f->g = s->ca[1] + t * (s->cb[1] - s->ca[1]);
    f->b = s->ca[2] + t * (s->cb[2] - s->ca[2]);
    Pending *q = &w->pend[px->pend_at + px->pend_count++];
    q->z = z, q->a = f->a;
    w->count++;
    if (z < px->near) px->near = z;
    if (!w->touched[p]) w->touched[p] = 1, w->touched_list[w->touched_count++] = (uint16_t)p;
}

static void close_pixel(hk_TileHair *w, int p)
{
    if (w->saturated[p]) return;
    w->saturated[p] = 1;
    w->open_row[p / HK_TILE] &= ~(1u << (p % HK_TILE));
    w->open--;
}

/* Fragments in front of `front` are final: fold them into their pixel's
 * transmittance and close the pixels that no longer let light through. */
static void settle(hk_TileHair *w, float front)
{
    /* No later fragment can be in front of the head where the head is nearer than
     * `front`. */
    while (w->head_next < w->head_count) {
        const uint64_t h = w->head_order[w->head_next];
        float cutoff;
        const uint32_t bits = (uint32_t)(h >> 32);
        memcpy(&cutoff, &bits, sizeof cutoff);
        if (cutoff > front) break;
        close_pixel(w, (int)(h & 0xffffu));
        w->head_next++;
    }
    uint32_t front_bits, inf_bits;
    const float inf = HUGE_VALF;
    memcpy(&front_bits, &front, sizeof front_bits);
    memcpy(&inf_bits, &inf, sizeof inf_bits);
    for (int k = 0; k < w->touched_count; k++) {
        const int p = w->touched_list[k];
        w->touched[p] = 0;
        /* Nothing to fold: walking the pixel's pending fragments would change
         * nothing. */
        Pixel *px = &w->pixel[p];
        if (px->near > front) continue;
        Pending *v = w->pend + px->pend_at;
        /* Newest first: the products in the order of before (a list pushed at its
         * head), so that the same pixels close at the same fragments; those that
         * stay move up, in order, to end the block. Without branches (which fragments
         * are final is a coin toss; the compiler made branches of conditional
         * expressions), on the depths' bits (positive: they order as integers): a
         * fragment that stays multiplies by 1 - 0, which changes no bit, and one that
         * is final offers all ones, above +inf's bits, as the nearest. */
        float through = px->through;
        uint32_t nearest = inf_bits, top = px->pend_count;
        for (uint32_t i = px->pend_count; i-- > px->pend_first;) {
            uint32_t z, a_bits;
            memcpy(&z, &v[i].z, sizeof z);
            memcpy(&a_bits, &v[i].a, sizeof a_bits);
            const uint32_t final = -(uint32_t)(z <= front_bits);
            a_bits &= final;
            float a;
            memcpy(&a, &a_bits, sizeof a);
            through *= 1.0f - a;
            nearest = (z | final) < nearest ? z | final : nearest;
            v[top - 1] = v[i], top -= 1 + final;
        }
        /* None left: the block is empty from its start (no moving when it fills). */
        if (top == px->pend_count) top = px->pend_count = 0;
        px->through = through, px->pend_first = top;
        memcpy(&px->near, &nearest, sizeof nearest);
        if (through < SATURATED) close_pixel(w, p);
    }
    w->touched_count = 0;
}

/* Whether every pixel of the tile under a segment's box (the bins' box, which touches
 * the tile) is saturated: then the rasteriser would pass over all of them. */
static int hidden(const hk_TileHair *w, hk_TileBox b)
{
    const int x0 = b.x0 > w->r.x0 ? b.x0 - w->r.x0 : 0, y0 = b.y0 > w->r.y0 ? b.y0 - w->r.y0 : 0;
    const int x1 = (b.x1 < w->r.x1 ? b.x1 : w->r.x1) - w->r.x0, y1 = (b.y1 < w->r.y1 ? b.y1 : w->r.y1) - w->r.y0;
    /* bits x0 .. x1 - 1 (x1 - x0 is 1 to 32) */
    const uint32_t columns = (UINT32_MAX >> (HK_TILE - (x1 - x0))) << x0;
    for (int y = y0; y < y1; y++)
        if (w->open_row[y] & columns) return 0;
    return 1;
}

/* Sorts each pixel's fragments by depth (ties by drawing order) and composites them
 * front to back over the head or background. */
static int composite(hk_TileHair *w, hk_Canvas *image)
{
    uint32_t most = 0;
    for (int p = 0; p < NPX; p++)
        if (w->pixel[p].frag_count > most) most = w->pixel[p].frag_count;
    if (most > w->keys_cap) {
        uint64_t *k = realloc(w->keys, most * sizeof *k);
        if (k) w->keys = k;
        uint64_t *t = realloc(w->keys_tmp, most * sizeof *t);
        if (t) w->keys_tmp = t;
        if (!k || !t) {
            w->failed = 1;
            return (int)most;
        }
        w->keys_cap = most;
    }
    for (int y = w->r.y0; y < w->r.y1; y++)
        for (int x = w->r.x0; x < w->r.x1; x++) {
            const int p = (y - w->r.y0) * HK_TILE + (x - w->r.x0);
            const uint32_t n = w->pixel[p].frag_count;
            /* key = depth bits (positive floats order as integers) above the position in
             * the pool, which increases in drawing order (a pixel's chunks are taken in
             * turn), so that equal depths keep it. */
            uint64_t *k = w->keys;
            for (uint32_t i = 0, c = w->pixel[p].frag_first; i < n;) {
                const uint32_t end = n - i > FRAG_CHUNK ? i + FRAG_CHUNK : n;
                for (uint32_t at = c; i < end; i++, at++) {
                    uint32_t bits;
                    memcpy(&bits, &w->frag[at].z, sizeof bits);
                    k[i] = ((uint64_t)bits << 32) | (uint64_t)at;
                }
                if (i < n) c = w->chunk_next[c / FRAG_CHUNK];
            }
            /* The segments were drawn nearest first, so a pixel's fragments come nearly
             * in depth order: insertion sort, unless it moves them too often. */
            if (!hk_sort_nearly_sorted(k, n, n <= 64 ? SIZE_MAX : 8 * (size_t)n))
                hk_sort_by_high_bits(k, n, w->keys_tmp); /* places in increasing order */
            float cr = 0.0f, cg = 0.0f, cb = 0.0f, through = 1.0f;
            for (uint32_t i = 0; i < n && through > 1e-4f; i++) {
                const Fragment *f = &w->frag[k[i] & 0xffffffffu];
                const float a = f->a;
                cr += through * a * f->r, cg += through * a * f->g, cb += through * a * f->b;
                through *= 1.0f - a;
            }
            float *o = image->rgb + 3 * ((size_t)y * (size_t)image->width + (size_t)x);
            o[0] = cr + through * w->head->base[p][0];
            o[1] = cg + through * w->head->base[p][1];
            o[2] = cb + through * w->head->base[p][2];
        }
    return (int)most;
}

static float segment_width(const hk_Scene *sc, const Segment *s)
{
    return (float)(0.5 * (hk_hair_thickness_at(sc, s->first) * s->a.px_per_unit +
                          hk_hair_thickness_at(sc, s->first + 1) * s->b.px_per_unit));
}

int hk_tile_hair(hk_TileHair *w, const hk_TileInput *in, int tile, const hk_TileBase *head, hk_Canvas *image,
                 long long *fragments, int *most)
{
    const hk_Scene *sc = in->scene;
    const hk_TileBins *bins = in->hair_bins;
    w->r = hk_tile_rect(bins, tile, sc->opt->width, sc->opt->height);
    w->head = head, w->hair = sc->hair, w->shader = in->shader;
    w->lod = (float)sc->thickness_scale;
    w->count = 0, w->failed = 0, w->touched_count = 0, w->frag_used = 0, w->pend_used = 0;
    for (int p = 0; p < NPX; p++) {
        w->pixel[p] = (Pixel){0, 0, 0, 0, 0, 0, 0, HUGE_VALF, 1.0f};
        w->saturated[p] = 0, w->touched[p] = 0;
    }
    for (int y = 0; y < HK_TILE; y++)
        w->open_row[y] = y < w->r.y1 - w->r.y0 ? UINT32_MAX >> (HK_TILE - (w->r.x1 - w->r.x0)) : 0;
    w->open = (w->r.x1 - w->r.x0) * (w->r.y1 - w->r.y0);
    w->head_count = w->head_next = 0;
    for (int y = w->r.y0; y < w->r.y1; y++)
        for (int x = w->r.x0; x < w->r.x1; x++) {
            const int p = (y - w->r.y0) * HK_TILE + (x - w->r.x0);
            uint32_t bits;
            memcpy(&bits, &head->cutoff[p], sizeof bits);
            if (head->cutoff[p] < 3.0e38f) w->head_order[w->head_count++] = ((uint64_t)bits << 32) | (uint64_t)p;
        }
    hk_sort_by_high_bits(w->head_order, (uint32_t)w->head_count, w->head_tmp); /* p was increasing */
    /* The tile's segments sorted by their nearer depths. */
    const uint32_t n = bins->start[tile + 1] - bins->start[tile];
    if (!reserve_segments(w, n)) return 0;
    /* The order holds the segments themselves, and the keys their depths: no lookup
     * of a tile's entry through its place in the order (a cache miss a segment). The
     * keys are the nearer depths' bits (positive: hk_segment_box draws no segment with
     * an end at or behind the eye). */
    hk_DepthOrder depth;
    hk_depth_order_begin(&depth, n, bins->keys + bins->start[tile], bins->items + bins->start[tile], w->order,
                         w->sort_work);
    Segment *s = &w->segment;
    for (uint32_t k = 0; k < n && !w->failed; k++) {
        if (k + 9 > depth.sorted) hk_depth_order_ready(&depth, k + 9); /* this one and the one fetched ahead */
        const uint32_t i = w->order[k];
        /* Depth order scatters the reads over the segments: fetch ahead. */
        if (k + 8 < n) {
            const uint32_t ahead = w->order[k + 8];
            __builtin_prefetch(&in->hair_proj[ahead]);
            __builtin_prefetch(&in->hair_proj[ahead + 1]);
            __builtin_prefetch(&bins->boxes[ahead]);
        }
        if (k % SETTLE_BATCH == 0) {
            float front;
            memcpy(&front, &depth.keys[k], sizeof front);
            settle(w, front);
            if (w->open == 0) break; /* every pixel of the tile is saturated */
        }
        if (hidden(w, bins->boxes[i])) continue;
        s->a = in->hair_proj[i], s->b = in->hair_proj[i + 1];
        s->first = i;
        w->current = s, w->coloured = 0;
        hk_raster_segment(s->a, s->b, segment_width(sc, s), w->r, w->saturated, hair_fragment, w);
    }
    if (w->failed) return 0;
    *fragments += (long long)w->count;
    const int m = composite(w, image);
    if (m > *most) *most = m;
    return !w->failed;
}
