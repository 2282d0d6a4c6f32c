/* Helpers of the hair format readers and writers (see hair_io.h). */
#include "hair_io.h"

#include <errno.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/keyfile.h"

/* ---- binary input ---- */

hk_Status hk_binin_open(hk_BinIn *in, const char *path, hk_Error *err)
{
    memset(in, 0, sizeof *in);
    in->path = path;
    in->fp = fopen(path, "rb");
    if (!in->fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(in->fp), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        hk_binin_close(in);
        return hk_error_set(err, HK_ERR_IO, "%s: not a regular file", path);
    }
    in->size = (uint64_t)sb.st_size;
    return HK_OK;
}

void hk_binin_close(hk_BinIn *in)
{
    if (in->fp) fclose(in->fp);
    in->fp = NULL;
}

hk_Status hk_binin_error(const hk_BinIn *in, uint64_t offset, hk_Error *err, const char *fmt, ...)
{
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return hk_error_set(err, HK_ERR_PARSE, "%s:%llu: %s", in->path, (unsigned long long)offset, msg);
}

hk_Status hk_binin_read(hk_BinIn *in, void *dst, size_t n, const char *what, hk_Error *err)
{
    if (n > in->size || in->offset > in->size - n)
        return hk_binin_error(in, in->offset, err, "truncated in %s (%zu bytes needed, the file ends at %llu)", what, n,
                              (unsigned long long)in->size);
    if (fread(dst, 1, n, in->fp) != n)
        return hk_error_set(err, HK_ERR_IO, "%s:%llu: read error in %s", in->path, (unsigned long long)in->offset,
                            what);
    in->offset += n;
    return HK_OK;
}

hk_Status hk_binin_seek(hk_BinIn *in, uint64_t offset, hk_Error *err)
{
    if (offset > in->size)
        return hk_binin_error(in, in->offset, err, "offset %llu is past the end of the file (%llu bytes)",
                              (unsigned long long)offset, (unsigned long long)in->size);
    if (offset > (uint64_t)INT64_MAX / 2 || fseeko(in->fp, (off_t)offset, SEEK_SET) != 0)
        return hk_error_set(err, HK_ERR_IO, "%s: cannot seek to %llu", in->path, (unsigned long long)offset);
    in->offset = offset;
    return HK_OK;
}

hk_Status hk_binin_read_xyz(hk_BinIn *in, float *dst, size_t records, size_t stride, const char *what, hk_Error *err)
{
    unsigned char buf[8192];
    const size_t rec = 4 * stride, per = sizeof buf / rec;
    for (size_t done = 0; done < records;) {
        size_t n = records - done < per ? records - done : per;
        hk_Status st = hk_binin_read(in, buf, n * rec, what, err);
        if (st != HK_OK) return st;
        for (size_t i = 0; i < n; i++)
            for (size_t k = 0; k < 3; k++) dst[3 * (done + i) + k] = hk_le_f32(buf + i * rec + 4 * k);
        done += n;
    }
    return HK_OK;
}

/* ---- little-endian values ---- */

uint16_t hk_le_u16(const unsigned char *p) { return (uint16_t)(p[0] | p[1] << 8); }

uint32_t hk_le_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

uint64_t hk_le_u64(const unsigned char *p) { return (uint64_t)hk_le_u32(p) | (uint64_t)hk_le_u32(p + 4) << 32; }

float hk_le_f32(const unsigned char *p)
{
    uint32_t u = hk_le_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

double hk_le_f64(const unsigned char *p)
{
    uint64_t u = hk_le_u64(p);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

void hk_put_u16(unsigned char *p, uint16_t v)
{
    p[0] = (unsigned char)v;
    p[1] = (unsigned char)(v >> 8);
}

void hk_put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++) p[i] = (unsigned char)(v >> (8 * i));
}

void hk_put_f32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    hk_put_u32(p, u);
}

/* ---- output ---- */

char hk_locale_point(void)
{
    const char *p = localeconv()->decimal_point;
    return p && p[0] && !p[1] ? p[0] : '.';
}

hk_Status hk_writer_open(hk_Writer *w, const char *path, hk_Error *err)
{
    w->used = 0;
    w->ok = 1;
    w->point = hk_locale_point();
    return hk_outfile_open(&w->out, path, err);
}

static void writer_flush(hk_Writer *w)
{
    if (w->used && w->ok && fwrite(w->buf, 1, w->used, w->out.fp) != w->used) w->ok = 0;
    w->used = 0;
}

void hk_writer_bytes(hk_Writer *w, const void *data, size_t n)
{
    const unsigned char *p = data;
    while (n) {
        if (w->used == sizeof w->buf) writer_flush(w);
        size_t k = sizeof w->buf - w->used;
        if (k > n) k = n;
        memcpy(w->buf + w->used, p, k);
        w->used += k, p += k, n -= k;
    }
}

void hk_writer_u32(hk_Writer *w, uint32_t v)
{
    unsigned char b[4];
    hk_put_u32(b, v);
    hk_writer_bytes(w, b, 4);
}

void hk_writer_f32(hk_Writer *w, float f)
{
    unsigned char b[4];
    hk_put_f32(b, f);
    hk_writer_bytes(w, b, 4);
}

void hk_writer_printf(hk_Writer *w, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= sizeof line) {
        w->ok = 0;
        return;
    }
    hk_writer_bytes(w, line, (size_t)n);
}

