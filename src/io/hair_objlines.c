/* Hair as Wavefront OBJ polylines (docs/file-formats.md, "OBJ polylines"): `v x y z`
 * points and `l i j k ...` lines, one strand per line (1-based indices, negative ones
 * counted back from the last `v` so far, `i/t` forms taking the point index). Lines that
 * continue the previous one (their first index is its last, as a polyline written one
 * segment per `l` line) are joined into one strand. `vt`, `vn`, `vp`, `g`, `o`, `s`,
 * `usemtl`, `mtllib`, `f` and `p` are ignored (a head in the same file stays out of the
 * hair); free-form curves and other statements are refused. This reader is separate from
 * the OBJ mesh reader (obj.c), which reads heads. */
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"
#include "hairkit/version.h"

/* The next line of t from *pos: [*b, *e), comment removed; returns 0 at the end. */
static int next_line(const hk_TextIn *t, size_t *pos, long *line, const char **b, const char **e)
{
    if (*pos >= t->size) return 0;
    const char *d = t->data;
    size_t p = *pos, q = p;
    while (q < t->size && d[q] != '\n' && d[q] != '\r') q++;
    *b = d + p;
    *e = d + q;
    const char *hash = memchr(*b, '#', (size_t)(*e - *b));
    if (hash) *e = hash;
    if (q < t->size) q += d[q] == '\r' && q + 1 < t->size && d[q + 1] == '\n' ? 2 : 1;
    *pos = q;
    (*line)++;
    return 1;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

/* The next token in [*p, e): returns its length (0 at the end). */
static size_t next_token(const char **p, const char *e, const char **tok)
{
    const char *s = *p;
    while (s < e && is_blank(*s)) s++;
    const char *t = s;
    while (t < e && !is_blank(*t)) t++;
    *tok = s;
    *p = t;
    return (size_t)(t - s);
}

static int keyword(const char *tok, size_t n, const char *kw) { return n == strlen(kw) && !memcmp(tok, kw, n); }

hk_Status hk_obj_hair_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    hk_TextIn t;
    hk_Status st = hk_textin_load(&t, path, err);
    if (st != HK_OK) return st;
    float *verts = NULL;
    uint32_t *index = NULL, *counts = NULL, *starts = NULL;
    for (size_t i = 0; i < t.size; i++)
        if (t.data[i] == '\0') {
            st = hk_textin_error(&t, 0, err, "binary data (a NUL byte at offset %zu): not an OBJ text file", i);
            goto done;
        }
    /* Pass 1: counts. */
    uint64_t nv = 0, nidx = 0, nl = 0;
    size_t pos = 0;
    long line = 0;
    const char *b, *e;
    while (next_line(&t, &pos, &line, &b, &e)) {
        const char *tok, *p = b;
        size_t n = next_token(&p, e, &tok);
        if (keyword(tok, n, "v"))
            nv++;
        else if (keyword(tok, n, "l")) {
            nl++;
            while (next_token(&p, e, &tok)) nidx++;
        }
    }
    if (nl == 0) {
        st = hk_textin_error(&t, 0, err, "no polylines ('l' lines): not an OBJ hair file");
        goto done;
    }
    if (nv > UINT32_MAX || nidx > UINT32_MAX) {
        st = hk_textin_error(&t, 0, err, "more than 2^32 points");
        goto done;
    }
    verts = hk_alloc_array((size_t)nv, 3 * sizeof(float), err);
    index = hk_alloc_array((size_t)nidx, sizeof *index, err);
    starts = hk_alloc_array((size_t)nl + 1, sizeof *starts, err);
    if (!verts || !index || !starts) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    /* Pass 2: points and strands. */
    uint32_t v = 0, ns = 0, np = 0;
    int joinable = 0; /* the previous statement was an `l` line */
    pos = 0, line = 0;
    while (next_line(&t, &pos, &line, &b, &e)) {
        const char *tok, *p = b;
        size_t n = next_token(&p, e, &tok);
        if (n == 0) continue;
        if (keyword(tok, n, "v")) {
            joinable = 0;
            int k = 0;
            float xyz[3];
            while ((n = next_token(&p, e, &tok)) != 0) {
                float f;
                if (!hk_parse_float(tok, n, t.point, &f)) {
                    st = hk_textin_error(&t, line, err, "'%.*s' is not a number", (int)(n < 40 ? n : 40), tok);
                    goto done;
                }
                if (k < 3) xyz[k] = f;
                k++;
            }
            if (k < 3 || k > 7) {
                st = hk_textin_error(&t, line, err,
                                     "a vertex has 3 coordinates (and optionally w or a colour), got %d numbers", k);
                goto done;
            }
            memcpy(verts + 3 * (size_t)v++, xyz, sizeof xyz);
        } else if (keyword(tok, n, "l")) {
            const uint32_t before = np;
            int first = 1, joined = 0;
            while ((n = next_token(&p, e, &tok)) != 0) {
                size_t m = 0;
                while (m < n && tok[m] != '/') m++;
                long long k;
                if (!hk_parse_long(tok, m, -(long long)v, (long long)nv, &k) || k == 0) {
                    st =
                        hk_textin_error(&t, line, err, "'%.*s' is not a vertex index (%u vertices so far, %llu in all)",
                                        (int)(n < 40 ? n : 40), tok, v, (unsigned long long)nv);
                    goto done;
                }
                const uint32_t idx = (uint32_t)(k < 0 ? (long long)v + k : k - 1);
                /* A line that starts where the previous one ended continues its strand. */
                if (first && joinable && index[np - 1] == idx)
                    joined = 1;
                else
                    index[np++] = idx;
                first = 0;
            }
            if (first) {
                st = hk_textin_error(&t, line, err, "an 'l' line without vertex indices");
                goto done;
            }
            if (!joined) starts[ns++] = before;
            joinable = 1;
        } else if (keyword(tok, n, "vt") || keyword(tok, n, "vn") || keyword(tok, n, "vp") || keyword(tok, n, "g") ||
                   keyword(tok, n, "o") || keyword(tok, n, "s") || keyword(tok, n, "usemtl") ||
                   keyword(tok, n, "mtllib") || keyword(tok, n, "f") || keyword(tok, n, "p")) {
            joinable = 0;
        } else if (keyword(tok, n, "cstype") || keyword(tok, n, "curv") || keyword(tok, n, "curv2") ||
                   keyword(tok, n, "deg") || keyword(tok, n, "parm")) {
            st = hk_textin_error(&t, line, err, "free-form curves ('%.*s') are not read: only polylines ('l')", (int)n,
                                 tok);
            goto done;
        } else {
            st = hk_textin_error(&t, line, err, "unknown statement '%.*s'", (int)(n < 40 ? n : 40), tok);
            goto done;
        }
    }
    starts[ns] = np;
    counts = hk_alloc_array(ns, sizeof *counts, err);
    if (!counts) {
        st = HK_ERR_NOMEM;
        goto done;
    }
    for (uint32_t i = 0; i < ns; i++) counts[i] = starts[i + 1] - starts[i];
    hk_Error sub;
    st = hk_hair_alloc(h, ns, counts, &sub);
    if (st != HK_OK) {
        hk_error_set(err, st, "%s: %s", path, sub.message);
        goto done;
    }
    for (uint32_t i = 0; i < np; i++)
        memcpy(h->points + 3 * (size_t)i, verts + 3 * (size_t)index[i], 3 * sizeof(float));
done:
    hk_free(verts);
    hk_free(index);
    hk_free(counts);
    hk_free(starts);
    hk_textin_free(&t);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

hk_Status hk_obj_hair_save(const char *path, const hk_HairFile *h, hk_Error *err)
{
    hk_Writer w;
    hk_Status st = hk_writer_open(&w, path, err);
    if (st != HK_OK) return st;
    hk_writer_printf(&w, "# hairkit %s: %u strands, %u points; one 'l' polyline per strand, root first\n", hk_version(),
                     h->strand_count, h->point_count);
    for (size_t i = 0; i < h->point_count; i++) {
        const float *p = h->points + 3 * i;
        hk_writer_bytes(&w, "v ", 2);
        hk_writer_float_text(&w, p[0]);
        hk_writer_bytes(&w, " ", 1);
        hk_writer_float_text(&w, p[1]);
        hk_writer_bytes(&w, " ", 1);
        hk_writer_float_text(&w, p[2]);
        hk_writer_bytes(&w, "\n", 1);
    }
    for (uint32_t s = 0; s < h->strand_count; s++) {
        hk_writer_bytes(&w, "l", 1);
        for (uint32_t i = h->first_point[s]; i < h->first_point[s + 1]; i++) hk_writer_printf(&w, " %u", i + 1);
        hk_writer_bytes(&w, "\n", 1);
    }
    return hk_writer_commit(&w, err);
}
