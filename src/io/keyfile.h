/* Reader for the thesis's `Key value...` text files (Lansink 2010 §4.2.1, Appendix B):
 * one entry per line, `#` starts a comment outside double quotes, values separated by
 * blanks or tabs, "a value with blanks" in double quotes. Used for the hairstyle,
 * collision, setup and visuality files; every message names the file and the line. */
#ifndef HK_IO_KEYFILE_H
#define HK_IO_KEYFILE_H

#include "hairkit/core.h"

typedef struct hk_KeyLine {
    int line;            /* 1-based line number in the file */
    const char *key;     /* first token */
    int count;           /* number of values after the key */
    const char **values; /* the values, quotes removed */
} hk_KeyLine;

typedef struct hk_KeyFile {
    char *path;        /* as given to hk_keyfile_read */
    char *text;        /* file contents, cut into tokens in place */
    hk_KeyLine *lines; /* lines with at least one token, in file order */
    int line_count;
    const char **tokens; /* storage behind every line's key and values */
} hk_KeyFile;

/* Reads and tokenises a whole file. Lines end with \n, \r\n or a lone \r; the last
 * needs no line end; a UTF-8 byte-order mark is skipped. Refuses, with "path: ..."
 * or "path:line: ..." messages: a missing or unreadable file and anything that is not
 * a regular file (HK_ERR_IO); an empty file, one larger than HK_MAX_INPUT_FILE_BYTES,
 * binary content (NUL or other control bytes), an unterminated double quote and a
 * quote glued to other text (HK_ERR_PARSE). On error kf holds nothing to free. */
hk_Status hk_keyfile_read(const char *path, hk_KeyFile *kf, hk_Error *err);

/* The same with another size limit (bytes): for the
 * files hairkit writes itself whose size grows with the hair (imported guides). */
hk_Status hk_keyfile_read_limited(const char *path, long max_bytes, hk_KeyFile *kf, hk_Error *err);

/* Releases what hk_keyfile_read allocated; safe on a zeroed or freed kf. */
void hk_keyfile_free(hk_KeyFile *kf);

/* "path:line: message" (or "path: message" when line <= 0); returns code. */
hk_Status hk_keyfile_error(const hk_KeyFile *kf, int line, hk_Status code, hk_Error *err, const char *fmt, ...)
    HK_PRINTF_LIKE(5, 6);

/* ASCII case-insensitive comparison of two keys (locale-independent): 1 if equal. */
int hk_key_equal(const char *a, const char *b);

/* One key a file may contain. */
typedef struct hk_KeySpec {
    const char *name;  /* canonical spelling, used in messages */
    const char *alias; /* another accepted spelling, or NULL */
    int required;      /* nonzero: the file must give it */
} hk_KeySpec;

/* Index of the spec whose name or alias equals key (any case), or -1. */
int hk_keyspec_find(const hk_KeySpec *specs, int spec_count, const char *key);

/* Checks every line's key against specs: "unknown key 'Foo'" and "duplicate key
 * 'Young' (first given at line 12)" at the offending line, then "missing required
 * key 'Young'" (HK_ERR_PARSE). `kind` ("hairstyle", ...; may be NULL) is named in the
 * unknown-key message. line_of[spec_count] receives the line giving each key, 0 when
 * absent. */
hk_Status hk_keyfile_check_keys(const hk_KeyFile *kf, const hk_KeySpec *specs, int spec_count, const char *kind,
                                int *line_of, hk_Error *err);

/* Exactly `count` finite numbers after the key: "expected 3 numbers after 'Sphere',
 * got 2" (HK_ERR_PARSE). Numbers are decimal ([+-]digits[.digits][e[+-]digits]),
 * whatever the C locale; nan, inf, hex and "1.0abc" are refused. */
hk_Status hk_keyline_doubles(const hk_KeyFile *kf, const hk_KeyLine *kl, int count, double *out, hk_Error *err);

/* One to `max` finite numbers into out[max]; *got receives how many. More than max
 * is HK_ERR_INVALID, none is HK_ERR_PARSE. */
hk_Status hk_keyline_double_list(const hk_KeyFile *kf, const hk_KeyLine *kl, int max, double *out, int *got,
                                 hk_Error *err);

/* 1 when the n bytes at s are one decimal number, [+-]digits[.digits][e[+-]digits] with
 * at least one digit before the exponent, else 0: the syntax every reader of decimal text
 * checks before strtod/strtof (which would also take nan, inf, hex and leading blanks). */
int hk_decimal_syntax(const char *s, size_t n);

/* What hk_parse_decimal found. */
enum { HK_NUM_OK, HK_NUM_SYNTAX, HK_NUM_RANGE };

/* One decimal number, the whole of s: [+-]digits[.digits][e[+-]digits], whatever the C
 * locale. nan, inf, hex floats ("0x10"), blanks and trailing text are HK_NUM_SYNTAX; an
 * overflow, or an underflow to a denormal, HK_NUM_RANGE. The key files' numbers and
 * the OBJ reader's (obj.c). */
int hk_parse_decimal(const char *s, double *out);

/* One whole number in [lo, hi] (outside: HK_ERR_INVALID). */
hk_Status hk_keyline_int(const hk_KeyFile *kf, const hk_KeyLine *kl, long lo, long hi, long *out, hk_Error *err);

/* One boolean: true/false, yes/no, on/off, 1/0, any case. */
hk_Status hk_keyline_bool(const hk_KeyFile *kf, const hk_KeyLine *kl, int *out, hk_Error *err);

/* One string, bare or quoted; *out points into kf (valid until hk_keyfile_free). */
hk_Status hk_keyline_string(const hk_KeyFile *kf, const hk_KeyLine *kl, const char **out, hk_Error *err);

/* `relative` resolved against the folder of the file being read (absolute paths are
 * returned unchanged), so that a setup file can name its files relative to itself.
 * The result is allocated with hk_alloc_array: release it with hk_free. NULL (and err
 * set) for an empty path or when out of memory. */
char *hk_keyfile_resolve_path(const hk_KeyFile *kf, const char *relative, hk_Error *err);

#endif
