/* Hair as USD ascii (.usda) BasisCurves (docs/file-formats.md, "USD"): the subset
 * written here from the USD documentation (UsdGeomBasisCurves), no USD library.
 *
 * Written: the layer metadata upAxis = "Y" and metersPerUnit, one prim
 * `def BasisCurves "hair"` with type = "linear", wrap = "nonperiodic", curveVertexCounts,
 * extent, points (point3f[]) and widths (per vertex when the hair has a thickness array,
 * else one constant width: the default thickness).
 * Read: every BasisCurves prim of the file (nested at any depth), in file order, with
 * type = "linear" and wrap = "nonperiodic"; curveVertexCounts, points (default values:
 * time samples alone are refused), widths or primvars:widths with their interpolation;
 * the layer's upAxis ("Y" or "Z": Z is rotated onto +y) and metersPerUnit (points and
 * widths multiplied by it: the result is in metres). Transforms are not applied: an
 * xformOp that is not the identity is refused. Cubic curves, references, payloads,
 * variants and other layers are not followed (variant bodies are skipped). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hair_io.h"
#include "hairkit/hair_formats.h"
#include "hairkit/version.h"

/* ---- tokens ---- */
enum { TK_END, TK_WORD, TK_STRING, TK_PATH, TK_PUNCT };

typedef struct Lexer {
    hk_TextIn t;
    size_t pos;
    long line;
    /* current token */
    int kind;
    const char *s;
    size_t n;
    long tline;
} Lexer;

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
static int is_punct(char c)
{
    return c == '(' || c == ')' || c == '[' || c == ']' || c == '{' || c == '}' || c == '=' || c == ',' || c == ';' ||
           c == '<' || c == '>' || c == '@' || c == '"' || c == '\'' || c == '#';
}

static hk_Status lex_error(const Lexer *lx, hk_Error *err, const char *what)
{
    return hk_textin_error(&lx->t, lx->tline, err, "%s", what);
}

/* Advances to the next token. */
static hk_Status lex(Lexer *lx, hk_Error *err)
{
    const char *d = lx->t.data;
    const size_t size = lx->t.size;
    size_t p = lx->pos;
    for (;;) {
        while (p < size && is_space(d[p])) {
            if (d[p] == '\n' || (d[p] == '\r' && (p + 1 >= size || d[p + 1] != '\n'))) lx->line++;
            p++;
        }
        if (p < size && d[p] == '#') {
            while (p < size && d[p] != '\n' && d[p] != '\r') p++;
            continue;
        }
        break;
    }
    lx->tline = lx->line;
    lx->s = d + p;
    if (p >= size) {
        lx->kind = TK_END, lx->n = 0, lx->pos = p;
        return HK_OK;
    }
    const char c = d[p];
    if (c == '"' || c == '\'') {
        const int triple = p + 2 < size && d[p + 1] == c && d[p + 2] == c;
        size_t q = p + (triple ? 3 : 1);
        for (;;) {
            if (q >= size) {
                lx->pos = q;
                return lex_error(lx, err, "unterminated string");
            }
            if (d[q] == '\\' && q + 1 < size) {
                q += 2;
                continue;
            }
            if (d[q] == '\n') {
                if (!triple) return lex_error(lx, err, "unterminated string");
                lx->line++;
            }
            if (d[q] == c && (!triple || (q + 2 < size && d[q + 1] == c && d[q + 2] == c))) break;
            q++;
        }
        lx->kind = TK_STRING;
        lx->s = d + p + (triple ? 3 : 1);
        lx->n = q - p - (triple ? 3 : 1);
        lx->pos = q + (triple ? 3 : 1);
        return HK_OK;
    }
    if (c == '<' || c == '@') {
        const char close = c == '<' ? '>' : '@';
        size_t q = p + 1;
        while (q < size && d[q] != close && d[q] != '\n') q++;
        if (q >= size || d[q] != close)
            return lex_error(lx, err, c == '<' ? "unterminated path" : "unterminated asset path");
        lx->kind = TK_PATH, lx->n = q + 1 - p, lx->pos = q + 1;
        return HK_OK;
    }
    if (is_punct(c)) {
        lx->kind = TK_PUNCT, lx->n = 1, lx->pos = p + 1;
        return HK_OK;
    }
    size_t q = p;
    while (q < size && !is_space(d[q]) && !is_punct(d[q])) {
        if ((unsigned char)d[q] < 0x20) {
            lx->pos = q;
            return lex_error(lx, err, "binary data: not a USD ascii file");
        }
        q++;
    }
    lx->kind = TK_WORD, lx->n = q - p, lx->pos = q;
    return HK_OK;
}

