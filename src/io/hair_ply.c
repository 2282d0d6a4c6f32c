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
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"
#include "hairkit/version.h"

enum { T_I8 = 1, T_U8, T_I16, T_U16, T_I32, T_U32, T_F32, T_F64 };
static const struct {
    const char *name, *alias;
    int size;
} types[] = {{"", "", 0},          {"char", "int8", 1},   {"uchar", "uint8", 1},    {"short", "int16", 2},
             {"ushort", "uint16", 2}, {"int", "int32", 4}, {"uint", "uint32", 4}, {"float", "float32", 4},
             {"double", "float64", 8}};

#define MAX_ELEMS 32
#define MAX_PROPS 64
#define NAME_SIZE 64

typedef struct Prop {
    char name[NAME_SIZE];
    int type;       /* of the value (of the items, for a list) */
    int count_type; /* of a list's count; 0 for a scalar */
} Prop;

typedef struct Elem {
    char name[NAME_SIZE];
    uint64_t count;
    Prop props[MAX_PROPS];
    int nprops;
    long line;
} Elem;

typedef struct Ply {
    hk_TextIn t;
    int ascii;
    Elem elems[MAX_ELEMS];
    int nelems;
    /* the body cursor */
    size_t pos;
    long line; /* ASCII: line of pos */
} Ply;

#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
static hk_Status ply_error(const Ply *ply, hk_Error *err, const char *fmt, ...);

/* file:line (ASCII body, header) or file:offset (binary body) */
static hk_Status ply_error(const Ply *ply, hk_Error *err, const char *fmt, ...)
{
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (ply->ascii || ply->line < 0) return hk_textin_error(&ply->t, ply->line < 0 ? -ply->line : ply->line, err, "%s", msg);
    return hk_error_set(err, HK_ERR_PARSE, "%s:%zu: %s", ply->t.path, ply->pos, msg);
}

static int type_of(const char *name)
{
    for (int i = 1; i <= T_F64; i++)
        if (!strcmp(name, types[i].name) || !strcmp(name, types[i].alias)) return i;
    return 0;
}

/* Splits a header line (NUL-terminated, modified) into at most max tokens. */
static int split(char *line, char **tok, int max)
{
    int n = 0;
    char *p = line;
    while (*p) {
        while (*p == ' ' || *p == '\t') *p++ = '\0';
        if (!*p) break;
        if (n == max) return max + 1;
        tok[n++] = p;
        while (*p && *p != ' ' && *p != '\t') p++;
    }
    return n;
}

