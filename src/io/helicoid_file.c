/* Helicoid files (docs/file-formats.md, "Helicoid file"): global keys, then one block
 * per strand opened by `Strand`:
 *     Step      0.002
 *     Waviness  0.0005 300
 *     Strand
 *     Root      x y z
 *     Frame     tx ty tz  nx ny nz      E_T and E_N at the root (E_B = E_T x E_N)
 *     Piece     kT kN kB alpha length   one line per helicoid piece, root to tip
 *     Wisp      count radius spread     optional (Piuze et al. 2011 §3.3)
 * Every error names the file and line. */
#include <math.h>
#include <string.h>

#include "hairkit/helicoid_file.h"
#include "io/outfile.h"
#include "io/keyfile.h"

void hk_helicoid_set_free(hk_HelicoidSet *set)
{
    if (!set) return;
    hk_free(set->strands);
    hk_free(set->wisp_count);
    hk_free(set->wisp_radius);
    hk_free(set->wisp_spread);
    hk_free(set->has_waves);
    hk_free(set->waves);
    memset(set, 0, sizeof *set);
    set->step = 0.002;
}

hk_Status hk_helicoid_set_alloc(hk_HelicoidSet *set, int count, hk_Error *err)
{
    memset(set, 0, sizeof *set);
    set->step = 0.002;
    if (count < 0 || count > HK_HELICOID_FILE_MAX_STRANDS)
        return hk_error_set(err, HK_ERR_INVALID, "%d strands: at most %d", count, HK_HELICOID_FILE_MAX_STRANDS);
    const size_t n = count > 0 ? (size_t)count : 1;
    set->strands = hk_calloc_array(n, sizeof *set->strands, err);
    set->wisp_count = hk_calloc_array(n, sizeof *set->wisp_count, err);
    set->wisp_radius = hk_calloc_array(n, sizeof *set->wisp_radius, err);
    set->wisp_spread = hk_calloc_array(n, sizeof *set->wisp_spread, err);
    set->has_waves = hk_calloc_array(n, sizeof *set->has_waves, err);
    set->waves = hk_calloc_array(n, sizeof *set->waves, err);
    if (!set->strands || !set->wisp_count || !set->wisp_radius || !set->wisp_spread || !set->has_waves || !set->waves) {
        hk_helicoid_set_free(set);
        return HK_ERR_NOMEM;
    }
    set->count = count;
    return HK_OK;
}

typedef struct Block {
    int line;               /* of its `Strand` */
    int root, frame, waves; /* lines that gave them, 0 when absent */
} Block;

/* HK_OK when `name` was not given yet in the strand (first == 0), else the error that
 * names the line of its first. */
static hk_Status once_a_strand(const hk_KeyFile *kf, const hk_KeyLine *kl, const char *name, int first, hk_Error *err)
{
    if (!first) return HK_OK;
    return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err, "second %s in a strand (first at line %d)", name, first);
}

/* Ends the strand opened at b: it needs a root, a frame and a piece. */
static hk_Status close_block(const hk_KeyFile *kf, const Block *b, const hk_PHelicoid *h, hk_Error *err)
{
    if (!b->root) return hk_keyfile_error(kf, b->line, HK_ERR_PARSE, err, "Strand has no Root");
    if (!b->frame) return hk_keyfile_error(kf, b->line, HK_ERR_PARSE, err, "Strand has no Frame");
    if (h->piece_count < 1) return hk_keyfile_error(kf, b->line, HK_ERR_PARSE, err, "Strand has no Piece");
    return HK_OK;
}

static hk_Status read_frame(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Mat3 *frame, hk_Error *err)
{
    double v[6];
    hk_Status st = hk_keyline_doubles(kf, kl, 6, v, err);
    if (st != HK_OK) return st;
    hk_Vec3 t = hk_v3(v[0], v[1], v[2]), n = hk_v3(v[3], v[4], v[5]);
    const double lt = hk_v3_norm(t), ln = hk_v3_norm(n);
    if (!(lt > 1e-12) || !(ln > 1e-12) || !isfinite(lt) || !isfinite(ln))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Frame needs two non-zero vectors (E_T, E_N)");
    /* Vectors that are unit and orthogonal to rounding are kept as written, so that a
     * saved file loads back to the same numbers; others are normalised and made
     * orthogonal (Gram-Schmidt), so the frame is a rotation to rounding. */
    if (fabs(lt - 1.0) > 1e-15) t = hk_v3_scale(t, 1.0 / lt);
    if (fabs(ln - 1.0) > 1e-15) n = hk_v3_scale(n, 1.0 / ln);
    const double cosine = hk_v3_dot(t, n);
    if (fabs(cosine) > 1e-3)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                "Frame: E_T and E_N must be orthogonal (their cosine is %.3g)", cosine);
    if (fabs(cosine) > 1e-15) n = hk_v3_normalize(hk_v3_madd(n, t, -cosine));
    *frame = hk_m3_from_cols(t, n, hk_v3_cross(t, n));
    return HK_OK;
}

