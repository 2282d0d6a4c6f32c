/* Imported-guides files (docs/file-formats.md, "Imported guides"; hairkit/capture.h):
 *     HairkitImport 1
 *     StrandsFile   strands.hair          the captured strands, .hair, beside this file
 *     Strands       11400
 *     Guides        300
 *     StationStep   0.001
 *     Material      muJ EI1 EI2  rho_l  Ir0 Ir1 Ir2  gx gy gz
 *     Guide   c strand                    then, in this order:
 *     Root    x y z
 *     Frame   9 numbers, row by row
 *     Lengths l_1 ... l_N
 *     QRest   3N numbers (tau kappa1 kappa2 per element)
 *     Q       3N numbers
 *     Attach  i  g0 w0  g1 w1  g2 w2       one per strand, in order (g -1: unused)
 * Doubles are written with 17 digits: read back exactly. Every error names the file and
 * line; the counts are checked against the file's lines before anything is allocated. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "hairkit/capture.h"
#include "io/keyfile.h"
#include "io/outfile.h"

#define HK_IMPORT_VERSION 1

static int write_doubles(FILE *fp, const char *key, const double *v, int count)
{
    int ok = fputs(key, fp) >= 0;
    for (int i = 0; i < count && ok; i++) ok = fprintf(fp, " %.17g", v[i]) > 0;
    return ok && fputc('\n', fp) != EOF;
}

/* Directory part of path with a trailing slash ("" when none). */
static void folder_of(const char *path, char *buf, size_t size)
{
    const char *slash = strrchr(path, '/');
    const size_t n = slash ? (size_t)(slash - path + 1) : 0;
    if (n >= size) {
        buf[0] = '\0';
        return;
    }
    memcpy(buf, path, n);
    buf[n] = '\0';
}

hk_Status hk_imported_groom_save(const char *path, const char *strands_file, const hk_ImportedGroom *g, hk_Error *err)
{
    if (!strands_file || !*strands_file || strchr(strands_file, '"') || strchr(strands_file, '\n'))
        return hk_error_set(err, HK_ERR_INVALID, "%s: the strands file needs a plain name", path);
    /* the strands first, beside the guides file */
    char dir[4096], spath[8192];
    folder_of(path, dir, sizeof dir);
    if (snprintf(spath, sizeof spath, "%s%s", strands_file[0] == '/' ? "" : dir, strands_file) >= (int)sizeof spath)
        return hk_error_set(err, HK_ERR_INVALID, "%s: name too long", path);
    hk_HairFile h;
    memset(&h, 0, sizeof h);
    h.strand_count = (uint32_t)g->strand_count;
    h.point_count = g->first_point[g->strand_count];
    h.flags = HK_HAIR_POINTS | HK_HAIR_SEGMENTS;
    h.default_thickness = 8e-5f; /* a diameter of 80 um, in metres */
    h.default_transparency = 0.0f;
    h.points = g->points;
    h.first_point = g->first_point;
    h.segments = hk_alloc_array((size_t)g->strand_count, sizeof(uint16_t), err);
    if (!h.segments) return HK_ERR_NOMEM;
    hk_Status st = HK_OK;
    for (int i = 0; i < g->strand_count && st == HK_OK; i++) {
        const uint32_t seg = g->first_point[i + 1] - g->first_point[i] - 1;
        if (seg > 65535)
            st = hk_error_set(err, HK_ERR_INVALID, "strand %d has %u segments: a .hair holds 65535", i, seg);
        else
            h.segments[i] = (uint16_t)seg;
    }
    if (st == HK_OK) st = hk_hair_save(spath, &h, err);
    hk_free(h.segments);
    if (st != HK_OK) return st;

    hk_OutFile of;
    st = hk_outfile_open(&of, path, err);
    if (st != HK_OK) return st;
    FILE *fp = of.fp;
    const hk_RodMaterial *m = &g->material;
    const double mat[10] = {m->stiffness[0],      m->stiffness[1],      m->stiffness[2],      m->mass_per_length,
                            m->rotary_inertia[0], m->rotary_inertia[1], m->rotary_inertia[2], m->gravity.x,
                            m->gravity.y,         m->gravity.z};
    int ok = fprintf(fp,
                     "# hairkit imported guides (docs/file-formats.md, \"Imported guides\")\n"
                     "HairkitImport %d\nStrandsFile \"%s\"\nStrands %d\nGuides %d\nStationStep %.17g\n",
                     HK_IMPORT_VERSION, strands_file, g->strand_count, g->guide_count, g->station_step) > 0;
    ok = ok && write_doubles(fp, "Material", mat, 10);
    for (int c = 0; c < g->guide_count && ok; c++) {
        const hk_SuperHelix *sh = g->guide[c];
        const hk_Mat3 *f = &sh->root_frame;
        const double frame[9] = {f->m[0][0], f->m[0][1], f->m[0][2], f->m[1][0], f->m[1][1],
                                 f->m[1][2], f->m[2][0], f->m[2][1], f->m[2][2]};
        const double root[3] = {sh->root.x, sh->root.y, sh->root.z};
        ok = fprintf(fp, "\nGuide %d %d\n", c, g->guide_strand[c]) > 0 && write_doubles(fp, "Root", root, 3) &&
             write_doubles(fp, "Frame", frame, 9) && write_doubles(fp, "Lengths", sh->length, sh->n) &&
             write_doubles(fp, "QRest", sh->q_rest, 3 * sh->n) && write_doubles(fp, "Q", sh->q, 3 * sh->n);
    }
    ok = ok && fputc('\n', fp) != EOF;
    for (int i = 0; i < g->strand_count && ok; i++) {
        ok = fprintf(fp, "Attach %d", i) > 0;
        for (int a = 0; a < HK_IMPORT_ATTACH && ok; a++)
            ok = fprintf(fp, " %d %.17g", g->attach_guide[(size_t)i * HK_IMPORT_ATTACH + (size_t)a],
                         g->attach_weight[(size_t)i * HK_IMPORT_ATTACH + (size_t)a]) > 0;
        ok = ok && fputc('\n', fp) != EOF;
    }
    if (!ok) {
        hk_outfile_abort(&of);
        return hk_error_set(err, HK_ERR_IO, "%s: cannot write", path);
    }
    const long size = ftell(fp);
    if (size > HK_MAX_IMPORT_FILE_BYTES) { /* the reader would refuse it */
        hk_outfile_abort(&of);
        return hk_error_set(err, HK_ERR_INVALID,
                            "%s: %d guides and %d strands take %ld bytes, more than the %ld an imported-guides file "
                            "may have (fewer guides: --guides)",
                            path, g->guide_count, g->strand_count, size, HK_MAX_IMPORT_FILE_BYTES);
    }
    return hk_outfile_commit(&of, err);
}