static hk_Status parse_header(Ply *ply, hk_Error *err)
{
    char *d = ply->t.data;
    const size_t size = ply->t.size;
    size_t pos = 0;
    long line = 0;
    int have_format = 0;
    if (size < 4 || memcmp(d, "ply", 3) != 0 || (d[3] != '\n' && d[3] != '\r')) {
        ply->line = -1;
        return ply_error(ply, err, "not a PLY file (no 'ply' line)");
    }
    for (;;) {
        if (pos >= size) {
            ply->line = -(line + 1);
            return ply_error(ply, err, "the header has no end_header line");
        }
        line++;
        size_t end = pos;
        while (end < size && d[end] != '\n' && d[end] != '\r') end++;
        if (end == size) {
            ply->line = -line;
            return ply_error(ply, err, "the header has no end_header line");
        }
        const size_t next = end + (d[end] == '\r' && end + 1 < size && d[end + 1] == '\n' ? 2 : 1);
        for (size_t i = pos; i < end; i++)
            if ((unsigned char)d[i] < 0x20 && d[i] != '\t') {
                ply->line = -line;
                return ply_error(ply, err, "binary data in the header (not a PLY file?)");
            }
        char buf[512];
        if (end - pos >= sizeof buf) {
            ply->line = -line;
            return ply_error(ply, err, "header line too long");
        }
        memcpy(buf, d + pos, end - pos);
        buf[end - pos] = '\0';
        pos = next;
        ply->line = -line;
        char *tok[8];
        const int n = split(buf, tok, 7);
        if (line == 1) {
            if (n != 1 || strcmp(tok[0], "ply")) return ply_error(ply, err, "not a PLY file (no 'ply' line)");
            continue;
        }
        if (n == 0) continue;
        if (!strcmp(tok[0], "comment") || !strcmp(tok[0], "obj_info")) continue;
        if (!strcmp(tok[0], "format")) {
            if (n != 3 || have_format) return ply_error(ply, err, "malformed format line");
            if (!strcmp(tok[1], "ascii")) ply->ascii = 1;
            else if (!strcmp(tok[1], "binary_little_endian")) ply->ascii = 0;
            else if (!strcmp(tok[1], "binary_big_endian"))
                return ply_error(ply, err, "big-endian PLY is not read (binary_little_endian and ascii are)");
            else return ply_error(ply, err, "unknown format '%s'", tok[1]);
            if (strcmp(tok[2], "1.0")) return ply_error(ply, err, "PLY version '%s' (1.0 is read)", tok[2]);
            have_format = 1;
            continue;
        }
        if (!strcmp(tok[0], "element")) {
            long long count;
            if (n != 3 || !hk_parse_long(tok[2], strlen(tok[2]), 0, (long long)UINT32_MAX, &count))
                return ply_error(ply, err, "malformed element line (element NAME COUNT, COUNT < 2^32)");
            if (ply->nelems == MAX_ELEMS) return ply_error(ply, err, "more than %d elements", MAX_ELEMS);
            if (strlen(tok[1]) >= NAME_SIZE) return ply_error(ply, err, "element name too long");
            for (int e = 0; e < ply->nelems; e++)
                if (!strcmp(ply->elems[e].name, tok[1])) return ply_error(ply, err, "element '%s' given twice", tok[1]);
            Elem *el = &ply->elems[ply->nelems++];
            memset(el, 0, sizeof *el);
            strcpy(el->name, tok[1]);
            el->count = (uint64_t)count;
            el->line = line;
            continue;
        }
        if (!strcmp(tok[0], "property")) {
            if (!ply->nelems) return ply_error(ply, err, "property before any element");
            Elem *el = &ply->elems[ply->nelems - 1];
            if (el->nprops == MAX_PROPS) return ply_error(ply, err, "more than %d properties", MAX_PROPS);
            Prop p;
            memset(&p, 0, sizeof p);
            const char *name;
            if (n == 5 && !strcmp(tok[1], "list")) {
                p.count_type = type_of(tok[2]);
                p.type = type_of(tok[3]);
                if (!p.count_type || p.count_type >= T_F32 || !p.type)
                    return ply_error(ply, err, "unknown or non-integer list type in '%s %s'", tok[2], tok[3]);
                name = tok[4];
            } else if (n == 3) {
                p.type = type_of(tok[1]);
                if (!p.type) return ply_error(ply, err, "unknown property type '%s'", tok[1]);
                name = tok[2];
            } else {
                return ply_error(ply, err, "malformed property line");
            }
            if (strlen(name) >= NAME_SIZE) return ply_error(ply, err, "property name too long");
            for (int i = 0; i < el->nprops; i++)
                if (!strcmp(el->props[i].name, name)) return ply_error(ply, err, "property '%s' given twice", name);
            strcpy(p.name, name);
            el->props[el->nprops++] = p;
            continue;
        }
        if (!strcmp(tok[0], "end_header")) {
            if (n != 1) return ply_error(ply, err, "malformed end_header line");
            if (!have_format) return ply_error(ply, err, "no format line in the header");
            ply->pos = pos;
            ply->line = line + 1;
            return HK_OK;
        }
        return ply_error(ply, err, "unknown header line '%s'", tok[0]);
    }
}

