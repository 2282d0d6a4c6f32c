/* PLY hair strands (docs/file-formats.md, "PLY strands"), binary little-endian or ASCII.
 *
 * Read: a `vertex` element with x, y, z (float or double; optional red, green, blue as
 * uchar 0..255 or as float 0..1; other properties skipped), and either a `strand` element
 * whose property `nsegs` (or its only property) is each strand's segment count, the
 * CT2Hair / hairutil layout (strand i takes the next nsegs + 1 vertices), or an `edge`
 * element (vertex1, vertex2) whose edges are chained into strands: a strand runs from a
 * vertex with one edge to the other end of its chain, root first where the edges point
 * away from it; a vertex on no edge is a strand of one point; a vertex with three or
 * more edges (a branch) or a closed loop is refused. Strands come in the order of their
 * lowest-numbered end. Other elements (faces, ...) are read and ignored. With both
 * elements the strand element is used.
 * Written: the CT2Hair layout (vertex x, y, z float, red, green, blue uchar when the hair
 * has colours, and strand nsegs ushort). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"
#include "hairkit/version.h"
#include "ply.h"

typedef struct Data {
    float *xyz; /* 3 per vertex */
    float *rgb; /* 3 per vertex or NULL */
    uint32_t nverts;
    int have_vertex;
    uint32_t *nsegs; /* per strand */
    uint32_t nstrands;
    int have_strands;
    uint32_t *edges; /* 2 per edge */
    uint32_t nedges;
    int have_edges;
} Data;

static hk_Status store_vertex(hk_Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    (void)ply, (void)err;
    Data *d = user;
    for (int k = 0; k < 3; k++) d->xyz[3 * r + (uint64_t)k] = (float)row[k];
    if (d->rgb)
        for (int k = 0; k < 3; k++) d->rgb[3 * r + (uint64_t)k] = (float)row[3 + k];
    return HK_OK;
}

static hk_Status store_strand(hk_Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    Data *d = user;
    if (row[0] < 0 || row[0] > 65535 || row[0] != floor(row[0]))
        return hk_ply_error(ply, err, "strand %llu has %g segments (0 to 65535 are read)", (unsigned long long)r,
                            row[0]);
    d->nsegs[r] = (uint32_t)row[0];
    return HK_OK;
}

static hk_Status store_edge(hk_Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    (void)ply, (void)err;
    Data *d = user;
    for (int k = 0; k < 2; k++) {
        if (row[k] < 0 || row[k] > UINT32_MAX || row[k] != floor(row[k]))
            return hk_ply_error(ply, err, "edge %llu: vertex index %g", (unsigned long long)r, row[k]);
        d->edges[2 * r + (uint64_t)k] = (uint32_t)row[k];
    }
    return HK_OK;
}

