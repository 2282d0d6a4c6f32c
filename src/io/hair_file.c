/* cyHair .hair files (Cem Yuksel's format, see hairfile.h): checked reading and atomic,
 * byte-exact writing, little-endian whatever the host. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "hairkit/hairfile.h"
#include "io/outfile.h"

#define HEADER_SIZE 128

void hk_hair_free(hk_HairFile *h)
{
    hk_free(h->segments);
    hk_free(h->points);
    hk_free(h->thickness);
    hk_free(h->transparency);
    hk_free(h->colors);
    hk_free(h->first_point);
    memset(h, 0, sizeof *h);
}

void hk_hair_set_info(hk_HairFile *h, const char *text)
{
    memset(h->info, 0, sizeof h->info);
    size_t n = strlen(text);
    memcpy(h->info, text, n < sizeof h->info ? n : sizeof h->info);
}

hk_Status hk_hair_index(hk_HairFile *h, hk_Error *err)
{
    /* Without a segments array the total is known from the counts alone: checked before
     * the offsets are allocated (a header of 2^31 strands and 0 points was 8 GB). */
    if (!(h->flags & HK_HAIR_SEGMENTS) &&
        (uint64_t)h->strand_count * ((uint64_t)h->default_segments + 1) != h->point_count)
        return hk_error_set(
            err, HK_ERR_PARSE, "%u strands of default segment count %u make %llu points, the header says %u",
            h->strand_count, h->default_segments,
            (unsigned long long)h->strand_count * ((unsigned long long)h->default_segments + 1), h->point_count);
    if (h->strand_count > h->point_count)
        return hk_error_set(err, HK_ERR_PARSE, "%u strands need at least as many points, the header says %u",
                            h->strand_count, h->point_count);
    hk_free(h->first_point);
    h->first_point = hk_alloc_array((size_t)h->strand_count + 1, sizeof(uint32_t), err);
    if (!h->first_point) return HK_ERR_NOMEM;
    uint64_t total = 0;
    for (uint32_t i = 0; i < h->strand_count; i++) {
        h->first_point[i] = (uint32_t)(total > UINT32_MAX ? UINT32_MAX : total);
        uint32_t seg = (h->flags & HK_HAIR_SEGMENTS) ? h->segments[i] : h->default_segments;
        total += (uint64_t)seg + 1;
    }
    if (total != h->point_count)
        return hk_error_set(err, HK_ERR_PARSE, "the strands' segment counts add up to %llu points, the header says %u",
                            (unsigned long long)total, h->point_count);
    h->first_point[h->strand_count] = h->point_count;
    return HK_OK;
}