/* The line at *at with key `key`, or an error naming what was expected. */
static hk_Status expect(const hk_KeyFile *kf, int at, const char *key, const hk_KeyLine **out, hk_Error *err)
{
    if (at >= kf->line_count)
        return hk_keyfile_error(kf, kf->line_count > 0 ? kf->lines[kf->line_count - 1].line : 0, HK_ERR_PARSE, err,
                                "the file ends where %s was expected", key);
    if (!hk_key_equal(kf->lines[at].key, key))
        return hk_keyfile_error(kf, kf->lines[at].line, HK_ERR_PARSE, err, "expected %s, got '%s'", key,
                                kf->lines[at].key);
    *out = &kf->lines[at];
    return HK_OK;
}

static hk_Status expect_int(const hk_KeyFile *kf, int at, const char *key, long lo, long hi, long *v, hk_Error *err)
{
    const hk_KeyLine *kl;
    hk_Status st = expect(kf, at, key, &kl, err);
    return st == HK_OK ? hk_keyline_int(kf, kl, lo, hi, v, err) : st;
}

static hk_Status expect_doubles(const hk_KeyFile *kf, int at, const char *key, int count, double *v, hk_Error *err)
{
    const hk_KeyLine *kl;
    hk_Status st = expect(kf, at, key, &kl, err);
    return st == HK_OK ? hk_keyline_doubles(kf, kl, count, v, err) : st;
}

