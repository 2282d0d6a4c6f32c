/* The PLY reader shared by the strand and mesh readers (ply.h): the header parsed into
 * elements and properties, the body read value by value (binary little-endian or
 * ASCII), every count checked against the file's size before anything is allocated. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "ply.h"

const hk_PlyType hk_ply_types[HK_PLY_F64 + 1] = {
    {"", "", 0},           {"char", "int8", 1},     {"uchar", "uint8", 1},
    {"short", "int16", 2}, {"ushort", "uint16", 2}, {"int", "int32", 4},
    {"uint", "uint32", 4}, {"float", "float32", 4}, {"double", "float64", 8}};

/* file:line (ASCII body, header) or file:offset (binary body) */
hk_Status hk_ply_error(const hk_Ply *ply, hk_Error *err, const char *fmt, ...)
{
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (ply->ascii || ply->line < 0)
        return hk_textin_error(&ply->t, ply->line < 0 ? -ply->line : ply->line, err, "%s", msg);
    return hk_error_set(err, HK_ERR_PARSE, "%s:%zu: %s", ply->t.path, ply->pos, msg);
}

static int type_of(const char *name)
{
    for (int i = 1; i <= HK_PLY_F64; i++)
        if (!strcmp(name, hk_ply_types[i].name) || !strcmp(name, hk_ply_types[i].alias)) return i;
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

static hk_Status parse_header(hk_Ply *ply, hk_Error *err)
{
    char *d = ply->t.data;
    const size_t size = ply->t.size;
    size_t pos = 0;
    long line = 0;
    int have_format = 0;
    if (size < 4 || memcmp(d, "ply", 3) != 0 || (d[3] != '\n' && d[3] != '\r')) {
        ply->line = -1;
        return hk_ply_error(ply, err, "not a PLY file (no 'ply' line)");
    }
    for (;;) {
        if (pos >= size) {
            ply->line = -(line + 1);
            return hk_ply_error(ply, err, "the header has no end_header line");
        }
        line++;
        size_t end = pos;
        while (end < size && d[end] != '\n' && d[end] != '\r') end++;
        if (end == size) {
            ply->line = -line;
            return hk_ply_error(ply, err, "the header has no end_header line");
        }
        const size_t next = end + (d[end] == '\r' && end + 1 < size && d[end + 1] == '\n' ? 2 : 1);
        for (size_t i = pos; i < end; i++)
            if ((unsigned char)d[i] < 0x20 && d[i] != '\t') {
                ply->line = -line;
                return hk_ply_error(ply, err, "binary data in the header (not a PLY file?)");
            }
        char buf[512];
        if (end - pos >= sizeof buf) {
            ply->line = -line;
            return hk_ply_error(ply, err, "header line too long");
        }
        memcpy(buf, d + pos, end - pos);
        buf[end - pos] = '\0';
        pos = next;
        ply->line = -line;
        char *tok[8];
        const int n = split(buf, tok, 7);
        if (line == 1) {
            if (n != 1 || strcmp(tok[0], "ply")) return hk_ply_error(ply, err, "not a PLY file (no 'ply' line)");
            continue;
        }
        if (n == 0) continue;
        if (!strcmp(tok[0], "comment") || !strcmp(tok[0], "obj_info")) continue;
        if (!strcmp(tok[0], "format")) {
            if (n != 3 || have_format) return hk_ply_error(ply, err, "malformed format line");
            if (!strcmp(tok[1], "ascii"))
                ply->ascii = 1;
            else if (!strcmp(tok[1], "binary_little_endian"))
                ply->ascii = 0;
            else if (!strcmp(tok[1], "binary_big_endian"))
                return hk_ply_error(ply, err, "big-endian PLY is not read (binary_little_endian and ascii are)");
            else
                return hk_ply_error(ply, err, "unknown format '%s'", tok[1]);
            if (strcmp(tok[2], "1.0")) return hk_ply_error(ply, err, "PLY version '%s' (1.0 is read)", tok[2]);
            have_format = 1;
            continue;
        }
        if (!strcmp(tok[0], "element")) {
            long long count;
            if (n != 3 || !hk_parse_long(tok[2], strlen(tok[2]), 0, (long long)UINT32_MAX, &count))
                return hk_ply_error(ply, err, "malformed element line (element NAME COUNT, COUNT < 2^32)");
            if (ply->nelems == HK_PLY_MAX_ELEMS)
                return hk_ply_error(ply, err, "more than %d elements", HK_PLY_MAX_ELEMS);
            if (strlen(tok[1]) >= HK_PLY_NAME_SIZE) return hk_ply_error(ply, err, "element name too long");
            for (int e = 0; e < ply->nelems; e++)
                if (!strcmp(ply->elems[e].name, tok[1]))
                    return hk_ply_error(ply, err, "element '%s' given twice", tok[1]);
            hk_PlyElem *el = &ply->elems[ply->nelems++];
            memset(el, 0, sizeof *el);
            strcpy(el->name, tok[1]);
            el->count = (uint64_t)count;
            el->line = line;
            continue;
        }
        if (!strcmp(tok[0], "property")) {
            if (!ply->nelems) return hk_ply_error(ply, err, "property before any element");
            hk_PlyElem *el = &ply->elems[ply->nelems - 1];
            if (el->nprops == HK_PLY_MAX_PROPS)
                return hk_ply_error(ply, err, "more than %d properties", HK_PLY_MAX_PROPS);
            hk_PlyProp p;
            memset(&p, 0, sizeof p);
            const char *name;
            if (n == 5 && !strcmp(tok[1], "list")) {
                p.count_type = type_of(tok[2]);
                p.type = type_of(tok[3]);
                if (!p.count_type || p.count_type >= HK_PLY_F32 || !p.type)
                    return hk_ply_error(ply, err, "unknown or non-integer list type in '%s %s'", tok[2], tok[3]);
                name = tok[4];
            } else if (n == 3) {
                p.type = type_of(tok[1]);
                if (!p.type) return hk_ply_error(ply, err, "unknown property type '%s'", tok[1]);
                name = tok[2];
            } else {
                return hk_ply_error(ply, err, "malformed property line");
            }
            if (strlen(name) >= HK_PLY_NAME_SIZE) return hk_ply_error(ply, err, "property name too long");
            for (int i = 0; i < el->nprops; i++)
                if (!strcmp(el->props[i].name, name)) return hk_ply_error(ply, err, "property '%s' given twice", name);
            strcpy(p.name, name);
            el->props[el->nprops++] = p;
            continue;
        }
        if (!strcmp(tok[0], "end_header")) {
            if (n != 1) return hk_ply_error(ply, err, "malformed end_header line");
            if (!have_format) return hk_ply_error(ply, err, "no format line in the header");
            ply->pos = pos;
            ply->line = line + 1;
            return HK_OK;
        }
        return hk_ply_error(ply, err, "unknown header line '%s'", tok[0]);
    }
}

hk_Status hk_ply_read_value(hk_Ply *ply, int type, double *out, const char *what, hk_Error *err)
{
    const char *d = ply->t.data;
    const size_t size = ply->t.size;
    if (!ply->ascii) {
        const size_t n = (size_t)hk_ply_types[type].size;
        if (ply->pos > size || size - ply->pos < n)
            return hk_ply_error(ply, err, "truncated in %s (the file ends at %zu)", what, size);
        const unsigned char *p = (const unsigned char *)d + ply->pos;
        switch (type) {
        case HK_PLY_I8:
            *out = (double)(int8_t)p[0];
            break;
        case HK_PLY_U8:
            *out = (double)p[0];
            break;
        case HK_PLY_I16:
            *out = (double)(int16_t)hk_le_u16(p);
            break;
        case HK_PLY_U16:
            *out = (double)hk_le_u16(p);
            break;
        case HK_PLY_I32:
            *out = (double)(int32_t)hk_le_u32(p);
            break;
        case HK_PLY_U32:
            *out = (double)hk_le_u32(p);
            break;
        case HK_PLY_F32:
            *out = (double)hk_le_f32(p);
            break;
        default:
            *out = hk_le_f64(p);
            break;
        }
        if (!isfinite(*out)) return hk_ply_error(ply, err, "non-finite number in %s", what);
        ply->pos += n;
        return HK_OK;
    }
    size_t p = ply->pos;
    while (p < size && (d[p] == ' ' || d[p] == '\t' || d[p] == '\n' || d[p] == '\r')) {
        if (d[p] == '\n' || (d[p] == '\r' && (p + 1 >= size || d[p + 1] != '\n'))) ply->line++;
        p++;
    }
    ply->pos = p;
    if (p >= size) return hk_ply_error(ply, err, "truncated in %s (the file ends)", what);
    size_t e = p;
    while (e < size && d[e] != ' ' && d[e] != '\t' && d[e] != '\n' && d[e] != '\r') e++;
    int ok;
    if (type == HK_PLY_F32) {
        float f;
        ok = hk_parse_float(d + p, e - p, ply->t.point, &f);
        *out = (double)f;
    } else if (type == HK_PLY_F64) {
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
        return hk_ply_error(ply, err, "'%s' is not a %s in %s", tok, hk_ply_types[type].name, what);
    }
    ply->pos = e;
    return HK_OK;
}

uint64_t hk_ply_min_record(const hk_Ply *ply, const hk_PlyElem *el, uint64_t min_items)
{
    uint64_t n = 0;
    for (int i = 0; i < el->nprops; i++) {
        const hk_PlyProp *p = &el->props[i];
        if (ply->ascii)
            n += p->count_type ? 2 + 2 * min_items : 2;
        else if (p->count_type)
            n += (uint64_t)hk_ply_types[p->count_type].size + min_items * (uint64_t)hk_ply_types[p->type].size;
        else
            n += (uint64_t)hk_ply_types[p->type].size;
    }
    return n;
}

int hk_ply_prop_index(const hk_PlyElem *el, const char *name)
{
    for (int i = 0; i < el->nprops; i++)
        if (!strcmp(el->props[i].name, name)) return i;
    return -1;
}

hk_Status hk_ply_read_element(hk_Ply *ply, const hk_PlyElem *el, const int *keep, double *row, int ncol,
                              hk_PlyStoreFn store, void *user, hk_Error *err)
{
    char what[HK_PLY_NAME_SIZE + 48];
    for (uint64_t r = 0; r < el->count; r++) {
        for (int c = 0; c < ncol; c++) row[c] = 0.0;
        snprintf(what, sizeof what, "%s %llu", el->name, (unsigned long long)r);
        for (int i = 0; i < el->nprops; i++) {
            const hk_PlyProp *p = &el->props[i];
            double v;
            if (p->count_type) {
                hk_Status st = hk_ply_read_value(ply, p->count_type, &v, what, err);
                if (st != HK_OK) return st;
                if (v < 0 || v > 1e9) return hk_ply_error(ply, err, "list of %g items in %s", v, what);
                for (uint64_t k = 0; k < (uint64_t)v; k++) {
                    double skip;
                    st = hk_ply_read_value(ply, p->type, &skip, what, err);
                    if (st != HK_OK) return st;
                }
                continue;
            }
            hk_Status st = hk_ply_read_value(ply, p->type, &v, what, err);
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
hk_Status hk_ply_elem_error(hk_Ply *ply, const hk_PlyElem *el, hk_Error *err, const char *fmt, ...)
{
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    ply->line = -el->line;
    return hk_ply_error(ply, err, "%s", msg);
}

hk_Status hk_ply_check_room(hk_Ply *ply, const hk_PlyElem *el, uint64_t min_items, hk_Error *err)
{
    const uint64_t left = ply->t.size - ply->pos;
    const uint64_t rec = hk_ply_min_record(ply, el, min_items);
    /* rec * count without overflow: counts are < 2^32 and records small */
    const uint64_t need = el->count * rec;
    if (need > left + (ply->ascii ? 1 : 0))
        return hk_ply_error(
            ply, err, "truncated: element '%s' announces %llu records (at least %llu bytes), %llu are left", el->name,
            (unsigned long long)el->count, (unsigned long long)need, (unsigned long long)left);
    return HK_OK;
}

hk_Status hk_ply_check_end(hk_Ply *ply, hk_Error *err)
{
    size_t p = ply->pos;
    if (ply->ascii)
        while (p < ply->t.size &&
               (ply->t.data[p] == ' ' || ply->t.data[p] == '\t' || ply->t.data[p] == '\n' || ply->t.data[p] == '\r'))
            p++;
    if (p != ply->t.size) return hk_ply_error(ply, err, "data after the last element");
    return HK_OK;
}

hk_Status hk_ply_open(hk_Ply *ply, const char *path, hk_Error *err)
{
    memset(ply, 0, sizeof *ply);
    hk_Status st = hk_textin_load(&ply->t, path, err);
    if (st != HK_OK) return st;
    st = parse_header(ply, err);
    if (st != HK_OK) hk_ply_close(ply);
    return st;
}

void hk_ply_close(hk_Ply *ply) { hk_textin_free(&ply->t); }
