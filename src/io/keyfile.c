/* Tokeniser and typed accessors for the thesis's `Key value...` input files
 * (Lansink 2010 §4.2.1, Appendix B), with file:line error messages. */
#include "keyfile.h"

#include <errno.h>
#include <fcntl.h>
#include <locale.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hairkit/io.h"

hk_Status hk_keyfile_error(const hk_KeyFile *kf, int line, hk_Status code, hk_Error *err, const char *fmt, ...)
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

/* ---- Reading ------------------------------------------------------------------------ */

static hk_Status too_large(const char *path, long max_bytes, hk_Error *err)
{
    return hk_error_set(err, HK_ERR_PARSE, "%s: file is larger than the %ld bytes allowed for an input file", path,
                        max_bytes);
}

/* Reads the whole file into a NUL-terminated buffer. open() with O_NONBLOCK, so that
 * a FIFO without a writer is refused instead of hanging; the size is checked before
 * allocating and again while reading (the file may grow, /proc files report 0). */
static hk_Status read_all(const char *path, long max_bytes, char **text, size_t *size, hk_Error *err)
{
    int fd = open(path, O_RDONLY | O_NOCTTY | O_NONBLOCK);
    if (fd < 0) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    hk_Status st = HK_OK;
    if (fstat(fd, &sb) != 0)
        st = hk_error_set(err, HK_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    else if (S_ISDIR(sb.st_mode))
        st = hk_error_set(err, HK_ERR_IO, "%s: is a folder, not a file", path);
    else if (!S_ISREG(sb.st_mode))
        st = hk_error_set(err, HK_ERR_IO, "%s: not a regular file", path);
    else if (sb.st_size > max_bytes)
        st = too_large(path, max_bytes, err);
    if (st != HK_OK) {
        close(fd);
        return st;
    }
    const size_t limit = (size_t)max_bytes;
    size_t cap = (size_t)sb.st_size + 2, len = 0; /* +1 to see growth, +1 for the NUL */
    if (cap < 256) cap = 256;
    char *buf = hk_alloc_array(cap, 1, err);
    while (buf) {
        if (len + 1 == cap) {
            if (len > limit) {
                st = too_large(path, max_bytes, err);
                break;
            }
            size_t grown = cap > limit / 2 ? limit + 2 : cap * 2;
            char *bigger = realloc(buf, grown); /* hk_free is free() */
            if (!bigger) {
                st = hk_error_set(err, HK_ERR_NOMEM, "%s: out of memory reading the file", path);
                break;
            }
            buf = bigger;
            cap = grown;
        }
        ssize_t n = read(fd, buf + len, cap - 1 - len);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            st = hk_error_set(err, HK_ERR_IO, "%s: read error: %s", path, strerror(errno));
            break;
        }
        if (n == 0) break;
        len += (size_t)n;
    }
    close(fd);
    if (!buf) return HK_ERR_NOMEM;
    if (st == HK_OK && len > limit) st = too_large(path, max_bytes, err);
    if (st == HK_OK && len == 0) st = hk_error_set(err, HK_ERR_PARSE, "%s: file is empty", path);
    if (st != HK_OK) {
        hk_free(buf);
        return st;
    }
    buf[len] = '\0';
    *text = buf;
    *size = len;
    return HK_OK;
}

/* A text file holds no control bytes but blanks and line ends. Lines are counted as
 * everywhere else here: \n, \r\n or a lone \r ends one. */
static hk_Status check_text(const char *path, const unsigned char *s, size_t size, hk_Error *err)
{
    if (size >= 2 && ((s[0] == 0xFF && s[1] == 0xFE) || (s[0] == 0xFE && s[1] == 0xFF)))
        return hk_error_set(err, HK_ERR_PARSE, "%s: not a text file (UTF-16 encoded: save it as UTF-8 or ASCII)", path);
    int line = 1;
    for (size_t i = 0; i < size; i++) {
        unsigned char c = s[i];
        if (c == '\n' || (c == '\r' && (i + 1 == size || s[i + 1] != '\n')))
            line++;
        else if ((c < 0x20 && c != '\t' && c != '\r' && c != '\f' && c != '\v') || c == 0x7F)
            return hk_error_set(err, HK_ERR_PARSE, "%s: not a text file (binary data at line %d)", path, line);
    }
    return HK_OK;
}