/* Guide c's block of 6 lines from line `at`. */
static hk_Status read_guide(const hk_KeyFile *kf, int at, int c, hk_ImportedGroom *g, hk_Error *err)
{
    const hk_KeyLine *kl;
    double v[9];
    hk_Status st = expect(kf, at, "Guide", &kl, err);
    if (st != HK_OK) return st;
    if (kl->count != 2)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "Guide takes its index and its strand");
    double idx[2];
    if ((st = hk_keyline_doubles(kf, kl, 2, idx, err)) != HK_OK) return st;
    if (idx[0] != c || !(idx[1] >= 0 && idx[1] < g->strand_count && idx[1] == floor(idx[1])))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                "Guide %s %s: expected guide %d and a strand 0 to %d", kl->values[0], kl->values[1], c,
                                g->strand_count - 1);
    g->guide_strand[c] = (int)idx[1];
    const hk_KeyLine *lengths;
    if ((st = expect(kf, at + 3, "Lengths", &lengths, err)) != HK_OK) return st;
    const int n = lengths->count;
    if (n < 1 || n > HK_MAX_ELEMENTS)
        return hk_keyfile_error(kf, lengths->line, HK_ERR_INVALID, err, "%d element lengths: 1 to %d", n,
                                HK_MAX_ELEMENTS);
    double l[HK_MAX_ELEMENTS];
    if ((st = hk_keyline_doubles(kf, lengths, n, l, err)) != HK_OK) return st;
    for (int q = 0; q < n; q++)
        if (!(l[q] > 0.0))
            return hk_keyfile_error(kf, lengths->line, HK_ERR_INVALID, err, "element length %s: must be > 0",
                                    lengths->values[q]);
    if ((st = hk_superhelix_create(n, l, &g->guide[c], err)) != HK_OK) return st;
    hk_SuperHelix *sh = g->guide[c];
    sh->material = g->material;
    if ((st = expect_doubles(kf, at + 1, "Root", 3, v, err)) != HK_OK) return st;
    sh->root = hk_v3(v[0], v[1], v[2]);
    if ((st = expect_doubles(kf, at + 2, "Frame", 9, v, err)) != HK_OK) return st;
    for (int r = 0; r < 3; r++)
        for (int k = 0; k < 3; k++) sh->root_frame.m[r][k] = v[3 * r + k];
    /* a rotation: orthonormal columns, determinant +1 */
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) {
            const double d = hk_v3_dot(hk_m3_col(&sh->root_frame, a), hk_m3_col(&sh->root_frame, b));
            if (fabs(d - (a == b ? 1.0 : 0.0)) > 1e-6)
                return hk_keyfile_error(kf, kf->lines[at + 2].line, HK_ERR_INVALID, err,
                                        "Frame is not a rotation (columns %d and %d: dot %.3g)", a, b, d);
        }
    if ((st = expect_doubles(kf, at + 4, "QRest", 3 * n, sh->q_rest, err)) != HK_OK) return st;
    return expect_doubles(kf, at + 5, "Q", 3 * n, sh->q, err);
}