static hk_Status read_body(hk_Ply *ply, Data *d, hk_Error *err)
{
    for (int e = 0; e < ply->nelems; e++) {
        const hk_PlyElem *el = &ply->elems[e];
        hk_Status st = hk_ply_check_room(ply, el, 0, err);
        if (st != HK_OK) return st;
        int keep[HK_PLY_MAX_PROPS];
        for (int i = 0; i < HK_PLY_MAX_PROPS; i++) keep[i] = -1;
        double row[6];
        if (!strcmp(el->name, "vertex")) {
            const char *names[6] = {"x", "y", "z", "red", "green", "blue"};
            int at[6];
            for (int k = 0; k < 6; k++) at[k] = hk_ply_prop_index(el, names[k]);
            for (int k = 0; k < 3; k++) {
                if (at[k] < 0 || el->props[at[k]].count_type) {
                    ply->line = -el->line;
                    return hk_ply_error(ply, err, "the vertex element has no property %s", names[k]);
                }
                if (el->props[at[k]].type != HK_PLY_F32 && el->props[at[k]].type != HK_PLY_F64) {
                    ply->line = -el->line;
                    return hk_ply_error(ply, err, "vertex %s is %s (float or double are read)", names[k],
                                        hk_ply_types[el->props[at[k]].type].name);
                }
                keep[at[k]] = k;
            }
            int colours = 1;
            for (int k = 3; k < 6; k++)
                colours &= at[k] >= 0 && !el->props[at[k]].count_type &&
                           (el->props[at[k]].type == HK_PLY_U8 || el->props[at[k]].type >= HK_PLY_F32);
            d->nverts = (uint32_t)el->count;
            d->have_vertex = 1;
            d->xyz = hk_alloc_array((size_t)el->count, 3 * sizeof(float), err);
            if (!d->xyz) return HK_ERR_NOMEM;
            if (colours) {
                for (int k = 3; k < 6; k++) keep[at[k]] = k;
                d->rgb = hk_alloc_array((size_t)el->count, 3 * sizeof(float), err);
                if (!d->rgb) return HK_ERR_NOMEM;
            }
            st = hk_ply_read_element(ply, el, keep, row, 6, store_vertex, d, err);
            if (st == HK_OK && colours && el->props[at[3]].type == HK_PLY_U8)
                for (size_t i = 0; i < 3 * (size_t)el->count; i++) d->rgb[i] /= 255.0f;
        } else if (!strcmp(el->name, "strand")) {
            int at = hk_ply_prop_index(el, "nsegs");
            if (at < 0 && el->nprops == 1) at = 0;
            if (at < 0 || el->props[at].count_type || el->props[at].type >= HK_PLY_F32) {
                ply->line = -el->line;
                return hk_ply_error(ply, err, "the strand element has no integer property nsegs (segments per strand)");
            }
            keep[at] = 0;
            d->nstrands = (uint32_t)el->count;
            d->have_strands = 1;
            d->nsegs = hk_alloc_array((size_t)el->count, sizeof(uint32_t), err);
            if (!d->nsegs) return HK_ERR_NOMEM;
            st = hk_ply_read_element(ply, el, keep, row, 1, store_strand, d, err);
        } else if (!strcmp(el->name, "edge")) {
            const int a = hk_ply_prop_index(el, "vertex1"), b = hk_ply_prop_index(el, "vertex2");
            if (a < 0 || b < 0 || el->props[a].count_type || el->props[b].count_type ||
                el->props[a].type >= HK_PLY_F32 || el->props[b].type >= HK_PLY_F32) {
                ply->line = -el->line;
                return hk_ply_error(ply, err, "the edge element has no integer properties vertex1 and vertex2");
            }
            keep[a] = 0, keep[b] = 1;
            d->nedges = (uint32_t)el->count;
            d->have_edges = 1;
            d->edges = hk_alloc_array((size_t)el->count, 2 * sizeof(uint32_t), err);
            if (!d->edges) return HK_ERR_NOMEM;
            st = hk_ply_read_element(ply, el, keep, row, 2, store_edge, d, err);
        } else {
            st = hk_ply_read_element(ply, el, NULL, row, 0, NULL, NULL, err);
        }
        if (st != HK_OK) return st;
    }
    return hk_ply_check_end(ply, err);
}

/* Chains the edges into strands; order[] receives the vertices strand by strand,
 * counts[] the points of each strand. */