static int is(const Lexer *lx, const char *text)
{
    return (lx->kind == TK_WORD || lx->kind == TK_PUNCT) && lx->n == strlen(text) && !memcmp(lx->s, text, lx->n);
}
static int is_str(const Lexer *lx, const char *text)
{
    return lx->kind == TK_STRING && lx->n == strlen(text) && !memcmp(lx->s, text, lx->n);
}

static hk_Status expect(Lexer *lx, const char *text, hk_Error *err)
{
    if (is(lx, text)) return lex(lx, err);
    char msg[128];
    if (lx->kind == TK_END)
        snprintf(msg, sizeof msg, "expected '%s', found the end of the file", text);
    else
        snprintf(msg, sizeof msg, "expected '%s', found '%.*s'", text, (int)(lx->n < 40 ? lx->n : 40), lx->s);
    return lex_error(lx, err, msg);
}

/* Skips one value: a word, string or path, or a bracketed group. */
static hk_Status skip_value(Lexer *lx, hk_Error *err)
{
    if (lx->kind == TK_END) return lex_error(lx, err, "a value is missing at the end of the file");
    if (lx->kind == TK_PUNCT && (is(lx, "(") || is(lx, "[") || is(lx, "{"))) {
        char stack[256];
        int depth = 0;
        do {
            if (lx->kind == TK_END) return lex_error(lx, err, "unbalanced brackets: the file ends inside a value");
            if (is(lx, "(") || is(lx, "[") || is(lx, "{")) {
                if (depth == (int)sizeof stack) return lex_error(lx, err, "brackets nested too deep");
                stack[depth++] = *lx->s == '(' ? ')' : *lx->s == '[' ? ']' : '}';
            } else if (is(lx, ")") || is(lx, "]") || is(lx, "}")) {
                if (*lx->s != stack[depth - 1]) return lex_error(lx, err, "mismatched brackets");
                depth--;
            }
            hk_Status st = lex(lx, err);
            if (st != HK_OK) return st;
        } while (depth > 0);
        return HK_OK;
    }
    if (lx->kind == TK_PUNCT) return lex_error(lx, err, "a value is expected here");
    /* a word may be followed by a path (e.g. a relationship target) */
    return lex(lx, err);
}

/* Skips a metadata block "( ... )". */
static hk_Status skip_parens(Lexer *lx, hk_Error *err) { return skip_value(lx, err); }

/* ---- growable arrays ---- */
typedef struct Floats {
    float *v;
    size_t n, cap;
} Floats;
typedef struct U32s {
    uint32_t *v;
    size_t n, cap;
} U32s;

static int grow(void **v, size_t *cap, size_t need, size_t item, hk_Error *err)
{
    if (need <= *cap) return 1;
    size_t c = *cap ? *cap : 256;
    while (c < need) c *= 2;
    void *d = hk_alloc_array(c, item, err);
    if (!d) return 0;
    if (*cap) memcpy(d, *v, *cap * item);
    hk_free(*v);
    *v = d;
    *cap = c;
    return 1;
}

static int push_f(Floats *a, float f, hk_Error *err)
{
    if (!grow((void **)&a->v, &a->cap, a->n + 1, sizeof(float), err)) return 0;
    a->v[a->n++] = f;
    return 1;
}
static int push_u(U32s *a, uint32_t u, hk_Error *err)
{
    if (!grow((void **)&a->v, &a->cap, a->n + 1, sizeof(uint32_t), err)) return 0;
    a->v[a->n++] = u;
    return 1;
}