hk_Status hk_hair_alloc(hk_HairFile *h, uint32_t strand_count, const uint32_t *points_per_strand, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    uint64_t total = 0;
    for (uint32_t i = 0; i < strand_count; i++) {
        if (points_per_strand[i] < 1 || points_per_strand[i] > 65536)
            return hk_error_set(err, HK_ERR_INVALID, "strand %u has %u points (1 to 65536 allowed)", i,
                                points_per_strand[i]);
        total += points_per_strand[i];
    }
    if (total > UINT32_MAX) return hk_error_set(err, HK_ERR_INVALID, "more than 2^32 points");
    h->strand_count = strand_count;
    h->point_count = (uint32_t)total;
    h->flags = HK_HAIR_SEGMENTS | HK_HAIR_POINTS;
    h->default_thickness = 1.0f;
    h->default_color[0] = h->default_color[1] = h->default_color[2] = 1.0f;
    h->segments = hk_alloc_array(strand_count, sizeof(uint16_t), err);
    h->points = hk_alloc_array((size_t)total, 3 * sizeof(float), err);
    if (!h->segments || !h->points) {
        hk_hair_free(h);
        return HK_ERR_NOMEM;
    }
    for (uint32_t i = 0; i < strand_count; i++) h->segments[i] = (uint16_t)(points_per_strand[i] - 1);
    hk_Status st = hk_hair_index(h, err);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

static uint32_t get_u32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

static float get_f32(const unsigned char *p)
{
    uint32_t u = get_u32(p);
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

static void put_u32(unsigned char *p, uint32_t v)
{
    p[0] = (unsigned char)v, p[1] = (unsigned char)(v >> 8), p[2] = (unsigned char)(v >> 16),
    p[3] = (unsigned char)(v >> 24);
}

static void put_f32(unsigned char *p, float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    put_u32(p, u);
}

/* Whether this machine stores numbers little-endian, as the file does: then the arrays
 * go between the file and memory in one fread / fwrite, without conversion (the hot
 * path: a million strands read in about the time stdio takes to move the bytes). */
static int host_little_endian(void)
{
    const uint16_t one = 1;
    unsigned char b;
    memcpy(&b, &one, 1);
    return b == 1;
}

/* Reads `count` little-endian 32-bit floats (or 16-bit integers when `u16`). */
static hk_Status read_array(FILE *fp, void *dst, size_t count, int u16, const char *path, const char *what,
                            hk_Error *err)
{
    const size_t item = u16 ? 2 : 4;
    if (host_little_endian()) {
        if (fread(dst, item, count, fp) != count)
            return hk_error_set(err, HK_ERR_PARSE, "%s: truncated in the %s array", path, what);
        return HK_OK;
    }
    unsigned char buf[4096];
    size_t done = 0;
    while (done < count) {
        size_t n = count - done;
        if (n > sizeof buf / item) n = sizeof buf / item;
        if (fread(buf, item, n, fp) != n)
            return hk_error_set(err, HK_ERR_PARSE, "%s: truncated in the %s array", path, what);
        for (size_t i = 0; i < n; i++) {
            if (u16)
                ((uint16_t *)dst)[done + i] = (uint16_t)(buf[2 * i] | buf[2 * i + 1] << 8);
            else
                ((float *)dst)[done + i] = get_f32(buf + 4 * i);
        }
        done += n;
    }
    return HK_OK;
}

/* The index of the first non-finite float of p[0..n), or n: whole blocks are tested
 * without a branch (exponent bits all set means inf or nan), so that the loop
 * vectorises. */
static size_t first_non_finite(const float *p, size_t n)
{
    size_t i = 0;
    while (i < n) {
        const size_t end = n - i > 4096 ? i + 4096 : n;
        uint32_t bad = 0;
        for (size_t k = i; k < end; k++) {
            uint32_t u;
            memcpy(&u, p + k, sizeof u);
            bad |= (uint32_t)((u & 0x7f800000u) == 0x7f800000u);
        }
        if (bad)
            for (size_t k = i; k < end; k++)
                if (!isfinite(p[k])) return k;
        i = end;
    }
    return n;
}

hk_Status hk_hair_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    FILE *fp = fopen(path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(fp), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_IO, "%s: not a regular file", path);
    }
    unsigned char head[HEADER_SIZE];
    if (fread(head, 1, HEADER_SIZE, fp) != HEADER_SIZE) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_PARSE, "%s: too short for a .hair file (%lld bytes, header is 128)", path,
                            (long long)sb.st_size);
    }
    if (memcmp(head, "HAIR", 4) != 0) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_PARSE, "%s: not a .hair file (no HAIR signature)", path);
    }
    h->strand_count = get_u32(head + 4);
    h->point_count = get_u32(head + 8);
    h->flags = get_u32(head + 12);
    h->default_segments = get_u32(head + 16);
    h->default_thickness = get_f32(head + 20);
    h->default_transparency = get_f32(head + 24);
    for (int i = 0; i < 3; i++) h->default_color[i] = get_f32(head + 28 + 4 * i);
    memcpy(h->info, head + 40, HK_HAIR_INFO_SIZE);

    hk_Status st = HK_OK;
    /* Every count of the header is checked against the file's size, and against the
     * others, before anything is allocated: a lying header is refused at once, with the
     * field that is wrong. Each strand has at least one point (12 bytes) and, with the
     * segments array, its 2-byte count. */
    const uint64_t ns = h->strand_count, np = h->point_count, size = (uint64_t)sb.st_size;
    const int seg = (h->flags & HK_HAIR_SEGMENTS) != 0;
    uint64_t per_point = 12;
    if (h->flags & HK_HAIR_THICKNESS) per_point += 4;
    if (h->flags & HK_HAIR_TRANSPARENCY) per_point += 4;
    if (h->flags & HK_HAIR_COLORS) per_point += 12;
    const uint64_t need_strands = HEADER_SIZE + ns * (seg ? 2 + per_point : per_point);
    const uint64_t need = HEADER_SIZE + (seg ? 2 * ns : 0) + per_point * np;
    if (!(h->flags & HK_HAIR_POINTS))
        st = hk_error_set(err, HK_ERR_PARSE, "%s: the file has no points array (flags 0x%x)", path, h->flags);
    else if (h->flags & ~0x1Fu)
        st = hk_error_set(err, HK_ERR_PARSE, "%s: unknown flags 0x%x in the header", path, h->flags);
    else if (need_strands > size)
        st = hk_error_set(err, HK_ERR_PARSE,
                          "%s: strand count %u in the header needs at least %llu bytes but the file has %lld "
                          "(a wrong header, or a truncated file)",
                          path, h->strand_count, (unsigned long long)need_strands, (long long)sb.st_size);
    else if (need > size)
        st = hk_error_set(err, HK_ERR_PARSE,
                          "%s: point count %u in the header needs %llu bytes (with %u strands, flags 0x%x) but the "
                          "file has %lld (a wrong header, or a truncated file)",
                          path, h->point_count, (unsigned long long)need, h->strand_count, h->flags,
                          (long long)sb.st_size);
    else if (!seg && (uint64_t)h->default_segments + 1 > 65536)
        st = hk_error_set(err, HK_ERR_PARSE, "%s: default segment count %u is absurd", path, h->default_segments);
    else if (!seg && ns * ((uint64_t)h->default_segments + 1) != np)
        st = hk_error_set(err, HK_ERR_PARSE,
                          "%s: %u strands of default segment count %u in the header make %llu points, its point count "
                          "says %u",
                          path, h->strand_count, h->default_segments,
                          (unsigned long long)(ns * ((uint64_t)h->default_segments + 1)), h->point_count);
    else if (ns > np)
        st = hk_error_set(err, HK_ERR_PARSE,
                          "%s: strand count %u in the header is more than its point count %u (a strand has at least "
                          "one point)",
                          path, h->strand_count, h->point_count);
    else {
        /* The arrays, the offsets hk_hair_index adds, within the memory budget. */
        char what[160];
        snprintf(what, sizeof what, "%s (%u strands, %u points)", path, h->strand_count, h->point_count);
        st = hk_memory_check((double)(need - HEADER_SIZE) + 4.0 * ((double)ns + 1.0), what, err);
    }
    if (st == HK_OK) {
        if (h->flags & HK_HAIR_SEGMENTS) {
            h->segments = hk_alloc_array((size_t)ns, sizeof(uint16_t), err);
            st = h->segments ? read_array(fp, h->segments, (size_t)ns, 1, path, "segments", err) : HK_ERR_NOMEM;
        }
        const struct {
            uint32_t flag;
            float **dst;
            size_t per_point;
            const char *name;
        } arrays[4] = {{HK_HAIR_POINTS, &h->points, 3, "points"},
                       {HK_HAIR_THICKNESS, &h->thickness, 1, "thickness"},
                       {HK_HAIR_TRANSPARENCY, &h->transparency, 1, "transparency"},
                       {HK_HAIR_COLORS, &h->colors, 3, "colours"}};
        for (int a = 0; a < 4 && st == HK_OK; a++) {
            if (!(h->flags & arrays[a].flag)) continue;
            *arrays[a].dst = hk_alloc_array((size_t)np, arrays[a].per_point * sizeof(float), err);
            st = *arrays[a].dst
                     ? read_array(fp, *arrays[a].dst, (size_t)np * arrays[a].per_point, 0, path, arrays[a].name, err)
                     : HK_ERR_NOMEM;
        }
    }
    fclose(fp);
    if (st == HK_OK) {
        hk_Error sub;
        st = hk_hair_index(h, &sub);
        if (st != HK_OK) hk_error_set(err, st, "%s: %s", path, sub.message);
    }
    if (st == HK_OK && h->points) {
        const size_t i = first_non_finite(h->points, (size_t)(3 * np));
        if (i < 3 * np)
            st = hk_error_set(err, HK_ERR_PARSE, "%s: point %llu has a non-finite coordinate", path,
                              (unsigned long long)(i / 3));
    }
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