static hk_Status chain_edges(hk_Ply *ply, const Data *d, uint32_t *order, uint32_t *counts, uint32_t *nstrands,
                             hk_Error *err)
{
    const uint32_t nv = d->nverts;
    hk_Status st = HK_OK;
    uint32_t *nbr = hk_alloc_array(nv, 2 * sizeof(uint32_t), err);
    unsigned char *deg = hk_calloc_array(nv, 1, err), *root = hk_calloc_array(nv, 1, err),
                  *seen = hk_calloc_array(nv, 1, err);
    if (!nbr || !deg || !root || !seen) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (uint32_t e = 0; e < d->nedges; e++) {
        const uint32_t a = d->edges[2 * e], b = d->edges[2 * e + 1];
        if (a >= nv || b >= nv || a == b) {
            st = hk_error_set(err, HK_ERR_PARSE, "%s: edge %u joins vertices %u and %u (%u vertices)", ply->t.path, e,
                              a, b, nv);
            goto done;
        }
        for (int k = 0; k < 2; k++) {
            const uint32_t v = k ? b : a;
            if (deg[v] == 2) {
                st =
                    hk_error_set(err, HK_ERR_PARSE, "%s: edge %u gives vertex %u a third edge: strands must not branch",
                                 ply->t.path, e, v);
                goto done;
            }
            nbr[2 * v + deg[v]] = k ? a : b;
            deg[v]++;
        }
        root[a] = 1; /* an edge leaves a: a can be a strand's root */
    }
    uint32_t n = 0, s = 0;
    for (uint32_t v = 0; v < nv; v++) {
        if (seen[v] || deg[v] == 2) continue;
        const uint32_t start = n;
        uint32_t prev = UINT32_MAX, cur = v;
        for (;;) {
            seen[cur] = 1;
            order[n++] = cur;
            uint32_t next = UINT32_MAX;
            for (unsigned k = 0; k < deg[cur]; k++)
                if (nbr[2 * cur + k] != prev && !seen[nbr[2 * cur + k]]) next = nbr[2 * cur + k];
            if (next == UINT32_MAX) break;
            prev = cur, cur = next;
        }
        if (n - start > 65536) {
            st = hk_error_set(err, HK_ERR_PARSE, "%s: the strand from vertex %u has %u points (65536 at most)",
                              ply->t.path, v, n - start);
            goto done;
        }
        if (deg[v] == 1 && !root[v]) /* the edge points into v: v is the tip */
            for (uint32_t i = start, j = n - 1; i < j; i++, j--) {
                const uint32_t t = order[i];
                order[i] = order[j], order[j] = t;
            }
        counts[s++] = n - start;
    }
    for (uint32_t v = 0; v < nv; v++)
        if (!seen[v]) {
            st = hk_error_set(err, HK_ERR_PARSE, "%s: vertex %u lies on a closed loop of edges: strands need two ends",
                              ply->t.path, v);
            goto done;
        }
    *nstrands = s;
done:
    hk_free(nbr);
    hk_free(deg);
    hk_free(root);
    hk_free(seen);
    return st;
}

hk_Status hk_ply_hair_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    hk_Ply ply;
    Data d;
    memset(&d, 0, sizeof d);
    uint32_t *order = NULL, *counts = NULL;
    hk_Status st = hk_ply_open(&ply, path, err);
    if (st != HK_OK) return st;
    st = read_body(&ply, &d, err);
    if (st != HK_OK) goto done;
    if (!d.have_vertex) {
        st = hk_error_set(err, HK_ERR_PARSE, "%s: no vertex element", path);
        goto done;
    }
    uint32_t nstrands = 0;
    if (d.have_strands) {
        uint64_t total = 0;
        for (uint32_t s = 0; s < d.nstrands; s++) total += (uint64_t)d.nsegs[s] + 1;
        if (total != d.nverts) {
            st = hk_error_set(err, HK_ERR_PARSE,
                              "%s: the strands' segment counts add up to %llu points, the file has %u vertices", path,
                              (unsigned long long)total, d.nverts);
            goto done;
        }
        counts = d.nsegs;
        d.nsegs = NULL;
        for (uint32_t s = 0; s < d.nstrands; s++) counts[s]++;
        nstrands = d.nstrands;
    } else if (d.have_edges) {
        order = hk_alloc_array(d.nverts, sizeof *order, err);
        counts = hk_alloc_array(d.nverts, sizeof *counts, err);
        if (!order || !counts) {
            st = HK_ERR_NOMEM;
            goto done;
        }
        st = chain_edges(&ply, &d, order, counts, &nstrands, err);
        if (st != HK_OK) goto done;
    } else {
        int faces = 0;
        for (int e = 0; e < ply.nelems; e++) faces |= !strcmp(ply.elems[e].name, "face");
        st = hk_error_set(err, HK_ERR_PARSE,
                          "%s: neither a strand element (segments per strand) nor an edge element: "
                          "where the strands begin is not known%s",
                          path, faces ? " (this PLY has faces: a mesh, not hair strands)" : "");
        goto done;
    }
    hk_Error sub;
    st = hk_hair_alloc(h, nstrands, counts, &sub);
    if (st != HK_OK) {
        hk_error_set(err, st, "%s: %s", path, sub.message);
        goto done;
    }
    if (d.rgb) {
        h->colors = hk_alloc_array(d.nverts, 3 * sizeof(float), err);
        if (!h->colors) {
            st = HK_ERR_NOMEM;
            goto done;
        }
        h->flags |= HK_HAIR_COLORS;
    }
    for (uint32_t i = 0; i < d.nverts; i++) {
        const uint32_t v = order ? order[i] : i;
        memcpy(h->points + 3 * (size_t)i, d.xyz + 3 * (size_t)v, 3 * sizeof(float));
        if (d.rgb) memcpy(h->colors + 3 * (size_t)i, d.rgb + 3 * (size_t)v, 3 * sizeof(float));
    }
    st = hk_hair_check_finite(path, h, err);