/* Reads a number token. as_double: parse as double, then round to float. */
static hk_Status number(Lexer *lx, int as_double, double *out, hk_Error *err)
{
    int ok = 0;
    if (lx->kind == TK_WORD) {
        if (as_double) {
            ok = hk_parse_double(lx->s, lx->n, lx->t.point, out);
        } else {
            float f;
            ok = hk_parse_float(lx->s, lx->n, lx->t.point, &f);
            *out = (double)f;
        }
    }
    if (!ok) {
        char msg[96];
        snprintf(msg, sizeof msg, "'%.*s' is not a number", (int)(lx->n < 40 ? lx->n : 40), lx->s);
        return lex_error(lx, err, msg);
    }
    return lex(lx, err);
}

/* [ n, n, ... ] (or a tuple "( ... )" when tuple): numbers into out; flatten: any
 * nesting of brackets and parentheses. */
static hk_Status number_list(Lexer *lx, int as_double, Floats *out, int tuples3, hk_Error *err)
{
    hk_Status st = expect(lx, "[", err);
    if (st != HK_OK) return st;
    while (!is(lx, "]")) {
        if (tuples3) {
            st = expect(lx, "(", err);
            for (int k = 0; k < 3 && st == HK_OK; k++) {
                double v;
                st = number(lx, as_double, &v, err);
                if (st == HK_OK && k < 2) st = expect(lx, ",", err);
                if (st == HK_OK && !push_f(out, (float)v, err)) st = HK_ERR_NOMEM;
            }
            if (st == HK_OK) st = expect(lx, ")", err);
        } else {
            double v;
            st = number(lx, as_double, &v, err);
            if (st == HK_OK && !push_f(out, (float)v, err)) st = HK_ERR_NOMEM;
        }
        if (st != HK_OK) return st;
        if (is(lx, ",")) {
            st = lex(lx, err);
            if (st != HK_OK) return st;
        } else if (!is(lx, "]")) {
            return lex_error(lx, err, "expected ',' or ']' in an array");
        }
    }
    return lex(lx, err);
}

/* Every number in a value of any nesting (for the identity check of xformOps). */
static hk_Status flat_numbers(Lexer *lx, double *out, int cap, int *count, hk_Error *err)
{
    int depth = 0;
    *count = 0;
    do {
        if (lx->kind == TK_END) return lex_error(lx, err, "the file ends inside a value");
        if (is(lx, "(") || is(lx, "["))
            depth++;
        else if (is(lx, ")") || is(lx, "]"))
            depth--;
        else if (lx->kind == TK_WORD) {
            double v;
            if (!hk_parse_double(lx->s, lx->n, lx->t.point, &v)) return lex_error(lx, err, "a number is expected here");
            if (*count < cap) out[*count] = v;
            (*count)++;
        } else if (!is(lx, ",")) {
            return lex_error(lx, err, "a number is expected here");
        }
        hk_Status st = lex(lx, err);
        if (st != HK_OK) return st;
    } while (depth > 0);
    return HK_OK;
}

/* ---- one BasisCurves prim ---- */
typedef struct Curves {
    U32s counts;
    Floats points;
    Floats widths;
    int have_counts, have_points, points_sampled;
    int linear, type_given, periodic;
    char interp[16];
    long line;
} Curves;

typedef struct Reader {
    Lexer lx;
    U32s counts; /* all prims */
    Floats points;
    Floats widths; /* per point; NAN where no width was given */
    int any_width;
    int prims;
    double meters_per_unit;
    int z_up;
} Reader;

static void curves_free(Curves *c)
{
    hk_free(c->counts.v);
    hk_free(c->points.v);
    hk_free(c->widths.v);
}

/* The word without a trailing "[]" type suffix handled by the caller. */
static int word_is(const Lexer *lx, const char *w)
{
    return lx->kind == TK_WORD && lx->n == strlen(w) && !memcmp(lx->s, w, lx->n);
}