/* Reads one value of `type` at the cursor into *out (exact for float and double). */
static hk_Status read_value(Ply *ply, int type, double *out, const char *what, hk_Error *err)
{
    const char *d = ply->t.data;
    const size_t size = ply->t.size;
    if (!ply->ascii) {
        const size_t n = (size_t)types[type].size;
        if (ply->pos > size || size - ply->pos < n)
            return ply_error(ply, err, "truncated in %s (the file ends at %zu)", what, size);
        const unsigned char *p = (const unsigned char *)d + ply->pos;
        switch (type) {
        case T_I8: *out = (double)(int8_t)p[0]; break;
        case T_U8: *out = (double)p[0]; break;
        case T_I16: *out = (double)(int16_t)hk_le_u16(p); break;
        case T_U16: *out = (double)hk_le_u16(p); break;
        case T_I32: *out = (double)(int32_t)hk_le_u32(p); break;
        case T_U32: *out = (double)hk_le_u32(p); break;
        case T_F32: *out = (double)hk_le_f32(p); break;
        default: *out = hk_le_f64(p); break;
        }
        if (!isfinite(*out)) return ply_error(ply, err, "non-finite number in %s", what);
        ply->pos += n;
        return HK_OK;
    }
    size_t p = ply->pos;
    while (p < size && (d[p] == ' ' || d[p] == '\t' || d[p] == '\n' || d[p] == '\r')) {
        if (d[p] == '\n' || (d[p] == '\r' && (p + 1 >= size || d[p + 1] != '\n'))) ply->line++;
        p++;
    }
    ply->pos = p;
    if (p >= size) return ply_error(ply, err, "truncated in %s (the file ends)", what);
    size_t e = p;
    while (e < size && d[e] != ' ' && d[e] != '\t' && d[e] != '\n' && d[e] != '\r') e++;
    int ok;
    if (type == T_F32) {
        float f;
        ok = hk_parse_float(d + p, e - p, ply->t.point, &f);
        *out = (double)f;
    } else if (type == T_F64) {
        ok = hk_parse_double(d + p, e - p, ply->t.point, out);
    } else {
        static const long long lo[] = {0, -128, 0, -32768, 0, INT32_MIN, 0};
        static const long long hi[] = {0, 127, 255, 32767, 65535, INT32_MAX, UINT32_MAX};
        long long v = 0;
        ok = hk_parse_long(d + p, e - p, lo[type], hi[type], &v);
        *out = (double)v;
    }
    if (!ok) {
        char tok[32];
        size_t n = e - p < sizeof tok - 1 ? e - p : sizeof tok - 1;
        memcpy(tok, d + p, n);
        tok[n] = '\0';
        return ply_error(ply, err, "'%s' is not a %s in %s", tok, types[type].name, what);
    }
    ply->pos = e;
    return HK_OK;
}

/* Fewest bytes a record of el can take. */
static uint64_t min_record(const Ply *ply, const Elem *el)
{
    uint64_t n = 0;
    for (int i = 0; i < el->nprops; i++)
        n += ply->ascii ? 2 : (uint64_t)types[el->props[i].count_type ? el->props[i].count_type : el->props[i].type].size;
    return n;
}

static int prop_index(const Elem *el, const char *name)
{
    for (int i = 0; i < el->nprops; i++)
        if (!strcmp(el->props[i].name, name)) return i;
    return -1;
}

typedef struct Data {
    float *xyz;       /* 3 per vertex */
    float *rgb;       /* 3 per vertex or NULL */
    uint32_t nverts;
    int have_vertex;
    uint32_t *nsegs;  /* per strand */
    uint32_t nstrands;
    int have_strands;
    uint32_t *edges;  /* 2 per edge */
    uint32_t nedges;
    int have_edges;
} Data;

/* Reads every record of el, keeping the values `keep` asks for: keep[i] >= 0 stores
 * property i's value into column keep[i] of dst (ncol columns, as double). */