/* End of the line starting at p (its \r, \n or the final NUL); *next is where the
 * following line starts. */
static char *line_end(char *p, char **next)
{
    while (*p && *p != '\n' && *p != '\r') p++;
    *next = p[0] == '\0' ? p : (p[0] == '\r' && p[1] == '\n' ? p + 2 : p + 1);
    return p;
}

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\f' || c == '\v'; }

enum { TOK_UNTERMINATED = -1, TOK_MISPLACED_QUOTE = -2 };

/* Cuts the line [s, end) into tokens. With out NULL it only counts and leaves the text
 * untouched; otherwise it stores the tokens and terminates them in place, writing only
 * behind its reading position (at most at *end, the line end). A `#` outside quotes
 * ends the line, even glued to a value ("3#c"); a quote must enclose a whole value.
 * Returns the token count or a TOK_ error. */
static int tokenize(char *s, char *end, const char **out)
{
    int n = 0;
    while (s < end) {
        if (is_blank(*s)) {
            s++;
            continue;
        }
        if (*s == '#') break;
        if (*s == '"') {
            char *close = memchr(s + 1, '"', (size_t)(end - s - 1));
            if (!close) return TOK_UNTERMINATED;
            if (close + 1 < end && !is_blank(close[1]) && close[1] != '#') return TOK_MISPLACED_QUOTE;
            if (out) {
                out[n] = s + 1;
                *close = '\0';
            }
            s = close + 1;
        } else {
            char *start = s;
            while (s < end && !is_blank(*s) && *s != '#' && *s != '"') s++;
            if (s < end && *s == '"') return TOK_MISPLACED_QUOTE;
            const int comment = s < end && *s == '#';
            if (out) {
                out[n] = start;
                *s = '\0';
            }
            if (comment) return n + 1;
            s++;
        }
        n++;
    }
    return n;
}

static hk_Status tokenize_error(const hk_KeyFile *kf, int line, int code, hk_Error *err)
{
    if (code == TOK_UNTERMINATED) return hk_keyfile_error(kf, line, HK_ERR_PARSE, err, "unterminated double quote");
    return hk_keyfile_error(kf, line, HK_ERR_PARSE, err,
                            "misplaced double quote: quotes enclose a whole value, "
                            "as in \"my file.txt\"");
}

hk_Status hk_keyfile_read(const char *path, hk_KeyFile *kf, hk_Error *err)
{
    return hk_keyfile_read_limited(path, HK_MAX_INPUT_FILE_BYTES, kf, err);
}