/* metadata "( key = value ... )" of a property: reads interpolation into interp. */
static hk_Status property_metadata(Lexer *lx, char *interp, size_t cap, hk_Error *err)
{
    hk_Status st = lex(lx, err); /* ( */
    while (st == HK_OK && !is(lx, ")")) {
        if (lx->kind == TK_END) return lex_error(lx, err, "the file ends inside metadata");
        if (lx->kind == TK_STRING) { /* doc string */
            st = lex(lx, err);
            continue;
        }
        const int is_interp = word_is(lx, "interpolation");
        st = lex(lx, err);
        if (st == HK_OK && is(lx, "=")) {
            st = lex(lx, err);
            if (st == HK_OK && is_interp && lx->kind == TK_STRING && interp) {
                snprintf(interp, cap, "%.*s", (int)(lx->n < cap ? lx->n : cap - 1), lx->s);
            }
            if (st == HK_OK) st = skip_value(lx, err);
        }
        if (st == HK_OK && (is(lx, ";") || is(lx, ","))) st = lex(lx, err);
    }
    if (st != HK_OK) return st;
    return lex(lx, err);
}

static int identity_op(const char *op, size_t n, const double *v, int count)
{
    char name[64];
    snprintf(name, sizeof name, "%.*s", (int)(n < 63 ? n : 63), op);
    const char *kind = name + strlen("xformOp:");
    int all = 1;
    if (!strncmp(kind, "translate", 9) || !strncmp(kind, "rotate", 6)) {
        for (int i = 0; i < count && i < 16; i++) all &= v[i] == 0.0;
        return all;
    }
    if (!strncmp(kind, "scale", 5)) {
        for (int i = 0; i < count && i < 16; i++) all &= v[i] == 1.0;
        return all;
    }
    if (!strncmp(kind, "orient", 6)) return count == 4 && v[0] == 1.0 && v[1] == 0.0 && v[2] == 0.0 && v[3] == 0.0;
    if (!strncmp(kind, "transform", 9)) {
        if (count != 16) return 0;
        for (int i = 0; i < 16; i++) all &= v[i] == (i % 5 == 0 ? 1.0 : 0.0);
        return all;
    }
    return 0;
}

static hk_Status prim(Reader *r, hk_Error *err);

