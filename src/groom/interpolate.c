/* Interpolated hair (Lansink 2010 §4.1.4.3-4.1.4.4, Bertails et al. 2006 §4.1): every wick triangle
 * is filled with area x HairDensity strands whose points blend the triangle's three
 * guides, evenly spread at the root and clumped around the nearest guide at the tip. */
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

#include "groom_internal.h"
#include "hairkit/rng.h"
#include "hairkit/rod.h"

/* Random streams of the counter-based generator (rng.h). */
enum { STREAM_COUNT = 1, STREAM_STRAND = 2 };

/* Uniform barycentric coordinates: reflecting (r1, r2) into the triangle when
 * r1 + r2 > 1 keeps the density uniform. (The thesis reflects only the larger value,
 * which is not uniform; its roots crowd towards one edge.) */
void hk_groom_root_weights(double r1, double r2, double b[3])
{
    if (r1 + r2 > 1.0) {
        r1 = 1.0 - r1;
        r2 = 1.0 - r2;
    }
    b[0] = r1;
    b[1] = r2;
    b[2] = 1.0 - r1 - r2;
}

/* Tip weights of thesis §4.1.4.3: two small values v1, v2 in [0, clump], the rest v3
 * on the guide nearest to the root (the largest root weight). With stray hairs the
 * thesis's own assignment is kept (§4.1.4.4): in half of the cases v1 goes to both
 * other guides, the weights no longer sum to one and the tip strays towards or away
 * from the origin. */
void hk_groom_tip_weights(const double root[3], double clump, double u1, double u2, int stray, double b[3])
{
    double v1 = clump * u1, v2 = clump * u2;
    if (v1 + v2 > 1.0) {
        if (v1 > v2)
            v1 = 1.0 - v1;
        else
            v2 = 1.0 - v2;
    }
    const double v3 = 1.0 - (v1 + v2);
    const double a = root[0], bb = root[1], c = root[2];
    if (stray) {
        b[0] = (a < bb) ? v1 : ((a < c) ? v2 : v3);
        b[1] = (bb < c) ? v1 : ((bb < a) ? v2 : v3);
        b[2] = (c < a) ? v1 : ((c < bb) ? v2 : v3);
        return;
    }
    const int near = (a >= bb && a >= c) ? 0 : (bb >= c ? 1 : 2);
    b[near] = v3;
    b[(near + 1) % 3] = v1;
    b[(near + 2) % 3] = v2;
}

static double dist3(const double *p, const double *q)
{
    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
    return sqrt(dx * dx + dy * dy + dz * dz);
}

/* How much a guide whose tip is `d` from the tip of the strand's nearest guide takes
 * part in the strand's blend, for MaxTipDistance `far`: fully up to far / 2, not at all
 * from far on, and a smoothstep between. Guides that fell to different sides of the
 * head (a parting, an ear, the hairline before the styling sphere) blend into a strand
 * that cuts through the head, which the body projection then slides round the scalp:
 * the stray strands across the forehead of issue 12. Bertails et al. 2006 (Fig. 4d) switches such
 * triangles to following the nearest guide; a fade over a range of distances does the
 * same without a jump when a simulated guide's tip crosses the distance. */
static double tip_fade(double d, double far)
{
    if (!(far > 0.0) || d <= 0.5 * far) return 1.0;
    if (d >= far) return 0.0;
    const double x = (far - d) / (0.5 * far);
    return x * x * (3.0 - 2.0 * x);
}

/* One strand: blended points, then segment lengths restored to the blended lengths
 * of the guides' segments, so that interpolation never shortens a strand
 * (inextensibility). fade[g] (tip_fade) scales guide g's weight, the sum of the
 * weights kept; with a fade below 1 the strand is carried by its root offset, as the
 * nearest guide's copy of the semi-interpolation is: fade 0 for both other guides is
 * that copy. `faded`: a fade below 1 (a constant where make_strand is called, so that
 * each case gets a loop of its own).
 * Written with a scalar per weight and coordinate, in the order of the operations of the
 * loops over guides and axes it replaced (the same bytes): GCC -O2 kept those loops
 * of three and their arrays in memory, 230 instructions a strand point. */