hk_Status hk_keyfile_read_limited(const char *path, long max_bytes, hk_KeyFile *kf, hk_Error *err)
{
    memset(kf, 0, sizeof *kf);
    size_t n = strlen(path);
    kf->path = hk_alloc_array(n + 1, 1, err);
    if (!kf->path) return HK_ERR_NOMEM;
    memcpy(kf->path, path, n + 1);

    size_t size = 0;
    hk_Status st = read_all(path, max_bytes, &kf->text, &size, err);
    if (st == HK_OK) st = check_text(path, (const unsigned char *)kf->text, size, err);
    if (st != HK_OK) {
        hk_keyfile_free(kf);
        return st;
    }
    char *first = kf->text;
    if (size >= 3 && !memcmp(first, "\xEF\xBB\xBF", 3)) first += 3; /* UTF-8 byte-order mark */

    /* Pass 1 counts lines and tokens, pass 2 stores them: no guessing at sizes. */
    int lines = 0;
    size_t tokens = 0;
    int line_no = 1;
    for (char *p = first, *next; *p; p = next, line_no++) {
        char *e = line_end(p, &next);
        int t = tokenize(p, e, NULL);
        if (t < 0) {
            st = tokenize_error(kf, line_no, t, err);
            hk_keyfile_free(kf);
            return st;
        }
        if (t > 0) {
            lines++;
            tokens += (size_t)t;
        }
    }
    kf->lines = hk_calloc_array((size_t)lines + 1, sizeof *kf->lines, err);
    kf->tokens = hk_calloc_array(tokens + 1, sizeof *kf->tokens, err);
    if (!kf->lines || !kf->tokens) {
        hk_keyfile_free(kf);
        return HK_ERR_NOMEM;
    }
    size_t ti = 0;
    line_no = 1;
    for (char *p = first, *next; *p; p = next, line_no++) {
        char *e = line_end(p, &next);
        const char **toks = kf->tokens + ti;
        int t = tokenize(p, e, toks);
        if (t > 0) {
            hk_KeyLine *kl = &kf->lines[kf->line_count++];
            kl->line = line_no;
            kl->key = toks[0];
            kl->count = t - 1;
            kl->values = toks + 1;
            ti += (size_t)t;
        }
    }
    return HK_OK;
}

void hk_keyfile_free(hk_KeyFile *kf)
{
    if (!kf) return;
    hk_free(kf->path);
    hk_free(kf->text);
    hk_free(kf->lines);
    hk_free((void *)kf->tokens);
    memset(kf, 0, sizeof *kf);
}

/* ---- Keys --------------------------------------------------------------------------- */

static char ascii_lower(char c) { return c >= 'A' && c <= 'Z' ? (char)(c - 'A' + 'a') : c; }

int hk_key_equal(const char *a, const char *b)
{
    for (; *a && ascii_lower(*a) == ascii_lower(*b); a++) b++;
    return *a == '\0' && *b == '\0';
}

int hk_keyspec_find(const hk_KeySpec *specs, int spec_count, const char *key)
{
    for (int k = 0; k < spec_count; k++)
        if (hk_key_equal(key, specs[k].name) || (specs[k].alias && hk_key_equal(key, specs[k].alias))) return k;
    return -1;
}

hk_Status hk_keyfile_check_keys(const hk_KeyFile *kf, const hk_KeySpec *specs, int spec_count, const char *kind,
                                int *line_of, hk_Error *err)
{
    for (int k = 0; k < spec_count; k++) line_of[k] = 0;
    for (int i = 0; i < kf->line_count; i++) {
        const hk_KeyLine *kl = &kf->lines[i];
        int k = hk_keyspec_find(specs, spec_count, kl->key);
        if (k < 0)
            return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "unknown key '%s'%s%s%s", kl->key,
                                    kind ? " in a " : "", kind ? kind : "", kind ? " file" : "");
        if (line_of[k])
            return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "duplicate key '%s' (first given at line %d)",
                                    specs[k].name, line_of[k]);
        line_of[k] = kl->line;
    }
    for (int k = 0; k < spec_count; k++)
        if (specs[k].required && !line_of[k])
            return hk_keyfile_error(kf, 0, HK_ERR_PARSE, err, "missing required key '%s'", specs[k].name);
    return HK_OK;
}

/* ---- Values ------------------------------------------------------------------------- */

static int is_digit(char c) { return c >= '0' && c <= '9'; }

/* Decimal numbers only (keyfile.h; the OBJ reader uses it too): strtod alone would
 * also take "nan", "inf", hex floats and leading blanks, and would read "0.5" as 0
 * under a locale with a decimal comma, which a program embedding hairkit may have set. */
int hk_decimal_syntax(const char *s, size_t n)
{
    size_t i = 0;
    int digits = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    while (i < n && is_digit(s[i])) i++, digits++;
    if (i < n && s[i] == '.') {
        i++;
        while (i < n && is_digit(s[i])) i++, digits++;
    }
    if (!digits) return 0;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        if (i >= n || !is_digit(s[i])) return 0;
        while (i < n && is_digit(s[i])) i++;
    }
    return i == n;
}