/* One property statement of a prim body; c is the prim's curves (NULL for other prims). */
static hk_Status property(Reader *r, Curves *c, hk_Error *err)
{
    Lexer *lx = &r->lx;
    hk_Status st = HK_OK;
    const int rel = word_is(lx, "rel");
    while (st == HK_OK && (word_is(lx, "custom") || word_is(lx, "uniform") || word_is(lx, "varying") ||
                           word_is(lx, "config") || word_is(lx, "prepend") || word_is(lx, "append") ||
                           word_is(lx, "delete") || word_is(lx, "add") || word_is(lx, "reorder") || word_is(lx, "rel")))
        st = lex(lx, err);
    if (st != HK_OK) return st;
    if (lx->kind != TK_WORD) return lex_error(lx, err, "a property type or name is expected here");
    /* type [ "[]" ] name, or (rel, reorder) just a name */
    const char *type = lx->s;
    size_t type_n = lx->n;
    st = lex(lx, err);
    int array = 0;
    if (st == HK_OK && is(lx, "[")) {
        st = lex(lx, err);
        if (st == HK_OK) st = expect(lx, "]", err);
        array = 1;
    }
    if (st != HK_OK) return st;
    const char *name = type;
    size_t name_n = type_n;
    if (lx->kind == TK_WORD) {
        name = lx->s, name_n = lx->n;
        st = lex(lx, err);
        if (st != HK_OK) return st;
    } else if (!rel && !is(lx, "=")) {
        return lex_error(lx, err, "a property name is expected here");
    }
    const long line = lx->tline;
#define NAME_IS(w) (name_n == strlen(w) && !memcmp(name, w, name_n))
    const int is_double = type_n > 0 && type[type_n - 1] == 'd';
    if (!is(lx, "=")) {
        if (is(lx, "(")) st = property_metadata(lx, NULL, 0, err);
        return st;
    }
    st = lex(lx, err); /* = */
    if (st != HK_OK) return st;
    char interp[16] = "";
    const int none = word_is(lx, "None");
    if (none) {
        st = lex(lx, err);
    } else if (c && NAME_IS("curveVertexCounts") && array) {
        Floats tmp = {0};
        c->counts.n = 0;
        st = number_list(lx, 1, &tmp, 0, err);
        for (size_t i = 0; st == HK_OK && i < tmp.n; i++) {
            const float v = tmp.v[i];
            if (!(v >= 1.0f && v <= 65536.0f) || v != floorf(v)) {
                char msg[96];
                snprintf(msg, sizeof msg, "curve %zu has %g vertices (1 to 65536 are read)", i, (double)v);
                st = hk_textin_error(&lx->t, line, err, "%s", msg);
            } else if (!push_u(&c->counts, (uint32_t)v, err)) {
                st = HK_ERR_NOMEM;
            }
        }
        hk_free(tmp.v);
        c->have_counts = 1;
    } else if (c && NAME_IS("points") && array) {
        c->points.n = 0;
        st = number_list(lx, is_double, &c->points, 1, err);
        c->have_points = 1;
    } else if (c && (NAME_IS("widths") || NAME_IS("primvars:widths")) && array) {
        c->widths.n = 0;
        st = number_list(lx, is_double, &c->widths, 0, err);
        if (st == HK_OK && is(lx, "(")) st = property_metadata(lx, interp, sizeof interp, err);
        if (st == HK_OK) snprintf(c->interp, sizeof c->interp, "%s", interp);
        return st;
    } else if (c && NAME_IS("points.timeSamples")) {
        c->points_sampled = 1;
        st = skip_value(lx, err);
    } else if (c && NAME_IS("type")) {
        c->type_given = 1;
        c->linear = is_str(lx, "linear");
        if (!c->linear && lx->kind == TK_STRING) {
            return hk_textin_error(&lx->t, line, err,
                                   "type = \"%.*s\": only linear BasisCurves are read (cubic curves are not)",
                                   (int)(lx->n < 20 ? lx->n : 20), lx->s);
        }
        st = skip_value(lx, err);
    } else if (c && NAME_IS("wrap")) {
        if (!is_str(lx, "nonperiodic"))
            return hk_textin_error(&lx->t, line, err, "wrap = \"%.*s\": only nonperiodic curves are read",
                                   (int)(lx->n < 20 ? lx->n : 20), lx->s);
        st = skip_value(lx, err);
    } else if (name_n > 8 && !memcmp(name, "xformOp:", 8) &&
               !(name_n > 12 && !memcmp(name + name_n - 12, ".timeSamples", 12))) {
        double v[16];
        int count;
        st = flat_numbers(lx, v, 16, &count, err);
        if (st == HK_OK && !identity_op(name, name_n, v, count))
            return hk_textin_error(&lx->t, line, err,
                                   "%.*s: transforms are not applied (only BasisCurves without transforms are read)",
                                   (int)(name_n < 60 ? name_n : 60), name);
    } else if (name_n > 8 && !memcmp(name, "xformOp:", 8)) {
        return hk_textin_error(&lx->t, line, err, "%.*s: animated transforms are not read",
                               (int)(name_n < 60 ? name_n : 60), name);
    } else {
        st = skip_value(lx, err);
    }
#undef NAME_IS
    if (st == HK_OK && is(lx, "(")) st = property_metadata(lx, NULL, 0, err);
    return st;
}

