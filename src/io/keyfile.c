/* Tokeniser and typed accessors for the thesis's `Key value...` input files
 * (thesis 004 §4.2.1, Appendix B), with file:line error messages. */
#include "keyfile.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "hairkit/io.h"

hk_Status hk_keyfile_error(const hk_KeyFile *kf, int line, hk_Status code, hk_Error *err,
                           const char *fmt, ...)
{
    if (!err) return code;
    char msg[HK_ERROR_MESSAGE_SIZE];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (line > 0) return hk_error_set(err, code, "%s:%d: %s", kf->path, line, msg);
    return hk_error_set(err, code, "%s: %s", kf->path, msg);
}

static char *dup_str(const char *s, hk_Error *err)
{
    size_t n = strlen(s);
    char *d = hk_alloc_array(n + 1, 1, err);
    if (d) memcpy(d, s, n + 1);
    return d;
}

/* Reads the whole file, refusing what is not a small text file. */
static hk_Status slurp(hk_KeyFile *kf, size_t *size, hk_Error *err)
{
    FILE *fp = fopen(kf->path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", kf->path, strerror(errno));
    struct stat sb;
    if (fstat(fileno(fp), &sb) != 0 || !S_ISREG(sb.st_mode)) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_IO, "%s: not a regular file", kf->path);
    }
    long len = -1;
    if (fseek(fp, 0, SEEK_END) == 0) len = ftell(fp);
    if (len < 0 || fseek(fp, 0, SEEK_SET) != 0) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_IO, "%s: cannot read (not a regular file?)", kf->path);
    }
    if (len == 0) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_PARSE, "%s: file is empty", kf->path);
    }
    if (len > HK_MAX_INPUT_FILE_BYTES) {
        fclose(fp);
        return hk_error_set(err, HK_ERR_PARSE, "%s: file is %ld bytes, larger than the %ld allowed for an input file",
                            kf->path, len, HK_MAX_INPUT_FILE_BYTES);
    }
    kf->text = hk_alloc_array((size_t)len + 1, 1, err);
    if (!kf->text) {
        fclose(fp);
        return HK_ERR_NOMEM;
    }
    size_t got = fread(kf->text, 1, (size_t)len, fp);
    fclose(fp);
    if (got != (size_t)len) return hk_error_set(err, HK_ERR_IO, "%s: read error", kf->path);
    kf->text[len] = '\0';
    *size = (size_t)len;
    /* Control bytes other than blanks and line ends mean binary data. */
    int line = 1;
    for (size_t i = 0; i < *size; i++) {
        unsigned char c = (unsigned char)kf->text[i];
        if (c == '\n') line++;
        else if (c < 0x20 && c != '\t' && c != '\r' && c != '\f' && c != '\v')
            return hk_error_set(err, HK_ERR_PARSE, "%s: not a text file (binary data at line %d)", kf->path, line);
    }
    return HK_OK;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

/* Cuts one line (NUL-terminated, in place) into tokens. With `out` NULL it only
 * counts them. Returns the token count, or -1 for an unterminated quote. */
static int tokenize(char *s, const char **out)
{
    int n = 0;
    for (;;) {
        while (is_blank(*s)) s++;
        if (*s == '\0' || *s == '#') return n;
        if (*s == '"') {
            char *end = strchr(s + 1, '"');
            if (!end) return -1;
            if (out) {
                *end = '\0';
                out[n] = s + 1;
            }
            n++;
            s = end + 1;
            continue;
        }
        char *start = s;
        while (*s && !is_blank(*s) && *s != '#') s++;
        const int comment = *s == '#';
        if (out) {
            out[n] = start;
            if (*s) *s++ = '\0';
        }
        n++;
        if (comment) return n; /* "value# comment": the rest of the line is a comment */
    }
}

hk_Status hk_keyfile_read(const char *path, hk_KeyFile *kf, hk_Error *err)
{
    memset(kf, 0, sizeof *kf);
    kf->path = dup_str(path, err);
    if (!kf->path) return HK_ERR_NOMEM;
    size_t size = 0;
    hk_Status st = slurp(kf, &size, err);
    if (st != HK_OK) {
        hk_keyfile_free(kf);
        return st;
    }
    /* Pass 1: count non-empty lines and tokens (on a scratch copy of each line,
     * because tokenising writes terminators). */
    int lines = 0;
    size_t tokens = 0;
    char *copy = hk_alloc_array(size + 2, 1, err);
    if (!copy) {
        hk_keyfile_free(kf);
        return HK_ERR_NOMEM;
    }
    {
        int line_no = 1;
        char *p = kf->text;
        while (*p) {
            char *nl = strchr(p, '\n');
            size_t len = nl ? (size_t)(nl - p) : strlen(p);
            memcpy(copy, p, len);
            copy[len] = '\0';
            int n = tokenize(copy, NULL);
            if (n < 0) {
                hk_free(copy);
                st = hk_keyfile_error(kf, line_no, HK_ERR_PARSE, err, "unterminated double quote");
                hk_keyfile_free(kf);
                return st;
            }
            if (n > 0) {
                lines++;
                tokens += (size_t)n;
            }
            line_no++;
            p = nl ? nl + 1 : p + len;
        }
    }
    char *text = hk_alloc_array(size + 2, 1, err);
    kf->lines = hk_calloc_array((size_t)lines + 1, sizeof *kf->lines, err);
    kf->tokens = hk_calloc_array(tokens + 1, sizeof *kf->tokens, err);
    if (!text || !kf->lines || !kf->tokens) {
        hk_free(copy);
        hk_free(text);
        hk_keyfile_free(kf);
        return HK_ERR_NOMEM;
    }
    /* Pass 2: tokenise each line into its own slice of a second buffer. */
    int line_no = 1, li = 0;
    size_t ti = 0;
    char *p = kf->text, *dst = text;
    while (*p) {
        char *nl = strchr(p, '\n');
        size_t len = nl ? (size_t)(nl - p) : strlen(p);
        memcpy(dst, p, len);
        dst[len] = '\0';
        const char **toks = kf->tokens + ti;
        int n = tokenize(dst, toks);
        if (n > 0) {
            kf->lines[li].line = line_no;
            kf->lines[li].key = toks[0];
            kf->lines[li].count = n - 1;
            kf->lines[li].values = toks + 1;
            li++;
            ti += (size_t)n;
        }
        dst += len + 1;
        line_no++;
        p = nl ? nl + 1 : p + len;
    }
    hk_free(copy);
    hk_free(kf->text);
    kf->text = text;
    kf->line_count = li;
    return HK_OK;
}