static hk_Status read_piece(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_PHelicoid *h, hk_Error *err)
{
    double v[5];
    hk_Status st = hk_keyline_doubles(kf, kl, 5, v, err);
    if (st != HK_OK) return st;
    if (h->piece_count >= HK_HELICOID_MAX_PIECES)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "more than %d pieces in one strand",
                                HK_HELICOID_MAX_PIECES);
    if (!(v[4] > 0.0) || v[4] > 100.0)
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "piece length must be in (0, 100] m, got %s",
                                kl->values[4]);
    for (int i = 0; i < 4; i++)
        if (fabs(v[i]) > 1e6)
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "helicoid parameter %s is absurd (|k| <= 1e6)",
                                    kl->values[i]);
    hk_Helicoid *k = &h->k[h->piece_count];
    k->kt = v[0], k->kn = v[1], k->kb = v[2], k->alpha = v[3];
    h->length[h->piece_count++] = v[4];
    return HK_OK;
}

hk_Status hk_helicoid_file_load(const char *path, hk_HelicoidSet *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    out->step = 0.002;
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    /* Count the strands first: the arrays have exactly that size. */
    int strands = 0;
    for (int i = 0; i < kf.line_count; i++)
        if (hk_key_equal(kf.lines[i].key, "Strand")) {
            if (++strands > HK_HELICOID_FILE_MAX_STRANDS) {
                st = hk_keyfile_error(&kf, kf.lines[i].line, HK_ERR_INVALID, err, "more than %d strands",
                                      HK_HELICOID_FILE_MAX_STRANDS);
                break;
            }
        }
    if (st == HK_OK && strands == 0) st = hk_keyfile_error(&kf, 0, HK_ERR_PARSE, err, "no Strand in the file");
    if (st == HK_OK) st = hk_helicoid_set_alloc(out, strands, err);
    int current = -1, step_line = 0, wave_line = 0;
    Block block = {0, 0, 0, 0};
    for (int i = 0; i < kf.line_count && st == HK_OK; i++) {
        const hk_KeyLine *kl = &kf.lines[i];
        hk_PHelicoid *h = current >= 0 ? &out->strands[current] : NULL;
        if (hk_key_equal(kl->key, "Strand")) {
            if (kl->count != 0) {
                st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "Strand takes no values");
            } else if (h && (st = close_block(&kf, &block, h, err)) == HK_OK) {
                current++;
            } else if (!h) {
                current = 0;
            }
            block = (Block){kl->line, 0, 0, 0};
        } else if (hk_key_equal(kl->key, "Step") || hk_key_equal(kl->key, "Waviness")) {
            const int is_step = hk_key_equal(kl->key, "Step");
            int *seen = is_step ? &step_line : &wave_line;
            double v[3] = {0.0, 0.0, 0.0};
            if (current >= 0)
                st =
                    hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "%s must come before the first Strand", kl->key);
            else if (*seen)
                st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "duplicate key '%s' (first given at line %d)",
                                      kl->key, *seen);
            else if (!is_step && kl->count != 2 && kl->count != 3)
                st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err,
                                      "Waviness expects 2 or 3 numbers (amplitude, frequency[, phase jitter]), got %d",
                                      kl->count);
            else if ((st = hk_keyline_doubles(&kf, kl, is_step ? 1 : kl->count, v, err)) == HK_OK) {
                *seen = kl->line;
                if (is_step && !(v[0] > 0.0 && v[0] <= 1.0))
                    st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err, "Step must be in (0, 1] m, got %s",
                                          kl->values[0]);
                else if (!is_step &&
                         !(v[0] >= 0.0 && v[1] >= 0.0 && v[0] <= 1.0 && v[1] <= 1e6 && v[2] >= 0.0 && v[2] <= 1.0))
                    st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err,
                                          "Waviness needs an amplitude in [0, 1] m, a frequency in [0, 1e6] rad/m "
                                          "and optionally a phase jitter in [0, 1] turns");
                else if (is_step)
                    out->step = v[0];
                else {
                    out->waviness = (hk_Waviness){v[0], v[1], 0.0};
                    out->wave_jitter = v[2];
                }
            }
        } else if (!h) {
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err, "'%s' before the first Strand", kl->key);
        } else if (hk_key_equal(kl->key, "Root")) {
            double v[3];
            if ((st = once_a_strand(&kf, kl, "Root", block.root, err)) == HK_OK &&
                (st = hk_keyline_doubles(&kf, kl, 3, v, err)) == HK_OK) {
                h->root = hk_v3(v[0], v[1], v[2]);
                block.root = kl->line;
            }
        } else if (hk_key_equal(kl->key, "Frame")) {
            if ((st = once_a_strand(&kf, kl, "Frame", block.frame, err)) == HK_OK &&
                (st = read_frame(&kf, kl, &h->frame, err)) == HK_OK)
                block.frame = kl->line;
        } else if (hk_key_equal(kl->key, "Piece")) {
            st = read_piece(&kf, kl, h, err);
        } else if (hk_key_equal(kl->key, "Waves")) {
            double v[3];
            if ((st = once_a_strand(&kf, kl, "Waves", block.waves, err)) == HK_OK &&
                (st = hk_keyline_doubles(&kf, kl, 3, v, err)) == HK_OK) {
                if (!(v[0] >= 0.0 && v[0] <= 1.0) || !(v[1] >= 0.0 && v[1] <= 1e6) || !(fabs(v[2]) <= 1e6))
                    st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err,
                                          "Waves needs an amplitude in [0, 1] m, a frequency in [0, 1e6] rad/m and "
                                          "a phase within +-1e6 rad");
                else {
                    out->has_waves[current] = 1;
                    out->waves[current] = (hk_Waviness){v[0], v[1], v[2]};
                    block.waves = kl->line;
                }
            }
        } else if (hk_key_equal(kl->key, "Wisp")) {
            double v[3];
            if ((st = hk_keyline_doubles(&kf, kl, 3, v, err)) == HK_OK) {
                if (!(v[0] >= 0.0 && v[0] <= 100000.0 && v[0] == floor(v[0])) || !(v[1] >= 0.0 && v[1] <= 1.0) ||
                    !(v[2] >= 0.0 && v[2] <= 3.2))
                    st = hk_keyfile_error(&kf, kl->line, HK_ERR_INVALID, err,
                                          "Wisp needs a whole count in [0, 100000], a radius in [0, 1] m and a "
                                          "spread in [0, pi] rad");
                else {
                    out->wisp_count[current] = (int)v[0];
                    out->wisp_radius[current] = v[1];
                    out->wisp_spread[current] = v[2];
                }
            }
        } else {
            st = hk_keyfile_error(&kf, kl->line, HK_ERR_PARSE, err,
                                  "unknown key '%s' (helicoid files know Step, Waviness, Strand, Root, Frame, "
                                  "Piece, Waves, Wisp)",
                                  kl->key);
        }
    }
    if (st == HK_OK && current >= 0) st = close_block(&kf, &block, &out->strands[current], err);
    hk_keyfile_free(&kf);
    if (st != HK_OK) hk_helicoid_set_free(out);
    return st;
}