static inline __attribute__((always_inline)) void make_strand(const double *const guide[3],
                                                              const double *const seg_len[3], const double *profile,
                                                              int points, const double root[3], const double tip[3],
                                                              const double fade[3], int faded, float *out)
{
    const double *const g0 = guide[0], *const g1 = guide[1], *const g2 = guide[2];
    const double *const l0 = seg_len[0], *const l1 = seg_len[1], *const l2 = seg_len[2];
    const double r0 = root[0], r1 = root[1], r2 = root[2];
    const double dw0 = tip[0] - r0, dw1 = tip[1] - r1, dw2 = tip[2] - r2;
    const double f0 = fade[0], f1 = fade[1], f2 = fade[2];
    double px = 0.0, py = 0.0, pz = 0.0; /* the blend at the previous point */
    double ax = 0.0, ay = 0.0, az = 0.0; /* the point placed */
    double ux = 0.0, uy = 0.0, uz = 1.0; /* the last segment's direction */
    double ox = 0.0, oy = 0.0, oz = 0.0; /* the root offset (faded) */
    for (int j = 0; j < points; j++) {
        const double s = profile[j];
        double w0 = r0 + dw0 * s, w1 = r1 + dw1 * s, w2 = r2 + dw2 * s;
        if (faded) {
            const double sum = w0 + w1 + w2, kept = w0 * f0 + w1 * f1 + w2 * f2;
            if (kept > 0.0) {
                const double scale = sum / kept;
                w0 = w0 * f0 * scale, w1 = w1 * f1 * scale, w2 = w2 * f2 * scale;
            } else {
                w0 = f0 == 1.0 ? sum : 0.0, w1 = f1 == 1.0 ? sum : 0.0, w2 = f2 == 1.0 ? sum : 0.0;
            }
        }
        const double *const a = g0 + 3 * j, *const b = g1 + 3 * j, *const c = g2 + 3 * j;
        double x = w0 * a[0] + w1 * b[0] + w2 * c[0];
        double y = w0 * a[1] + w1 * b[1] + w2 * c[1];
        double z = w0 * a[2] + w1 * b[2] + w2 * c[2];
        if (faded) {      /* only then: adding a zero offset would turn -0 into +0 */
            if (j == 0) { /* the root where the triangle puts it */
                ox = r0 * g0[0] + r1 * g1[0] + r2 * g2[0] - x;
                oy = r0 * g0[1] + r1 * g1[1] + r2 * g2[1] - y;
                oz = r0 * g0[2] + r1 * g1[2] + r2 * g2[2] - z;
            }
            x += ox, y += oy, z += oz;
        }
        if (j == 0) {
            ax = x, ay = y, az = z;
        } else {
            /* Target length: the guides' segment lengths blended with normalised weights. */
            const double ws = w0 + w1 + w2;
            const double len = 0.0 + w0 / ws * l0[j] + w1 / ws * l1[j] + w2 / ws * l2[j];
            const double dx = x - px, dy = y - py, dz = z - pz;
            const double n = sqrt(dx * dx + dy * dy + dz * dz);
            if (n > 1e-300) ux = dx / n, uy = dy / n, uz = dz / n;
            ax += ux * len, ay += uy * len, az += uz * len;
        }
        px = x, py = y, pz = z;
        out[3 * j] = (float)ax, out[3 * j + 1] = (float)ay, out[3 * j + 2] = (float)az;
    }
}

/* Bytes a groom of `strands` interpolated strands and `guides` guides of `points`
 * points takes with the .hair made from it (hk_groom_to_hair), the peak of `groom`
 * and `run`: per strand its float points, triangle and root weights, then the same
 * points again in the .hair with its segment count and offset (and the count
 * hk_groom_to_hair passes); per guide its double points and its .hair copy. Measured
 * on the default head (HairDensity 1000 and 2000): within 1 % of the peak RSS. */
static double groom_bytes(double strands, double guides, double points)
{
    return strands * (24.0 * points + 26.0) + guides * (36.0 * points + 10.0);
}

/* Strands per wick triangle, area x HairDensity with stochastic rounding (the same
 * draws as ever), as offsets into first[0..nt] when first is not NULL, and their total.
 * The counts are summed in double and checked before any conversion to an integer, so
 * that a huge or non-finite area (a wick vertex at 1e39) is an error, not an overflow. */