static float read_back(const char *text, char point)
{
    char local[48];
    size_t n = strlen(text);
    if (n >= sizeof local) return NAN;
    memcpy(local, text, n + 1);
    if (point != '.') {
        char *dot = strchr(local, '.');
        if (dot) *dot = point;
    }
    return strtof(local, NULL);
}

void hk_format_float(char *buf, size_t size, float f, char point)
{
    for (int prec = 6; prec <= 9; prec++) {
        snprintf(buf, size, "%.*g", prec, (double)f);
        if (point != '.') {
            char *c = strchr(buf, point);
            if (c) *c = '.';
        }
        float back = read_back(buf, point);
        if (memcmp(&back, &f, sizeof f) == 0) return;
    }
}

void hk_writer_float_text(hk_Writer *w, float f)
{
    char buf[48];
    hk_format_float(buf, sizeof buf, f, w->point);
    hk_writer_bytes(w, buf, strlen(buf));
}

hk_Status hk_writer_commit(hk_Writer *w, hk_Error *err)
{
    writer_flush(w);
    if (!w->ok) {
        const int e = errno;
        const char *path = w->out.path ? w->out.path : "?";
        hk_error_set(err, HK_ERR_IO, "%s: write failed: %s", path, e ? strerror(e) : "output error");
        hk_outfile_abort(&w->out);
        return HK_ERR_IO;
    }
    return hk_outfile_commit(&w->out, err);
}

void hk_writer_abort(hk_Writer *w) { hk_outfile_abort(&w->out); }

/* ---- text input ---- */

hk_Status hk_textin_load(hk_TextIn *t, const char *path, hk_Error *err)
{
    memset(t, 0, sizeof *t);
    t->path = path;
    t->point = hk_locale_point();
    hk_BinIn in;
    hk_Status st = hk_binin_open(&in, path, err);
    if (st != HK_OK) return st;
    if (in.size > HK_MAX_ALLOCATION - 1) {
        hk_binin_close(&in);
        return hk_error_set(err, HK_ERR_NOMEM, "%s: too large (%llu bytes)", path, (unsigned long long)in.size);
    }
    t->data = hk_alloc_array((size_t)in.size + 1, 1, err);
    if (!t->data) {
        hk_binin_close(&in);
        return HK_ERR_NOMEM;
    }
    st = hk_binin_read(&in, t->data, (size_t)in.size, "the file", err);
    hk_binin_close(&in);
    if (st != HK_OK) {
        hk_textin_free(t);
        return st;
    }
    t->data[in.size] = '\0';
    t->size = (size_t)in.size;
    return HK_OK;
}

void hk_textin_free(hk_TextIn *t)
{
    hk_free(t->data);
    t->data = NULL;
    t->size = 0;
}

hk_Status hk_textin_error(const hk_TextIn *t, long line, hk_Error *err, const char *fmt, ...)
{
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (line > 0) return hk_error_set(err, HK_ERR_PARSE, "%s:%ld: %s", t->path, line, msg);
    return hk_error_set(err, HK_ERR_PARSE, "%s: %s", t->path, msg);
}

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* Checks the decimal syntax (keyfile.c) and copies the token into local[] with the locale's point. */
static int decimal_token(const char *s, size_t n, char point, char *local, size_t cap)
{
    if (n == 0 || n >= cap) return 0;
    if (!hk_decimal_syntax(s, n)) return 0;
    memcpy(local, s, n);
    local[n] = '\0';
    if (point != '.') {
        char *dot = strchr(local, '.');
        if (dot) *dot = point;
    }
    return 1;
}

int hk_parse_float(const char *s, size_t n, char point, float *out)
{
    char local[128];
    if (!decimal_token(s, n, point, local, sizeof local)) return 0;
    char *end;
    float v = strtof(local, &end);
    if (*end != '\0' || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int hk_parse_double(const char *s, size_t n, char point, double *out)
{
    char local[128];
    if (!decimal_token(s, n, point, local, sizeof local)) return 0;
    char *end;
    double v = strtod(local, &end);
    if (*end != '\0' || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

int hk_parse_long(const char *s, size_t n, long long lo, long long hi, long long *out)
{
    size_t i = 0;
    int neg = 0;
    if (n && (s[0] == '+' || s[0] == '-')) neg = s[0] == '-', i++;
    if (i == n) return 0;
    unsigned long long v = 0;
    for (; i < n; i++) {
        if (!is_digit(s[i])) return 0;
        if (v > 1000000000000000000ull) return 0;
        v = 10 * v + (unsigned long long)(s[i] - '0');
    }
    if (v > 1000000000000000000ull) return 0;
    long long r = neg ? -(long long)v : (long long)v;
    if (r < lo || r > hi) return 0;
    *out = r;
    return 1;
}

hk_Status hk_hair_check_finite(const char *path, const hk_HairFile *h, hk_Error *err)
{
    for (uint64_t i = 0; i < 3 * (uint64_t)h->point_count; i++)
        if (!isfinite(h->points[i])) {
            const uint32_t p = (uint32_t)(i / 3);
            uint32_t s = 0;
            if (h->first_point)
                while (s + 1 < h->strand_count && h->first_point[s + 1] <= p) s++;
            return hk_error_set(err, HK_ERR_PARSE, "%s: point %u (strand %u) has a non-finite coordinate", path, p, s);
        }
    return HK_OK;
}