/* Appends a finished BasisCurves prim to the reader's hair. */
static hk_Status add_curves(Reader *r, Curves *c, hk_Error *err)
{
    const hk_TextIn *t = &r->lx.t;
    if (!c->type_given)
        return hk_textin_error(
            t, c->line, err, "BasisCurves without 'type' (the schema's default is cubic): only linear curves are read");
    if (!c->have_points)
        return hk_textin_error(t, c->line, err,
                               c->points_sampled ? "points are given only as time samples (animation is not read)"
                                                 : "BasisCurves without points");
    if (!c->have_counts) return hk_textin_error(t, c->line, err, "BasisCurves without curveVertexCounts");
    uint64_t total = 0;
    for (size_t i = 0; i < c->counts.n; i++) total += c->counts.v[i];
    const size_t np = c->points.n / 3;
    if (total != np)
        return hk_textin_error(t, c->line, err, "curveVertexCounts add up to %llu points, points has %zu",
                               (unsigned long long)total, np);
    /* widths by interpolation */
    const size_t nw = c->widths.n;
    const char *in = c->interp[0] ? c->interp : "vertex";
    size_t per = 0; /* 1: constant, 2: uniform (per curve), 3: per vertex */
    if (nw) {
        if (!strcmp(in, "constant") && nw == 1)
            per = 1;
        else if (!strcmp(in, "uniform") && nw == c->counts.n)
            per = 2;
        else if ((!strcmp(in, "vertex") || !strcmp(in, "varying")) && nw == np)
            per = 3;
        else if (nw == 1)
            per = 1;
        else
            return hk_textin_error(t, c->line, err, "%zu widths with interpolation \"%s\" for %zu curves of %zu points",
                                   nw, in, c->counts.n, np);
        r->any_width = 1;
    }
    for (size_t i = 0; i < c->counts.n; i++)
        if (!push_u(&r->counts, c->counts.v[i], err)) return HK_ERR_NOMEM;
    for (size_t i = 0; i < c->points.n; i++)
        if (!push_f(&r->points, c->points.v[i], err)) return HK_ERR_NOMEM;
    size_t k = 0;
    for (size_t i = 0; i < c->counts.n; i++)
        for (uint32_t j = 0; j < c->counts.v[i]; j++, k++) {
            const float w = per == 1 ? c->widths.v[0] : per == 2 ? c->widths.v[i] : per == 3 ? c->widths.v[k] : NAN;
            if (!push_f(&r->widths, w, err)) return HK_ERR_NOMEM;
        }
    r->prims++;
    return HK_OK;
}

/* def|over|class [Type] "name" [( metadata )] { body } */
static hk_Status prim(Reader *r, hk_Error *err)
{
    Lexer *lx = &r->lx;
    const long line = lx->tline;
    hk_Status st = lex(lx, err); /* def */
    if (st != HK_OK) return st;
    int curves = 0;
    if (lx->kind == TK_WORD) {
        curves = word_is(lx, "BasisCurves");
        st = lex(lx, err);
        if (st != HK_OK) return st;
    }
    if (lx->kind != TK_STRING) return lex_error(lx, err, "a prim name in quotes is expected here");
    st = lex(lx, err);
    if (st == HK_OK && is(lx, "(")) st = skip_parens(lx, err);
    if (st == HK_OK) st = expect(lx, "{", err);
    if (st != HK_OK) return st;
    Curves c;
    memset(&c, 0, sizeof c);
    c.line = line;
    while (st == HK_OK && !is(lx, "}")) {
        if (lx->kind == TK_END) {
            st = lex_error(lx, err, "the file ends inside a prim (missing '}')");
        } else if (word_is(lx, "def") || word_is(lx, "over") || word_is(lx, "class")) {
            st = prim(r, err);
        } else if (word_is(lx, "variantSet")) {
            st = lex(lx, err);
            if (st == HK_OK) st = lex(lx, err); /* name */
            if (st == HK_OK) st = expect(lx, "=", err);
            if (st == HK_OK) st = skip_value(lx, err);
        } else if (is(lx, ";")) {
            st = lex(lx, err);
        } else {
            st = property(r, curves ? &c : NULL, err);
        }
    }
    if (st == HK_OK) st = lex(lx, err); /* } */
    if (st == HK_OK && curves) st = add_curves(r, &c, err);
    curves_free(&c);
    return st;
}

/* The layer's metadata: upAxis and metersPerUnit. */
static hk_Status layer_metadata(Reader *r, hk_Error *err)
{
    Lexer *lx = &r->lx;
    hk_Status st = lex(lx, err); /* ( */
    while (st == HK_OK && !is(lx, ")")) {
        if (lx->kind == TK_END) return lex_error(lx, err, "the file ends inside the layer metadata");
        if (lx->kind == TK_STRING) { /* doc string */
            st = lex(lx, err);
            continue;
        }
        const int up = word_is(lx, "upAxis"), mpu = word_is(lx, "metersPerUnit");
        const long line = lx->tline;
        st = lex(lx, err);
        if (st == HK_OK && is(lx, "=")) {
            st = lex(lx, err);
            if (st == HK_OK && up) {
                if (is_str(lx, "Y"))
                    r->z_up = 0;
                else if (is_str(lx, "Z"))
                    r->z_up = 1;
                else
                    return hk_textin_error(&lx->t, line, err, "upAxis must be \"Y\" or \"Z\"");
                st = lex(lx, err);
            } else if (st == HK_OK && mpu) {
                double v;
                st = number(lx, 1, &v, err);
                if (st == HK_OK && !(v > 0.0))
                    return hk_textin_error(&lx->t, line, err, "metersPerUnit must be > 0, got %g", v);
                r->meters_per_unit = v;
            } else if (st == HK_OK) {
                st = skip_value(lx, err);
            }
        }
        if (st == HK_OK && (is(lx, ";") || is(lx, ","))) st = lex(lx, err);
    }
    if (st != HK_OK) return st;
    return lex(lx, err);
}