static hk_Status strand_counts(const hk_InterpolationDef *interp, const hk_Mesh *wick, uint64_t seed, long *first,
                               long *total_out, hk_Error *err)
{
    const int nt = wick->triangle_count;
    double total = 0.0;
    for (int t = 0; t < nt; t++) {
        /* HairDensity is per cm^2; stochastic rounding keeps the expected count. */
        const double area = hk_mesh_triangle_area(wick, t);
        const double expected = area * 1e4 * interp->hair_density;
        if (!isfinite(expected) || expected < 0.0)
            return hk_error_set(err, HK_ERR_INVALID, "wick triangle %d has an area of %g m^2 (not a finite size)",
                                t + 1, area);
        if (first) first[t] = (long)total;
        total += floor(expected + hk_rng_uniform(seed, STREAM_COUNT, (uint64_t)t));
        if (total > (double)HK_MAX_GROOM_STRANDS)
            return hk_error_set(err, HK_ERR_INVALID,
                                "HairDensity %g over the wick's %.4g cm^2 gives more than %ld strands, the most a "
                                "groom may have",
                                interp->hair_density, hk_mesh_area(wick) * 1e4, (long)HK_MAX_GROOM_STRANDS);
    }
    if (first) first[nt] = (long)total;
    *total_out = (long)total;
    return HK_OK;
}

static hk_Status check_bytes(const hk_InterpolationDef *interp, const hk_Mesh *wick, long strands, int guides,
                             int points, hk_Error *err)
{
    char what[256];
    snprintf(what, sizeof what, "HairDensity %g over the wick's %.4g cm^2: %ld strands of %d points with their .hair",
             interp->hair_density, hk_mesh_area(wick) * 1e4, strands, points);
    return hk_memory_check(groom_bytes((double)strands, (double)guides, (double)points), what, err);
}

hk_Status hk_groom_check_size(const hk_StrandDef *strand, const hk_InterpolationDef *interp, const hk_Mesh *wick,
                              const hk_GroomDef *options, long *strands, hk_Error *err)
{
    const hk_GroomDef o = options ? *options : hk_default_groom_def();
    long total = 0;
    hk_Status st = strand_counts(interp, wick, o.seed, NULL, &total, err);
    if (st != HK_OK) return st;
    hk_SuperHelix *probe;
    st = hk_superhelix_create(strand->element_count, strand->element_lengths, &probe, err);
    if (st != HK_OK) return st;
    const int points = hk_superhelix_sample_count(probe, strand->visuality_step);
    hk_superhelix_destroy(probe);
    st = check_bytes(interp, wick, total, wick->vertex_count, points, err);
    if (st == HK_OK && strands) *strands = total;
    return st;
}

