/* Reader for the thesis's `Key value...` text files (thesis 004 §4.2.1, Appendix B):
 * one entry per line, `#` starts a comment outside double quotes, values separated by
 * blanks, "a value with blanks" in double quotes. Used for the hairstyle, collision,
 * setup and visuality files; every message names the file and line. */
#ifndef HK_IO_KEYFILE_H
#define HK_IO_KEYFILE_H

#include "hairkit/core.h"

typedef struct hk_KeyLine {
    int line;            /* 1-based line number */
    const char *key;     /* first token */
    int count;           /* number of values after the key */
    const char **values; /* the values (quotes removed) */
} hk_KeyLine;

typedef struct hk_KeyFile {
    char *path;          /* as given to hk_keyfile_read */
    char *text;          /* file contents, cut into tokens in place */
    hk_KeyLine *lines;   /* non-empty lines only */
    int line_count;
    const char **tokens; /* storage behind every line's values */
} hk_KeyFile;

/* Reads and tokenises a file. Refuses missing, empty, oversized
 * (> HK_MAX_INPUT_FILE_BYTES) and binary files and unterminated quotes. */
hk_Status hk_keyfile_read(const char *path, hk_KeyFile *kf, hk_Error *err);
void hk_keyfile_free(hk_KeyFile *kf);

/* Exactly `count` finite numbers after the key. */
hk_Status hk_keyline_doubles(const hk_KeyFile *kf, const hk_KeyLine *kl, int count, double *out,
                             hk_Error *err);
/* One to `max` finite numbers; *got receives how many. */
hk_Status hk_keyline_double_list(const hk_KeyFile *kf, const hk_KeyLine *kl, int max, double *out,
                                 int *got, hk_Error *err);
/* One integer in [lo, hi]. */
hk_Status hk_keyline_int(const hk_KeyFile *kf, const hk_KeyLine *kl, long lo, long hi, long *out,
                         hk_Error *err);
/* One boolean: true/false, yes/no, on/off, 1/0 (any case). */
hk_Status hk_keyline_bool(const hk_KeyFile *kf, const hk_KeyLine *kl, int *out, hk_Error *err);
/* One string (bare or quoted). */
hk_Status hk_keyline_string(const hk_KeyFile *kf, const hk_KeyLine *kl, const char **out,
                            hk_Error *err);

/* `relative` resolved against the folder of the file (absolute paths unchanged);
 * returned string allocated with hk_alloc_array, release with hk_free. */
char *hk_keyfile_resolve_path(const hk_KeyFile *kf, const char *relative, hk_Error *err);

/* "path:line: " style error helper. */
#if defined(__GNUC__)
__attribute__((format(printf, 5, 6)))
#endif
hk_Status hk_keyfile_error(const hk_KeyFile *kf, int line, hk_Status code, hk_Error *err,
                           const char *fmt, ...);

#endif