hk_Status hk_usda_hair_load(const char *path, hk_HairFile *h, hk_Error *err)
{
    memset(h, 0, sizeof *h);
    Reader r;
    memset(&r, 0, sizeof r);
    r.meters_per_unit = 1.0;
    Lexer *lx = &r.lx;
    hk_Status st = hk_textin_load(&lx->t, path, err);
    if (st != HK_OK) return st;
    lx->line = 1;
    if (lx->t.size < 9 || memcmp(lx->t.data, "#usda 1.0", 9) != 0 || (lx->t.size > 9 && !is_space(lx->t.data[9]))) {
        st = hk_textin_error(&lx->t, 1, err, "not a USD ascii file (no '#usda 1.0' first line)");
        goto done;
    }
    if (memchr(lx->t.data, '\0', lx->t.size)) {
        st = hk_textin_error(&lx->t, 0, err, "binary data (a NUL byte): not a USD ascii file");
        goto done;
    }
    lx->pos = 9;
    st = lex(lx, err);
    if (st == HK_OK && is(lx, "(")) st = layer_metadata(&r, err);
    while (st == HK_OK && lx->kind != TK_END) {
        if (word_is(lx, "def") || word_is(lx, "over") || word_is(lx, "class"))
            st = prim(&r, err);
        else
            st = lex_error(lx, err, "a prim (def, over or class) is expected here");
    }
    if (st != HK_OK) goto done;
    if (!r.prims) {
        st = hk_textin_error(&lx->t, 0, err, "no BasisCurves prim");
        goto done;
    }
    if (r.counts.n > UINT32_MAX || r.points.n / 3 > UINT32_MAX) {
        st = hk_textin_error(&lx->t, 0, err, "more than 2^32 curves or points");
        goto done;
    }
    hk_Error sub;
    st = hk_hair_alloc(h, (uint32_t)r.counts.n, r.counts.v, &sub);
    if (st != HK_OK) {
        hk_error_set(err, st, "%s: %s", path, sub.message);
        goto done;
    }
    memcpy(h->points, r.points.v, r.points.n * sizeof(float));
    if (r.any_width) {
        float first = NAN;
        int same = 1;
        for (size_t i = 0; i < r.widths.n; i++)
            if (!isnan(r.widths.v[i])) {
                if (isnan(first)) first = r.widths.v[i];
                same &= r.widths.v[i] == first;
            }
        for (size_t i = 0; i < r.widths.n; i++)
            if (isnan(r.widths.v[i])) r.widths.v[i] = first, same = 0;
        if (same) {
            h->default_thickness = first;
        } else {
            h->thickness = hk_alloc_array(r.widths.n, sizeof(float), err);
            if (!h->thickness) {
                st = HK_ERR_NOMEM;
                goto done;
            }
            memcpy(h->thickness, r.widths.v, r.widths.n * sizeof(float));
            h->flags |= HK_HAIR_THICKNESS;
        }
    }
    if (r.z_up) hk_hair_up_to_y(h, HK_AXIS_POS_Z);
    if (r.meters_per_unit != 1.0) {
        st = hk_hair_scale(h, r.meters_per_unit, &sub);
        if (st != HK_OK)
            hk_error_set(err, HK_ERR_PARSE, "%s: metersPerUnit %g: %s", path, r.meters_per_unit, sub.message);
    }
    if (st == HK_OK) st = hk_hair_check_finite(path, h, err);
done:
    hk_free(r.counts.v);
    hk_free(r.points.v);
    hk_free(r.widths.v);
    hk_textin_free(&lx->t);
    if (st != HK_OK) hk_hair_free(h);
    return st;
}

