/* Internal helpers of the hair format readers and writers (hair_*.c): a checked binary
 * reader with file:offset messages, whole-file text buffers with file:line messages,
 * exact float32 <-> decimal text, little-endian packing and buffered writing. */
#ifndef HK_IO_HAIR_IO_H
#define HK_IO_HAIR_IO_H

#include <stdint.h>
#include <stdio.h>

#include "hairkit/core.h"
#include "hairkit/hairfile.h"
#include "io/outfile.h"

/* ---- binary input ---- */
typedef struct hk_BinIn {
    FILE *fp;
    const char *path;
    uint64_t size;   /* the file's length */
    uint64_t offset; /* of the next byte read */
} hk_BinIn;

/* Opens a regular file for reading; "path: cannot open: ..." otherwise. */
hk_Status hk_binin_open(hk_BinIn *in, const char *path, hk_Error *err);
void hk_binin_close(hk_BinIn *in);
/* "path:offset: message" (HK_ERR_PARSE), returns it. */
hk_Status hk_binin_error(const hk_BinIn *in, uint64_t offset, hk_Error *err, const char *fmt, ...) HK_PRINTF_LIKE(4, 5);
/* Reads n bytes; at the end of the file: "path:offset: truncated in WHAT (N bytes
 * needed, the file ends at SIZE)". */
hk_Status hk_binin_read(hk_BinIn *in, void *dst, size_t n, const char *what, hk_Error *err);
hk_Status hk_binin_seek(hk_BinIn *in, uint64_t offset, hk_Error *err);
/* Reads `records` records of `stride` little-endian floats and keeps the first 3 of
 * each (x, y, z) into dst[3 * records]. */
hk_Status hk_binin_read_xyz(hk_BinIn *in, float *dst, size_t records, size_t stride, const char *what, hk_Error *err);

/* ---- little-endian values ---- */
uint16_t hk_le_u16(const unsigned char *p);
uint32_t hk_le_u32(const unsigned char *p);
uint64_t hk_le_u64(const unsigned char *p);
float hk_le_f32(const unsigned char *p);
double hk_le_f64(const unsigned char *p);
void hk_put_u16(unsigned char *p, uint16_t v);
void hk_put_u32(unsigned char *p, uint32_t v);
void hk_put_f32(unsigned char *p, float f);

/* ---- output (atomic, through hk_OutFile) ---- */
typedef struct hk_Writer {
    hk_OutFile out;
    int ok; /* every write so far succeeded */
    unsigned char buf[8192];
    size_t used;
    char point; /* the C locale's decimal point character, replaced by '.' */
} hk_Writer;

hk_Status hk_writer_open(hk_Writer *w, const char *path, hk_Error *err);
void hk_writer_bytes(hk_Writer *w, const void *data, size_t n);
void hk_writer_u32(hk_Writer *w, uint32_t v);
void hk_writer_f32(hk_Writer *w, float f);
void hk_writer_printf(hk_Writer *w, const char *fmt, ...) HK_PRINTF_LIKE(2, 3);
/* The shortest decimal that reads back as f (strtof), '.' as decimal point. */
void hk_writer_float_text(hk_Writer *w, float f);
/* Flushes and renames onto the destination (or removes the temporary file and says why
 * the write failed). */
hk_Status hk_writer_commit(hk_Writer *w, hk_Error *err);
void hk_writer_abort(hk_Writer *w);

/* Into buf[32]: the shortest of %.6g .. %.9g that strtof reads back to the same bits. */
void hk_format_float(char *buf, size_t size, float f, char locale_point);
char hk_locale_point(void);

/* ---- text input ---- */
typedef struct hk_TextIn {
    const char *path;
    char *data; /* the whole file, NUL-terminated (hk_free) */
    size_t size;
    char point; /* locale decimal point, for the number parser */
} hk_TextIn;

/* Reads a whole regular file into memory. */
hk_Status hk_textin_load(hk_TextIn *t, const char *path, hk_Error *err);
void hk_textin_free(hk_TextIn *t);
/* "path:line: message" (HK_ERR_PARSE), returns it. */
hk_Status hk_textin_error(const hk_TextIn *t, long line, hk_Error *err, const char *fmt, ...) HK_PRINTF_LIKE(4, 5);

/* Decimal number token [s, s+n) ([+-]digits[.digits][e[+-]digits]) to a float, read
 * exactly (strtof); nan, inf, hex and glued text are refused: returns 0. */
int hk_parse_float(const char *s, size_t n, char locale_point, float *out);
/* Same for a double. */
int hk_parse_double(const char *s, size_t n, char locale_point, double *out);
/* A decimal integer token (optional sign) within [lo, hi]. */
int hk_parse_long(const char *s, size_t n, long long lo, long long hi, long long *out);

/* ---- checks ---- */
/* "path: point P (strand S) has a non-finite coordinate" for the first such point. */
hk_Status hk_hair_check_finite(const char *path, const hk_HairFile *h, hk_Error *err);

#endif