done:
    hk_free(d.xyz);
    hk_free(d.rgb);
    hk_free(d.nsegs);
    hk_free(d.edges);
    hk_free(order);
    hk_free(counts);
    hk_ply_close(&ply);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

static unsigned char to_byte(float c)
{
    const double v = (double)c * 255.0 + 0.5;
    return v <= 0.0 ? 0 : v >= 255.0 ? 255 : (unsigned char)v;
}

hk_Status hk_ply_hair_save(const char *path, const hk_HairFile *h, int ascii, hk_Error *err)
{
    const int colours = (h->flags & HK_HAIR_COLORS) && h->colors;
    hk_Writer w;
    hk_Status st = hk_writer_open(&w, path, err);
    if (st != HK_OK) return st;
    hk_writer_printf(&w,
                     "ply\nformat %s 1.0\ncomment hairkit %s: %u strands, %u points\n"
                     "element vertex %u\nproperty float x\nproperty float y\nproperty float z\n",
                     ascii ? "ascii" : "binary_little_endian", hk_version(), h->strand_count, h->point_count,
                     h->point_count);
    if (colours) hk_writer_printf(&w, "property uchar red\nproperty uchar green\nproperty uchar blue\n");
    hk_writer_printf(&w, "element strand %u\nproperty ushort nsegs\nend_header\n", h->strand_count);
    for (size_t i = 0; i < h->point_count; i++) {
        const float *p = h->points + 3 * i;
        const float *c = colours ? h->colors + 3 * i : NULL;
        if (ascii) {
            for (int k = 0; k < 3; k++) {
                if (k) hk_writer_bytes(&w, " ", 1);
                hk_writer_float_text(&w, p[k]);
            }
            if (c) hk_writer_printf(&w, " %u %u %u", to_byte(c[0]), to_byte(c[1]), to_byte(c[2]));
            hk_writer_bytes(&w, "\n", 1);
        } else {
            for (int k = 0; k < 3; k++) hk_writer_f32(&w, p[k]);
            if (c) {
                const unsigned char b[3] = {to_byte(c[0]), to_byte(c[1]), to_byte(c[2])};
                hk_writer_bytes(&w, b, 3);
            }
        }
    }
    for (uint32_t s = 0; s < h->strand_count; s++) {
        const uint16_t segs = (uint16_t)(hk_hair_strand_points(h, s) - 1);
        if (ascii) {
            hk_writer_printf(&w, "%u\n", (unsigned)segs);
        } else {
            unsigned char b[2];
            hk_put_u16(b, segs);
            hk_writer_bytes(&w, b, 2);
        }
    }
    return hk_writer_commit(&w, err);
}