static void write_double(hk_Writer *w, double v)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%.15g", v);
    if (strtod(buf, NULL) != v) snprintf(buf, sizeof buf, "%.17g", v);
    if (w->point != '.') {
        char *c = strchr(buf, w->point);
        if (c) *c = '.';
    }
    hk_writer_bytes(w, buf, strlen(buf));
}

static void write_vec(hk_Writer *w, const float *p)
{
    hk_writer_bytes(w, "(", 1);
    hk_writer_float_text(w, p[0]);
    hk_writer_bytes(w, ", ", 2);
    hk_writer_float_text(w, p[1]);
    hk_writer_bytes(w, ", ", 2);
    hk_writer_float_text(w, p[2]);
    hk_writer_bytes(w, ")", 1);
}

hk_Status hk_usda_hair_save(const char *path, const hk_HairFile *h, double meters_per_unit, hk_Error *err)
{
    if (meters_per_unit == 0.0) meters_per_unit = 1.0;
    if (!(meters_per_unit > 0.0) || !isfinite(meters_per_unit))
        return hk_error_set(err, HK_ERR_INVALID, "%s: metersPerUnit must be > 0, got %g", path, meters_per_unit);
    hk_Writer w;
    hk_Status st = hk_writer_open(&w, path, err);
    if (st != HK_OK) return st;
    hk_writer_printf(&w,
                     "#usda 1.0\n(\n    doc = \"hairkit %s: %u strands, %u points\"\n    defaultPrim = \"hair\"\n"
                     "    metersPerUnit = ",
                     hk_version(), h->strand_count, h->point_count);
    write_double(&w, meters_per_unit);
    hk_writer_printf(&w, "\n    upAxis = \"Y\"\n)\n\ndef BasisCurves \"hair\"\n{\n"
                         "    uniform token type = \"linear\"\n    uniform token wrap = \"nonperiodic\"\n"
                         "    int[] curveVertexCounts = [");
    for (uint32_t s = 0; s < h->strand_count; s++)
        hk_writer_printf(&w, "%s%u", s == 0 ? "" : s % 16 ? ", " : ",\n        ", hk_hair_strand_points(h, s));
    hk_writer_printf(&w, "]\n");
    if (h->point_count) {
        float lo[3], hi[3];
        memcpy(lo, h->points, sizeof lo);
        memcpy(hi, h->points, sizeof hi);
        for (size_t i = 0; i < h->point_count; i++)
            for (int k = 0; k < 3; k++) {
                const float v = h->points[3 * i + (size_t)k];
                lo[k] = v < lo[k] ? v : lo[k];
                hi[k] = v > hi[k] ? v : hi[k];
            }
        hk_writer_printf(&w, "    float3[] extent = [");
        write_vec(&w, lo);
        hk_writer_printf(&w, ", ");
        write_vec(&w, hi);
        hk_writer_printf(&w, "]\n");
    }
    hk_writer_printf(&w, "    point3f[] points = [");
    for (size_t i = 0; i < h->point_count; i++) {
        if (i) hk_writer_printf(&w, i % 4 ? ", " : ",\n        ");
        write_vec(&w, h->points + 3 * i);
    }
    hk_writer_printf(&w, "]\n");
    if ((h->flags & HK_HAIR_THICKNESS) && h->thickness) {
        hk_writer_printf(&w, "    float[] widths = [");
        for (size_t i = 0; i < h->point_count; i++) {
            if (i) hk_writer_printf(&w, i % 8 ? ", " : ",\n        ");
            hk_writer_float_text(&w, h->thickness[i]);
        }
        hk_writer_printf(&w, "] (\n        interpolation = \"vertex\"\n    )\n");
    } else {
        hk_writer_printf(&w, "    float[] widths = [");
        hk_writer_float_text(&w, h->default_thickness);
        hk_writer_printf(&w, "] (\n        interpolation = \"constant\"\n    )\n");
    }
    hk_writer_printf(&w, "}\n");
    return hk_writer_commit(&w, err);
}