static int write_floats(FILE *fp, const float *src, size_t count)
{
    if (host_little_endian()) return fwrite(src, 4, count, fp) == count;
    unsigned char buf[4096];
    size_t done = 0;
    while (done < count) {
        size_t n = count - done;
        if (n > sizeof buf / 4) n = sizeof buf / 4;
        for (size_t i = 0; i < n; i++) put_f32(buf + 4 * i, src[done + i]);
        if (fwrite(buf, 4, n, fp) != n) return 0;
        done += n;
    }
    return 1;
}

static int write_u16(FILE *fp, const uint16_t *src, size_t count)
{
    if (host_little_endian()) return fwrite(src, 2, count, fp) == count;
    unsigned char buf[4096];
    size_t done = 0;
    while (done < count) {
        size_t n = count - done;
        if (n > sizeof buf / 2) n = sizeof buf / 2;
        for (size_t i = 0; i < n; i++)
            buf[2 * i] = (unsigned char)src[done + i], buf[2 * i + 1] = (unsigned char)(src[done + i] >> 8);
        if (fwrite(buf, 2, n, fp) != n) return 0;
        done += n;
    }
    return 1;
}

hk_Status hk_hair_save(const char *path, const hk_HairFile *h, hk_Error *err)
{
    if (((h->flags & HK_HAIR_SEGMENTS) && !h->segments) || !(h->flags & HK_HAIR_POINTS) || !h->points ||
        ((h->flags & HK_HAIR_THICKNESS) && !h->thickness) || ((h->flags & HK_HAIR_TRANSPARENCY) && !h->transparency) ||
        ((h->flags & HK_HAIR_COLORS) && !h->colors))
        return hk_error_set(err, HK_ERR_INVALID, "%s: hair data lacks an array its flags announce", path);
    hk_OutFile out;
    hk_Status st = hk_outfile_open(&out, path, err);
    if (st != HK_OK) return st;
    unsigned char head[HEADER_SIZE];
    memcpy(head, "HAIR", 4);
    put_u32(head + 4, h->strand_count);
    put_u32(head + 8, h->point_count);
    put_u32(head + 12, h->flags);
    put_u32(head + 16, h->default_segments);
    put_f32(head + 20, h->default_thickness);
    put_f32(head + 24, h->default_transparency);
    for (int i = 0; i < 3; i++) put_f32(head + 28 + 4 * i, h->default_color[i]);
    memcpy(head + 40, h->info, HK_HAIR_INFO_SIZE);
    int ok = fwrite(head, 1, HEADER_SIZE, out.fp) == HEADER_SIZE;
    if (ok && (h->flags & HK_HAIR_SEGMENTS)) ok = write_u16(out.fp, h->segments, h->strand_count);
    const size_t np = h->point_count;
    if (ok) ok = write_floats(out.fp, h->points, 3 * np);
    if (ok && (h->flags & HK_HAIR_THICKNESS)) ok = write_floats(out.fp, h->thickness, np);
    if (ok && (h->flags & HK_HAIR_TRANSPARENCY)) ok = write_floats(out.fp, h->transparency, np);
    if (ok && (h->flags & HK_HAIR_COLORS)) ok = write_floats(out.fp, h->colors, 3 * np);
    if (!ok) {
        hk_outfile_abort(&out);
        return hk_error_set(err, HK_ERR_IO, "%s: write failed: %s", path, strerror(errno));
    }
    return hk_outfile_commit(&out, err);
}