hk_Status hk_groom_interpolate(const hk_InterpolationDef *interp, const hk_Shape *shapes, int shape_count,
                               const hk_Mesh *wick, const hk_GroomDef *o, hk_Groom *g, hk_Error *err)
{
    const int nt = wick->triangle_count, points = g->points_per_strand;
    /* Strand counts per triangle, then their offsets: a serial prefix sum, so the
     * layout does not depend on threads. */
    long *first = hk_alloc_array((size_t)nt + 1, sizeof(long), err);
    if (!first) return HK_ERR_NOMEM;
    long total = 0;
    hk_Status st = strand_counts(interp, wick, o->seed, first, &total, err);
    if (st == HK_OK) st = check_bytes(interp, wick, total, g->guide_count, points, err);
    if (st != HK_OK) {
        hk_free(first);
        return st;
    }
    /* The arrays of the strands g had are kept when they hold as many: a simulation
     * regrows the same strands every frame, and fresh arrays were 60 MB of new pages a
     * frame on the default head, faulted in and zeroed by the kernel, and unmapped
     * again. Every value is written below. */
    if (!(g->strands && g->strand_triangle && g->strand_root_weights && (long)g->strand_count == total)) {
        hk_free(g->strands);
        hk_free(g->strand_triangle);
        hk_free(g->strand_root_weights);
        g->strand_count = 0;
        g->strands = hk_alloc_array((size_t)total * (size_t)points, 3 * sizeof(float), err);
        g->strand_triangle = hk_alloc_array((size_t)total, sizeof(int), err);
        g->strand_root_weights = hk_alloc_array((size_t)total, 3 * sizeof(float), err);
        if (!g->strands || !g->strand_triangle || !g->strand_root_weights) {
            hk_free(first);
            return HK_ERR_NOMEM;
        }
    }
    g->strand_count = (int)total;
    hk_Shape *body = NULL;
    int body_count = 0;
    if (o->keep_outside && hk_groom_body_shapes(shapes, shape_count, &body, &body_count, err) != HK_OK) {
        hk_free(first);
        return HK_ERR_NOMEM;
    }
    /* What every strand would otherwise compute again at every point (a pow and three
     * square roots; the pow alone was about a fifth of a simulated frame's regrowth in
     * perf): the clump profile along the strand and the guides' segment lengths, the
     * same values computed once.
     * seg_len[g * points + j]: guide g's segment ending at point j. */
    double *profile = hk_alloc_array((size_t)points, sizeof(double), err);
    double *seg_len = hk_alloc_array((size_t)g->guide_count * (size_t)points, sizeof(double), err);
    if (!profile || !seg_len) {
        hk_free(profile);
        hk_free(seg_len);
        hk_free(body);
        hk_free(first);
        return HK_ERR_NOMEM;
    }
    for (int j = 0; j < points; j++) {
        const double t = points > 1 ? (double)j / (points - 1) : 0.0;
        profile[j] = interp->clump_profile == 1.0 ? t : pow(t, interp->clump_profile);
    }
#pragma omp parallel for schedule(static) num_threads(hk_groom_threads(o))
    for (int k = 0; k < g->guide_count; k++) {
        const double *guide = g->guides + (size_t)k * (size_t)points * 3;
        double *len = seg_len + (size_t)k * (size_t)points;
        len[0] = 0.0;
        for (int j = 1; j < points; j++) len[j] = dist3(guide + 3 * j, guide + 3 * (j - 1));
    }
    long done = 0;
#pragma omp parallel for schedule(dynamic, 8) num_threads(hk_groom_threads(o))
    for (int t = 0; t < nt; t++) {
        const int *tri = wick->triangles + 3 * t;
        const double *guide[3];
        const double *len[3];
        for (int k = 0; k < 3; k++) {
            guide[k] = g->guides + (size_t)tri[k] * (size_t)points * 3;
            len[k] = seg_len + (size_t)tri[k] * (size_t)points;
        }
        /* fades[near][g]: guide g's part in the blend of the strands nearest to guide
         * `near` (tip_fade of their tips' distance) */
        double fades[3][3];
        const size_t tipo = (size_t)(points - 1) * 3;
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++)
                fades[a][b] =
                    a == b ? 1.0 : tip_fade(dist3(guide[a] + tipo, guide[b] + tipo), interp->max_tip_distance);
        for (long s = first[t]; s < first[t + 1]; s++) {
            const uint64_t key = (uint64_t)(s - first[t]) * 4;
            double root[3], tip[3];
            hk_groom_root_weights(hk_rng_uniform(o->seed, STREAM_STRAND + ((uint64_t)t << 8), key),
                                  hk_rng_uniform(o->seed, STREAM_STRAND + ((uint64_t)t << 8), key + 1), root);
            hk_groom_tip_weights(
                root, interp->clump, hk_rng_uniform(o->seed, STREAM_STRAND + ((uint64_t)t << 8), key + 2),
                hk_rng_uniform(o->seed, STREAM_STRAND + ((uint64_t)t << 8), key + 3), interp->stray_hairs, tip);
            float *strand = g->strands + (size_t)s * (size_t)points * 3;
            const int near = (root[0] >= root[1] && root[0] >= root[2]) ? 0 : (root[1] >= root[2] ? 1 : 2);
            const double *fade = fades[near];
            if (fade[0] < 1.0 || fade[1] < 1.0 || fade[2] < 1.0)
                make_strand(guide, len, profile, points, root, tip, fade, 1, strand);
            else
                make_strand(guide, len, profile, points, root, tip, fade, 0, strand);
            hk_groom_keep_outside(body, body_count, strand, points);
            g->strand_triangle[s] = t;
            for (int k = 0; k < 3; k++) g->strand_root_weights[3 * s + k] = (float)root[k];
        }
        long d;
#pragma omp atomic capture
        d = done += first[t + 1] - first[t];
        if (omp_get_thread_num() == 0) hk_groom_report(o, "strands", d, total);
    }
    hk_groom_report(o, "strands", total, total);
    hk_free(profile);
    hk_free(seg_len);
    hk_free(body);
    hk_free(first);
    return HK_OK;
}