static hk_Status read_element(Ply *ply, const Elem *el, const int *keep, double *row, int ncol,
                              hk_Status (*store)(Ply *, void *, uint64_t, const double *, hk_Error *), void *user,
                              hk_Error *err)
{
    char what[NAME_SIZE + 48];
    for (uint64_t r = 0; r < el->count; r++) {
        for (int c = 0; c < ncol; c++) row[c] = 0.0;
        for (int i = 0; i < el->nprops; i++) {
            const Prop *p = &el->props[i];
            snprintf(what, sizeof what, "%s %llu", el->name, (unsigned long long)r);
            double v;
            if (p->count_type) {
                hk_Status st = read_value(ply, p->count_type, &v, what, err);
                if (st != HK_OK) return st;
                if (v < 0 || v > 1e9) return ply_error(ply, err, "list of %g items in %s", v, what);
                for (uint64_t k = 0; k < (uint64_t)v; k++) {
                    double skip;
                    st = read_value(ply, p->type, &skip, what, err);
                    if (st != HK_OK) return st;
                }
                continue;
            }
            hk_Status st = read_value(ply, p->type, &v, what, err);
            if (st != HK_OK) return st;
            if (keep && keep[i] >= 0) row[keep[i]] = v;
        }
        if (store) {
            hk_Status st = store(ply, user, r, row, err);
            if (st != HK_OK) return st;
        }
    }
    return HK_OK;
}

static hk_Status store_vertex(Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    (void)ply, (void)err;
    Data *d = user;
    for (int k = 0; k < 3; k++) d->xyz[3 * r + (uint64_t)k] = (float)row[k];
    if (d->rgb)
        for (int k = 0; k < 3; k++) d->rgb[3 * r + (uint64_t)k] = (float)row[3 + k];
    return HK_OK;
}

static hk_Status store_strand(Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    Data *d = user;
    if (row[0] < 0 || row[0] > 65535 || row[0] != floor(row[0]))
        return ply_error(ply, err, "strand %llu has %g segments (0 to 65535 are read)", (unsigned long long)r, row[0]);
    d->nsegs[r] = (uint32_t)row[0];
    return HK_OK;
}

static hk_Status store_edge(Ply *ply, void *user, uint64_t r, const double *row, hk_Error *err)
{
    (void)ply, (void)err;
    Data *d = user;
    for (int k = 0; k < 2; k++) {
        if (row[k] < 0 || row[k] > UINT32_MAX || row[k] != floor(row[k]))
            return ply_error(ply, err, "edge %llu: vertex index %g", (unsigned long long)r, row[k]);
        d->edges[2 * r + (uint64_t)k] = (uint32_t)row[k];
    }
    return HK_OK;
}