hk_Status hk_imported_groom_load(const char *path, hk_ImportedGroom *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read_limited(path, HK_MAX_IMPORT_FILE_BYTES, &kf, err);
    if (st != HK_OK) return st;
    hk_ImportedGroom *g = out;
    long version = 0, strands = 0, guides = 0;
    const hk_KeyLine *kl = NULL;
    const char *strands_file = NULL;
    double step = 0.0, mat[10];
    st = expect_int(&kf, 0, "HairkitImport", 0, 1000000, &version, err);
    if (st == HK_OK && version != HK_IMPORT_VERSION)
        st = hk_keyfile_error(&kf, kf.lines[0].line, HK_ERR_PARSE, err,
                              "version %ld: this hairkit reads imported guides of version %d", version,
                              HK_IMPORT_VERSION);
    if (st == HK_OK) st = expect(&kf, 1, "StrandsFile", &kl, err);
    if (st == HK_OK) st = hk_keyline_string(&kf, kl, &strands_file, err);
    /* every strand has its Attach line, every guide its 6: bounded by the file */
    if (st == HK_OK) st = expect_int(&kf, 2, "Strands", 1, kf.line_count, &strands, err);
    if (st == HK_OK) st = expect_int(&kf, 3, "Guides", 1, strands, &guides, err);
    if (st == HK_OK && 6 + 6 * guides + strands != kf.line_count)
        st = hk_keyfile_error(&kf, kf.lines[3].line, HK_ERR_PARSE, err,
                              "%ld strands and %ld guides take %ld lines, the file has %d", strands, guides,
                              6 + 6 * guides + strands, kf.line_count);
    if (st == HK_OK) st = expect_doubles(&kf, 4, "StationStep", 1, &step, err);
    if (st == HK_OK && !(step > 0.0))
        st = hk_keyfile_error(&kf, kf.lines[4].line, HK_ERR_INVALID, err, "StationStep must be > 0");
    if (st == HK_OK) st = expect_doubles(&kf, 5, "Material", 10, mat, err);
    if (st == HK_OK) {
        g->strand_count = (int)strands;
        g->guide_count = (int)guides;
        g->station_step = step;
        g->material.stiffness[0] = mat[0], g->material.stiffness[1] = mat[1], g->material.stiffness[2] = mat[2];
        g->material.mass_per_length = mat[3];
        g->material.rotary_inertia[0] = mat[4], g->material.rotary_inertia[1] = mat[5];
        g->material.rotary_inertia[2] = mat[6];
        g->material.gravity = hk_v3(mat[7], mat[8], mat[9]);
        for (int i = 0; i < 7; i++)
            if (!(mat[i] > 0.0))
                st = hk_keyfile_error(&kf, kf.lines[5].line, HK_ERR_INVALID, err,
                                      "Material: stiffnesses, mass and inertias must be > 0");
    }
    if (st == HK_OK) {
        g->guide_strand = hk_alloc_array((size_t)guides, sizeof(int), err);
        g->guide = hk_calloc_array((size_t)guides, sizeof(hk_SuperHelix *), err);
        g->attach_guide = hk_alloc_array((size_t)strands * HK_IMPORT_ATTACH, sizeof(int), err);
        g->attach_weight = hk_alloc_array((size_t)strands * HK_IMPORT_ATTACH, sizeof(double), err);
        if (!g->guide_strand || !g->guide || !g->attach_guide || !g->attach_weight) st = HK_ERR_NOMEM;
    }
    for (int c = 0; st == HK_OK && c < g->guide_count; c++) st = read_guide(&kf, 6 + 6 * c, c, g, err);
    for (int i = 0; st == HK_OK && i < g->strand_count; i++) {
        const int at = 6 + 6 * g->guide_count + i;
        st = expect(&kf, at, "Attach", &kl, err);
        double v[1 + 2 * HK_IMPORT_ATTACH];
        if (st == HK_OK) st = hk_keyline_doubles(&kf, kl, 1 + 2 * HK_IMPORT_ATTACH, v, err);
        if (st == HK_OK && v[0] != i)
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err, "expected Attach %d, got %s", i, kl->values[0]);
        double sum = 0.0;
        for (int a = 0; st == HK_OK && a < HK_IMPORT_ATTACH; a++) {
            const double gi = v[1 + 2 * a], w = v[2 + 2 * a];
            if (!(gi == floor(gi) && gi >= -1 && gi < g->guide_count) || !(w >= 0.0 && w <= 1.0) ||
                (gi < 0 && w != 0.0))
                st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err,
                                      "attachment %d: guide %s (-1 or 0 to %d) with weight %s (0 to 1; 0 for -1)", a,
                                      kl->values[1 + 2 * a], g->guide_count - 1, kl->values[2 + 2 * a]);
            if (st != HK_OK) break;
            g->attach_guide[(size_t)i * HK_IMPORT_ATTACH + (size_t)a] = (int)gi;
            g->attach_weight[(size_t)i * HK_IMPORT_ATTACH + (size_t)a] = w;
            sum += w;
        }
        if (st == HK_OK && fabs(sum - 1.0) > 1e-9)
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err, "the weights sum to %.17g, not 1", sum);
    }
    /* the captured strands */
    if (st == HK_OK) {
        char *spath = hk_keyfile_resolve_path(&kf, strands_file, err);
        hk_HairFile h;
        memset(&h, 0, sizeof h);
        st = spath ? hk_hair_load(spath, &h, err) : HK_ERR_NOMEM;
        if (st == HK_OK && h.strand_count != (uint32_t)g->strand_count)
            st = hk_keyfile_error(&kf, kf.lines[2].line, HK_ERR_PARSE, err, "%s holds %u strands, not %d", spath,
                                  h.strand_count, g->strand_count);
        for (int c = 0; st == HK_OK && c < g->guide_count; c++)
            if (hk_hair_strand_points(&h, (uint32_t)g->guide_strand[c]) < 2)
                st = hk_error_set(err, HK_ERR_PARSE, "%s: strand %d of guide %d has fewer than 2 points", spath,
                                  g->guide_strand[c], c);
        if (st == HK_OK) {
            g->first_point = h.first_point, h.first_point = NULL;
            g->points = h.points, h.points = NULL;
        }
        hk_hair_free(&h);
        hk_free(spath);
    }
    hk_keyfile_free(&kf);
    if (st != HK_OK) hk_imported_groom_free(g);
    return st;
}