hk_Status hk_helicoid_file_save(const char *path, const hk_HelicoidSet *set, const char *comment, hk_Error *err)
{
    hk_OutFile of;
    hk_Status st = hk_outfile_open(&of, path, err);
    if (st != HK_OK) return st;
    FILE *fp = of.fp;
    int ok = 1;
    if (comment) ok &= fprintf(fp, "# %s\n", comment) > 0;
    ok &= fprintf(fp, "# hairkit helicoid file (docs/file-formats.md)\nStep %.17g\n", set->step) > 0;
    if (set->waviness.amplitude > 0.0 && set->wave_jitter > 0.0)
        ok &= fprintf(fp, "Waviness %.17g %.17g %.17g\n", set->waviness.amplitude, set->waviness.frequency,
                      set->wave_jitter) > 0;
    else if (set->waviness.amplitude > 0.0)
        ok &= fprintf(fp, "Waviness %.17g %.17g\n", set->waviness.amplitude, set->waviness.frequency) > 0;
    for (int s = 0; s < set->count && ok; s++) {
        const hk_PHelicoid *h = &set->strands[s];
        const hk_Vec3 t = hk_m3_col(&h->frame, 0), n = hk_m3_col(&h->frame, 1);
        ok &= fprintf(fp, "\nStrand\nRoot %.17g %.17g %.17g\nFrame %.17g %.17g %.17g  %.17g %.17g %.17g\n", h->root.x,
                      h->root.y, h->root.z, t.x, t.y, t.z, n.x, n.y, n.z) > 0;
        for (int p = 0; p < h->piece_count && ok; p++)
            ok &= fprintf(fp, "Piece %.17g %.17g %.17g %.17g %.17g\n", h->k[p].kt, h->k[p].kn, h->k[p].kb,
                          h->k[p].alpha, h->length[p]) > 0;
        if (set->has_waves && set->has_waves[s])
            ok &= fprintf(fp, "Waves %.17g %.17g %.17g\n", set->waves[s].amplitude, set->waves[s].frequency,
                          set->waves[s].phase) > 0;
        if (set->wisp_count && set->wisp_count[s] > 0)
            ok &=
                fprintf(fp, "Wisp %d %.17g %.17g\n", set->wisp_count[s], set->wisp_radius[s], set->wisp_spread[s]) > 0;
    }
    if (!ok) {
        hk_outfile_abort(&of);
        return hk_error_set(err, HK_ERR_IO, "%s: cannot write", path);
    }
    return hk_outfile_commit(&of, err);
}