static hk_Status read_body(Ply *ply, Data *d, hk_Error *err)
{
    for (int e = 0; e < ply->nelems; e++) {
        const Elem *el = &ply->elems[e];
        const uint64_t left = ply->t.size - ply->pos;
        const uint64_t need = el->count * min_record(ply, el);
        if (need > left + (ply->ascii ? 1 : 0))
            return ply_error(ply, err, "truncated: element '%s' announces %llu records (at least %llu bytes), %llu are left",
                             el->name, (unsigned long long)el->count, (unsigned long long)need,
                             (unsigned long long)left);
        int keep[MAX_PROPS];
        for (int i = 0; i < MAX_PROPS; i++) keep[i] = -1;
        double row[6];
        hk_Status st;
        if (!strcmp(el->name, "vertex")) {
            const char *names[6] = {"x", "y", "z", "red", "green", "blue"};
            int at[6];
            for (int k = 0; k < 6; k++) at[k] = prop_index(el, names[k]);
            for (int k = 0; k < 3; k++) {
                if (at[k] < 0 || el->props[at[k]].count_type) {
                    ply->line = -el->line;
                    return ply_error(ply, err, "the vertex element has no property %s", names[k]);
                }
                if (el->props[at[k]].type != T_F32 && el->props[at[k]].type != T_F64) {
                    ply->line = -el->line;
                    return ply_error(ply, err, "vertex %s is %s (float or double are read)", names[k],
                                     types[el->props[at[k]].type].name);
                }
                keep[at[k]] = k;
            }
            int colours = 1;
            for (int k = 3; k < 6; k++)
                colours &= at[k] >= 0 && !el->props[at[k]].count_type &&
                           (el->props[at[k]].type == T_U8 || el->props[at[k]].type >= T_F32);
            d->nverts = (uint32_t)el->count;
            d->have_vertex = 1;
            d->xyz = hk_alloc_array((size_t)el->count, 3 * sizeof(float), err);
            if (!d->xyz) return HK_ERR_NOMEM;
            if (colours) {
                for (int k = 3; k < 6; k++) keep[at[k]] = k;
                d->rgb = hk_alloc_array((size_t)el->count, 3 * sizeof(float), err);
                if (!d->rgb) return HK_ERR_NOMEM;
            }
            st = read_element(ply, el, keep, row, 6, store_vertex, d, err);
            if (st == HK_OK && colours && el->props[at[3]].type == T_U8)
                for (size_t i = 0; i < 3 * (size_t)el->count; i++) d->rgb[i] /= 255.0f;
        } else if (!strcmp(el->name, "strand")) {
            int at = prop_index(el, "nsegs");
            if (at < 0 && el->nprops == 1) at = 0;
            if (at < 0 || el->props[at].count_type || el->props[at].type >= T_F32) {
                ply->line = -el->line;
                return ply_error(ply, err, "the strand element has no integer property nsegs (segments per strand)");
            }
            keep[at] = 0;
            d->nstrands = (uint32_t)el->count;
            d->have_strands = 1;
            d->nsegs = hk_alloc_array((size_t)el->count, sizeof(uint32_t), err);
            if (!d->nsegs) return HK_ERR_NOMEM;
            st = read_element(ply, el, keep, row, 1, store_strand, d, err);
        } else if (!strcmp(el->name, "edge")) {
            const int a = prop_index(el, "vertex1"), b = prop_index(el, "vertex2");
            if (a < 0 || b < 0 || el->props[a].count_type || el->props[b].count_type || el->props[a].type >= T_F32 ||
                el->props[b].type >= T_F32) {
                ply->line = -el->line;
                return ply_error(ply, err, "the edge element has no integer properties vertex1 and vertex2");
            }
            keep[a] = 0, keep[b] = 1;
            d->nedges = (uint32_t)el->count;
            d->have_edges = 1;
            d->edges = hk_alloc_array((size_t)el->count, 2 * sizeof(uint32_t), err);
            if (!d->edges) return HK_ERR_NOMEM;
            st = read_element(ply, el, keep, row, 2, store_edge, d, err);
        } else {
            st = read_element(ply, el, NULL, row, 0, NULL, NULL, err);
        }
        if (st != HK_OK) return st;
    }
    /* Nothing but blanks may follow (ASCII); nothing at all (binary). */
    size_t p = ply->pos;
    if (ply->ascii)
        while (p < ply->t.size && (ply->t.data[p] == ' ' || ply->t.data[p] == '\t' || ply->t.data[p] == '\n' ||
                                   ply->t.data[p] == '\r'))
            p++;
    if (p != ply->t.size) return ply_error(ply, err, "data after the last element");
    return HK_OK;
}

/* Chains the edges into strands; order[] receives the vertices strand by strand,
 * counts[] the points of each strand. */
static hk_Status chain_edges(Ply *ply, const Data *d, uint32_t *order, uint32_t *counts, uint32_t *nstrands,
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
            st = hk_error_set(err, HK_ERR_PARSE, "%s: edge %u joins vertices %u and %u (%u vertices)", ply->t.path, e, a,
                              b, nv);
            goto done;
        }
        for (int k = 0; k < 2; k++) {
            const uint32_t v = k ? b : a;
            if (deg[v] == 2) {
                st = hk_error_set(err, HK_ERR_PARSE,
                                  "%s: edge %u gives vertex %u a third edge: strands must not branch", ply->t.path, e,
                                  v);
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
    Ply ply;
    memset(&ply, 0, sizeof ply);
    Data d;
    memset(&d, 0, sizeof d);
    uint32_t *order = NULL, *counts = NULL;
    hk_Status st = hk_textin_load(&ply.t, path, err);
    if (st != HK_OK) return st;
    st = parse_header(&ply, err);
    if (st == HK_OK) st = read_body(&ply, &d, err);
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
            st = hk_error_set(err, HK_ERR_PARSE, "%s: the strands' segment counts add up to %llu points, the file has %u vertices",
                              path, (unsigned long long)total, d.nverts);
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
    hk_textin_free(&ply.t);
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