int hk_parse_decimal(const char *s, double *out)
{
    if (!hk_decimal_syntax(s, strlen(s))) return HK_NUM_SYNTAX;

    char local[256];
    const char *text = s;
    const char *point = localeconv()->decimal_point;
    if (point && point[0] && strcmp(point, ".") != 0 && strchr(s, '.')) {
        size_t at = (size_t)(strchr(s, '.') - s), pl = strlen(point), n = strlen(s);
        if (n + pl >= sizeof local) return HK_NUM_RANGE;
        memcpy(local, s, at);
        memcpy(local + at, point, pl);
        memcpy(local + at + pl, s + at + 1, n - at); /* with the NUL */
        text = local;
    }
    char *end;
    errno = 0;
    double v = strtod(text, &end);
    if (*end != '\0') return HK_NUM_SYNTAX;
    if (errno == ERANGE || !isfinite(v)) return HK_NUM_RANGE; /* overflow, or underflow to a denormal */
    *out = v;
    return HK_NUM_OK;
}

static hk_Status number_at(const hk_KeyFile *kf, const hk_KeyLine *kl, int i, double *out, hk_Error *err)
{
    switch (hk_parse_decimal(kl->values[i], out)) {
    case HK_NUM_OK:
        return HK_OK;
    case HK_NUM_RANGE:
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "'%s' is out of the range of double precision (value %d of '%s')", kl->values[i], i + 1,
                                kl->key);
    default:
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' is not a finite number (value %d of '%s')",
                                kl->values[i], i + 1, kl->key);
    }
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
    *got = 0;
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
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "expected one value after '%s', got %d%s", kl->key,
                                kl->count, kl->count > 1 ? " (write a value with blanks in double quotes)" : "");
    return HK_OK;
}

hk_Status hk_keyline_int(const hk_KeyFile *kf, const hk_KeyLine *kl, long lo, long hi, long *out, hk_Error *err)
{
    hk_Status st = one_value(kf, kl, err);
    if (st != HK_OK) return st;
    const char *s = kl->values[0], *p = s + (*s == '+' || *s == '-');
    if (!is_digit(*p))
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' is not a whole number (value of '%s')", s,
                                kl->key);
    while (is_digit(*p)) p++;
    if (*p != '\0')
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "'%s' is not a whole number (value of '%s')", s,
                                kl->key);
    errno = 0;
    long v = strtol(s, NULL, 10);
    if (errno == ERANGE || v < lo || v > hi)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s must be in [%ld, %ld], got %s", kl->key, lo, hi,
                                s);
    *out = v;
    return HK_OK;
}

hk_Status hk_keyline_bool(const hk_KeyFile *kf, const hk_KeyLine *kl, int *out, hk_Error *err)
{
    hk_Status st = one_value(kf, kl, err);
    if (st != HK_OK) return st;
    static const char *const yes[] = {"true", "yes", "on", "1"};
    static const char *const no[] = {"false", "no", "off", "0"};
    for (int i = 0; i < 4; i++) {
        if (hk_key_equal(kl->values[0], yes[i])) {
            *out = 1;
            return HK_OK;
        }
        if (hk_key_equal(kl->values[0], no[i])) {
            *out = 0;
            return HK_OK;
        }
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
    if (!relative || !relative[0]) {
        hk_keyfile_error(kf, 0, HK_ERR_PARSE, err, "empty path");
        return NULL;
    }
    const char *slash = strrchr(kf->path, '/');
    size_t dir = (relative[0] == '/' || !slash) ? 0 : (size_t)(slash - kf->path) + 1;
    size_t n = strlen(relative);
    char *out = hk_alloc_array(dir + n + 1, 1, err);
    if (!out) return NULL;
    memcpy(out, kf->path, dir);
    memcpy(out + dir, relative, n + 1);
    return out;
}