void hk_keyfile_free(hk_KeyFile *kf)
{
    hk_free(kf->path);
    hk_free(kf->text);
    hk_free(kf->lines);
    hk_free((void *)kf->tokens);
    memset(kf, 0, sizeof *kf);
}

static int parse_number(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v)) return 0;
    *out = v;
    return 1;
}

static hk_Status number_at(const hk_KeyFile *kf, const hk_KeyLine *kl, int i, double *out, hk_Error *err)
{
    if (!parse_number(kl->values[i], out))
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' is not a finite number (value %d of '%s')",
                                kl->values[i], i + 1, kl->key);
    return HK_OK;
}

hk_Status hk_keyline_doubles(const hk_KeyFile *kf, const hk_KeyLine *kl, int count, double *out, hk_Error *err)
{
    if (kl->count != count)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "expected %d number%s after '%s', got %d", count,
                                count == 1 ? "" : "s", kl->key, kl->count);
    for (int i = 0; i < count; i++) {
        hk_Status st = number_at(kf, kl, i, &out[i], err);
        if (st != HK_OK) return st;
    }
    return HK_OK;
}

hk_Status hk_keyline_double_list(const hk_KeyFile *kf, const hk_KeyLine *kl, int max, double *out, int *got,
                                 hk_Error *err)
{
    if (kl->count < 1)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' needs at least one number", kl->key);
    if (kl->count > max)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "'%s' has %d values, at most %d allowed", kl->key,
                                kl->count, max);
    for (int i = 0; i < kl->count; i++) {
        hk_Status st = number_at(kf, kl, i, &out[i], err);
        if (st != HK_OK) return st;
    }
    *got = kl->count;
    return HK_OK;
}

static hk_Status one_value(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Error *err)
{
    if (kl->count != 1)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "expected one value after '%s', got %d", kl->key,
                                kl->count);
    return HK_OK;
}

hk_Status hk_keyline_int(const hk_KeyFile *kf, const hk_KeyLine *kl, long lo, long hi, long *out, hk_Error *err)
{
    hk_Status st = one_value(kf, kl, err);
    if (st != HK_OK) return st;
    char *end;
    errno = 0;
    long v = strtol(kl->values[0], &end, 10);
    if (end == kl->values[0] || *end != '\0' || errno == ERANGE)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' is not a whole number (value of '%s')",
                                kl->values[0], kl->key);
    if (v < lo || v > hi)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s must be in [%ld, %ld], got %ld", kl->key, lo,
                                hi, v);
    *out = v;
    return HK_OK;
}

hk_Status hk_keyline_bool(const hk_KeyFile *kf, const hk_KeyLine *kl, int *out, hk_Error *err)
{
    hk_Status st = one_value(kf, kl, err);
    if (st != HK_OK) return st;
    static const char *const yes[] = {"true", "yes", "on", "1"}, *const no[] = {"false", "no", "off", "0"};
    for (int i = 0; i < 4; i++) {
        if (!strcasecmp(kl->values[0], yes[i])) return *out = 1, HK_OK;
        if (!strcasecmp(kl->values[0], no[i])) return *out = 0, HK_OK;
    }
    return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' must be true or false, got '%s'", kl->key,
                            kl->values[0]);
}

hk_Status hk_keyline_string(const hk_KeyFile *kf, const hk_KeyLine *kl, const char **out, hk_Error *err)
{
    hk_Status st = one_value(kf, kl, err);
    if (st != HK_OK) return st;
    *out = kl->values[0];
    return HK_OK;
}

char *hk_keyfile_resolve_path(const hk_KeyFile *kf, const char *relative, hk_Error *err)
{
    const char *slash = strrchr(kf->path, '/');
    size_t dir = (relative[0] == '/' || !slash) ? 0 : (size_t)(slash - kf->path) + 1;
    size_t n = strlen(relative);
    char *out = hk_alloc_array(dir + n + 1, 1, err);
    if (!out) return NULL;
    memcpy(out, kf->path, dir);
    memcpy(out + dir, relative, n + 1);
    return out;
}
