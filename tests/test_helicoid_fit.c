/* Fitting p-helicoids (Piuze et al. 2011 §5) with the helicoid piece as the model of the
 * piecewise fitter: strands traced from known parameters are fitted back (the
 * reference: the parameters they were made from), single pieces and two pieces; the
 * fitted strand retraces the target; bad input is refused. */
#include "hk_test.h"
#include "hk_test_curves.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/hairfile.h"
#include "hairkit/helicoid_file.h"
#include "hairkit/helicoid_fit.h"
#include "hairkit/helicoid_hair.h"

static double rnd(double lo, double hi) { return lo + (hi - lo) * hk_test_uniform(); }

/* A 30-point strand (the paper's data: about 30 vertices per hair) traced from h. */
static int trace30(const hk_PHelicoid *h, hk_Vec3 *pts)
{
    const double step = hk_phelicoid_length(h) / 29.0;
    hk_Error err;
    assert_int_equal(hk_phelicoid_point_count(h, step), 30);
    assert_int_equal(hk_phelicoid_trace(h, step, NULL, NULL, pts, NULL, &err), HK_OK);
    return 30;
}

/* Single helicoids with random parameters and root frames, fitted back from 30 points.
 * The reference is the parameters they were traced from. k_T and alpha show in every
 * strand (the initial curvature vector is k_T (E_N + alpha E_B)); k_N and k_B only
 * through the shape they bend far from the root (k_B acts through phi = alpha theta, not
 * at all when alpha = 0), so for them the shape is the check: the mean leash. */
static void fit_single_pieces(int method, double tolerance, int check_params, int must_recover)
{
    hk_Error err;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(512, &err);
    assert_non_null(f);
    int recovered = 0;
    const int trials = 20;
    for (int t = 0; t < trials; t++) {
        hk_PHelicoid h;
        memset(&h, 0, sizeof h);
        h.root = hk_v3(rnd(-0.1, 0.1), rnd(0, 0.2), rnd(-0.1, 0.1));
        h.frame = hk_helicoid_frame(rnd(-3, 3), rnd(-1.2, 1.2));
        h.piece_count = 1;
        h.k[0] = (hk_Helicoid){rnd(2, 30), rnd(-5, 5), rnd(-10, 10), rnd(-0.5, 0.5)};
        h.length[0] = rnd(0.05, 0.15);
        hk_Vec3 pts[30];
        trace30(&h, pts);
        hk_CurveFitDef opt = hk_default_helicoid_fit_def();
        opt.method = method;
        opt.tolerance = 1e-7; /* a strand the model can make exactly */
        opt.max_pieces = 1;
        opt.lambda = 0.0;
        hk_PHelicoid fit;
        hk_CurveFit report;
        assert_int_equal(hk_helicoid_fit(f, pts, 30, &opt, &fit, &report, &err), HK_OK);
        const int ok =
            report.error < tolerance && (!check_params || (fabs(fit.k[0].kt - h.k[0].kt) < 1e-3 * h.k[0].kt &&
                                                           fabs(fit.k[0].alpha - h.k[0].alpha) < 1e-3));
        if (ok)
            recovered++;
        else
            print_message("trial %d: error %.3g m, k = (%g %g %g %g) fitted (%g %g %g %g)\n", t, report.error,
                          h.k[0].kt, h.k[0].kn, h.k[0].kb, h.k[0].alpha, fit.k[0].kt, fit.k[0].kn, fit.k[0].kb,
                          fit.k[0].alpha);
        /* retracing the fit gives back the target to the reported error */
        hk_Vec3 again[30];
        trace30(&fit, again);
        double worst = 0.0;
        for (int i = 0; i < 30; i++) worst = fmax(worst, hk_v3_dist(again[i], pts[i]));
        assert_true(worst <= 10.0 * report.frechet + 1e-9);
    }
    print_message("  %s: %d of %d single helicoids recovered (mean leash < %g m%s)\n",
                  method == HK_CURVEFIT_LEAST_SQUARES ? "least squares" : "Nelder-Mead", recovered, trials, tolerance,
                  check_params ? ", k_T to 0.1%, alpha to 1e-3" : "");
    assert_true(recovered >= must_recover);
    hk_helicoid_fitter_destroy(f);
}

/* Least squares from the curvature seed, the root frame rolled by atan(alpha): every
 * one, to a micron, with its parameters (the target is resampled by estimated arc
 * length, and a fit above 0.1 um refines the root frame the first points estimate). */
static void test_single_pieces_recovered(void **state)
{
    (void)state;
    fit_single_pieces(HK_CURVEFIT_LEAST_SQUARES, 1e-6, 1, 20);
}

/* The paper's Nelder-Mead on the coupling is local and slow to close in: most shapes,
 * to 50 um. */
static void test_single_pieces_nelder_mead(void **state)
{
    (void)state;
    fit_single_pieces(HK_CURVEFIT_NELDER_MEAD, 5e-5, 0, 16);
}

static void test_two_pieces(void **state)
{
    (void)state;
    hk_Error err;
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(512, &err);
    hk_PHelicoid h;
    memset(&h, 0, sizeof h);
    h.frame = hk_helicoid_frame(0.3, -0.4);
    h.piece_count = 2;
    h.k[0] = (hk_Helicoid){8, 1, 3, 0.2};
    h.k[1] = (hk_Helicoid){40, -2, 0, 0.3};
    h.length[0] = 0.08;
    h.length[1] = 0.08;
    hk_Vec3 pts[61];
    const double step = 0.16 / 60.0; /* 30 steps per piece */
    assert_int_equal(hk_phelicoid_point_count(&h, step), 61);
    assert_int_equal(hk_phelicoid_trace(&h, step, NULL, NULL, pts, NULL, &err), HK_OK);
    hk_CurveFitDef opt = hk_default_helicoid_fit_def();
    opt.tolerance = 1e-4; /* four times the fitter's resampling floor (see above) */
    hk_PHelicoid fit;
    hk_CurveFit report;
    assert_int_equal(hk_helicoid_fit(f, pts, 61, &opt, &fit, &report, &err), HK_OK);
    print_message("two pieces: %d pieces, error %.3g m, Frechet %.3g m\n", fit.piece_count, report.error,
                  report.frechet);
    /* The fitter cuts at the longest prefix a piece follows within the tolerance, whose
     * end tangent leaves the rest on course: the join itself (sample 30). */
    assert_int_equal(fit.piece_count, 2);
    assert_true(abs(report.first_sample[1] - 30) <= 1);
    assert_true(report.error <= 0.1 * opt.tolerance);
    hk_assert_near(hk_phelicoid_length(&fit), 0.16, 1e-3);
    hk_helicoid_fitter_destroy(f);
}

/* Paper §5.4: a tuft reconstructed from one strand in ten, by inverse-distance blending
 * of their fits. The tuft's strands are themselves blends of four-piece guides, so the
 * reference is the same reconstruction from the sampled strands' true parameters: what
 * the inverse-distance blend alone can do. Fits on the common four-piece layout must come
 * close to it; fits that split each strand its own way cannot be blended piece by piece. */
enum { TUFT = 300, TUFT_POINTS = 41 };

static double tuft_error(const hk_PHelicoid *guides, int count, hk_Vec3 (*original)[TUFT_POINTS])
{
    double sum = 0.0;
    for (int i = 0; i < TUFT; i++) {
        hk_PHelicoid h;
        hk_Vec3 again[4 * TUFT_POINTS];
        assert_int_equal(hk_phelicoid_interpolate(guides, count, original[i][0], NULL, 3.0, &h, NULL), HK_OK);
        const double step = hk_phelicoid_length(&h) / (TUFT_POINTS - 1);
        const int m = hk_phelicoid_point_count(&h, step);
        assert_true(m >= 2 && m <= 4 * TUFT_POINTS);
        assert_int_equal(hk_phelicoid_trace(&h, step, NULL, NULL, again, NULL, NULL), HK_OK);
        hk_FrechetMeasures fm;
        assert_int_equal(hk_frechet_measures(original[i], TUFT_POINTS, again, m, &fm, NULL), HK_OK);
        sum += fm.normalized;
    }
    return sum / TUFT;
}

static void test_reconstruction(void **state)
{
    (void)state;
    hk_PHelicoid guides[9];
    for (int i = 0; i < 9; i++) {
        memset(&guides[i], 0, sizeof guides[i]);
        guides[i].root = hk_v3(0.02 * (i % 3) - 0.02, 0.0, 0.02 * (i / 3) - 0.02);
        guides[i].frame = hk_m3_from_cols(hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(0, 0, 1));
        guides[i].piece_count = 4;
        for (int p = 0; p < 4; p++) {
            guides[i].k[p] = (hk_Helicoid){rnd(2, 30), rnd(-3, 3), rnd(-8, 8), rnd(-0.3, 0.3)};
            guides[i].length[p] = 0.05;
        }
    }
    static hk_Vec3 original[TUFT][TUFT_POINTS];
    static hk_PHelicoid truth[TUFT / 10], common[TUFT / 10], own[TUFT / 10];
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, NULL);
    assert_non_null(f);
    for (int i = 0; i < TUFT; i++) {
        hk_PHelicoid h;
        const hk_Vec3 root = hk_v3(rnd(-0.025, 0.025), 0.0, rnd(-0.025, 0.025));
        assert_int_equal(hk_phelicoid_interpolate(guides, 9, root, NULL, 3.0, &h, NULL), HK_OK);
        assert_int_equal(hk_phelicoid_trace(&h, 0.2 / (TUFT_POINTS - 1), NULL, NULL, original[i], NULL, NULL), HK_OK);
        if (i % 10) continue;
        hk_CurveFitDef opt = hk_default_helicoid_fit_def();
        truth[i / 10] = h;
        opt.fixed_pieces = 4;
        assert_int_equal(hk_helicoid_fit(f, original[i], TUFT_POINTS, &opt, &common[i / 10], NULL, NULL), HK_OK);
        opt.fixed_pieces = 0;
        assert_int_equal(hk_helicoid_fit(f, original[i], TUFT_POINTS, &opt, &own[i / 10], NULL, NULL), HK_OK);
    }
    hk_helicoid_fitter_destroy(f);
    const double floor = tuft_error(truth, TUFT / 10, original), with_common = tuft_error(common, TUFT / 10, original),
                 with_own = tuft_error(own, TUFT / 10, original);
    print_message("  tuft of %d from %d: mean error %.3g m from the true parameters, %.3g m from fits on a common "
                  "4-piece layout, %.3g m from fits split their own way\n",
                  TUFT, TUFT / 10, floor, with_common, with_own);
    assert_true(with_common < 1.1 * floor + 1e-4);
    assert_true(with_common < with_own);
}

/* A reconstruction knows every strand's own length (the capture gives it) and rebuilds
 * each strand at that length, not at its guides' blended one. A tuft whose neighbouring
 * strands have lengths from 8 to 24 cm at random (as layered cuts do): every rebuilt strand
 * must be its own length to within a tracing step, which a blend of the neighbours'
 * lengths misses by centimetres. */
static void test_reconstruct_own_lengths(void **state)
{
    (void)state;
    enum { STRANDS = 60, POINTS = 25 };
    hk_PHelicoid guides[4];
    for (int i = 0; i < 4; i++) {
        memset(&guides[i], 0, sizeof guides[i]);
        guides[i].root = hk_v3(0.02 * (i % 2) - 0.01, 0.0, 0.02 * (i / 2) - 0.01);
        guides[i].frame = hk_m3_from_cols(hk_v3(0, -1, 0), hk_v3(1, 0, 0), hk_v3(0, 0, 1));
        guides[i].piece_count = 1;
        guides[i].k[0] = (hk_Helicoid){rnd(5, 15), rnd(-2, 2), rnd(-4, 4), 0.0};
        guides[i].length[0] = 0.2;
    }
    uint32_t counts[STRANDS];
    for (int i = 0; i < STRANDS; i++) counts[i] = POINTS;
    hk_HairFile hair = {0}, out = {0};
    assert_int_equal(hk_hair_alloc(&hair, STRANDS, counts, NULL), HK_OK);
    double own[STRANDS];
    for (int i = 0; i < STRANDS; i++) {
        hk_PHelicoid h;
        const hk_Vec3 root = hk_v3(rnd(-0.01, 0.01), 0.0, rnd(-0.01, 0.01));
        assert_int_equal(hk_phelicoid_interpolate(guides, 4, root, NULL, 3.0, &h, NULL), HK_OK);
        h.length[0] = rnd(0.08, 0.24);
        hk_Vec3 p[POINTS];
        assert_int_equal(hk_phelicoid_trace(&h, h.length[0] / (POINTS - 1), NULL, NULL, p, NULL, NULL), HK_OK);
        own[i] = 0.0;
        for (int k = 0; k < POINTS; k++) {
            float *q = hair.points + 3 * (size_t)(hair.first_point[i] + (uint32_t)k);
            q[0] = (float)p[k].x, q[1] = (float)p[k].y, q[2] = (float)p[k].z;
            if (k) own[i] += hk_v3_dist(p[k], p[k - 1]);
        }
    }
    const double step = 0.002;
    hk_HelicoidReconstruction report;
    hk_Error err;
    if (hk_helicoid_reconstruct(&hair, 10, NULL, 3.0, step, 1, 1, NULL, NULL, &out, &report, &err) != HK_OK)
        fail_msg("%s", err.message);
    assert_int_equal(out.strand_count, STRANDS);
    double worst = 0.0;
    for (int i = 0; i < STRANDS; i++) {
        double length = 0.0;
        for (uint32_t k = out.first_point[i] + 1; k < out.first_point[i + 1]; k++) {
            const float *a = out.points + 3 * (size_t)(k - 1), *b = a + 3;
            length += hk_v3_dist(hk_v3(a[0], a[1], a[2]), hk_v3(b[0], b[1], b[2]));
        }
        worst = fmax(worst, fabs(length - own[i]));
    }
    print_message("  %d strands of 8-24 cm rebuilt from %ld: lengths within %.2g mm of their own, mean error %.2g mm\n",
                  STRANDS, report.fitted, 1e3 * worst, 1e3 * report.mean_error);
    assert_true(worst <= step);
    hk_hair_free(&hair);
    hk_hair_free(&out);
}

/* A parting (§5.4 on a groom that has one): strands rooted on a plane, those left of x = 0
 * leaving towards -x and those right of it towards +x, each a circular arc of 10 cm radius
 * curling down, 6 to 14 cm long, in random order so that the fitted one in ten falls
 * anywhere. The known answer: every strand is a piece of its side's arc, so rebuilt from
 * its side's fits alone it comes back to the fits' accuracy (7 microns on average, 21 at
 * worst); blending by root distance alone mixes the two sides' shapes near the parting
 * (HK_RECONSTRUCT_DIRECTION_WIDTH at 1e9 instead: 2.7 mm on average, 38 mm at worst). */
static hk_Vec3 parting_arc(double x, double z, double s)
{
    const double radius = 0.1, a = s / radius, side = x < 0.0 ? -1.0 : 1.0;
    return hk_v3(x + side * radius * sin(a), -radius * (1.0 - cos(a)), z);
}

static void test_reconstruct_parting(void **state)
{
    (void)state;
    enum { STRANDS = 300, POINTS = 31 };
    uint32_t counts[STRANDS];
    for (int i = 0; i < STRANDS; i++) counts[i] = POINTS;
    hk_HairFile hair = {0}, out = {0};
    assert_int_equal(hk_hair_alloc(&hair, STRANDS, counts, NULL), HK_OK);
    double root[STRANDS][2];
    for (int i = 0; i < STRANDS; i++) {
        root[i][0] = rnd(-0.03, 0.03), root[i][1] = rnd(-0.03, 0.03);
        const double length = rnd(0.06, 0.14);
        for (int k = 0; k < POINTS; k++) {
            const hk_Vec3 p = parting_arc(root[i][0], root[i][1], length * k / (POINTS - 1));
            float *q = hair.points + 3 * (size_t)(hair.first_point[i] + (uint32_t)k);
            q[0] = (float)p.x, q[1] = (float)p.y, q[2] = (float)p.z;
        }
    }
    hk_HelicoidReconstruction report;
    hk_Error err;
    const double step = 0.002;
    if (hk_helicoid_reconstruct(&hair, 10, NULL, 3.0, step, 1, 0, NULL, NULL, &out, &report, &err) != HK_OK)
        fail_msg("%s", err.message);
    /* Rebuilt point j against the arc at the same arc length, j times the spacing (the
     * Fréchet figures of the report also measure the two samplings' spacings, 2 to 5 mm). */
    double worst = 0.0, sum = 0.0;
    long points = 0;
    for (int i = 0; i < STRANDS; i++) {
        const uint32_t a = out.first_point[i], b = out.first_point[i + 1];
        const double spacing = hk_v3_dist(hk_v3(out.points[3 * a], out.points[3 * a + 1], out.points[3 * a + 2]),
                                          hk_v3(out.points[3 * a + 3], out.points[3 * a + 4], out.points[3 * a + 5]));
        assert_true(spacing <= step * (1.0 + 1e-6));
        for (uint32_t k = a; k < b; k++) {
            const hk_Vec3 p = hk_v3(out.points[3 * k], out.points[3 * k + 1], out.points[3 * k + 2]);
            const double d = hk_v3_dist(p, parting_arc(root[i][0], root[i][1], spacing * (k - a)));
            worst = fmax(worst, d), sum += d, points++;
        }
    }
    print_message("  parting: %d strands rebuilt from %ld: points off their arcs by %.3f mm on average, %.3f mm at "
                  "worst (Frechet coupling: mean %.2f mm)\n",
                  STRANDS, report.fitted, 1e3 * sum / points, 1e3 * worst, 1e3 * report.mean_error);
    assert_true(worst <= 1e-4);
    hk_hair_free(&hair);
    hk_hair_free(&out);
}

/* A p-helicoid of three pieces at the origin. */
static hk_PHelicoid three_pieces(hk_Mat3 frame, const hk_Helicoid *k, const double *length)
{
    hk_PHelicoid h;
    memset(&h, 0, sizeof h);
    h.frame = frame;
    h.piece_count = 3;
    for (int p = 0; p < 3; p++) h.k[p] = k[p], h.length[p] = length[p];
    return h;
}

/* A fit describes a curve, not one discretisation of it: a wavy strand (not a p-helicoid:
 * eq. 4's waviness on top) fitted piece by piece, then traced 4 times finer than its
 * samples, is as close to the target as the fit said. Before the fitter refused pieces
 * that turn more than a radian per sample or pass near their field's singular axis, fits
 * of such strands re-traced centimetres away. */
static void test_fit_is_a_curve(void **state)
{
    (void)state;
    const hk_Helicoid k[3] = {{150, 0, 0, 0}, {20, 3, -4, 0.1}, {12, -2, 5, -0.2}};
    const hk_PHelicoid h = three_pieces(hk_helicoid_frame(0.4, 0.2), k, (const double[3]){0.008, 0.08, 0.112});
    const hk_Waviness wave = {0.004, 120.0, 0.0};
    enum { N = 101 };
    hk_Vec3 pts[N];
    assert_int_equal(hk_phelicoid_point_count(&h, 0.002), N);
    assert_int_equal(hk_phelicoid_trace(&h, 0.002, &wave, NULL, pts, NULL, NULL), HK_OK);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(N, NULL);
    assert_non_null(f);
    hk_PHelicoid fit;
    hk_CurveFit report;
    assert_int_equal(hk_helicoid_fit(f, pts, N, NULL, &fit, &report, NULL), HK_OK);
    hk_helicoid_fitter_destroy(f);
    const double step = report.sample_spacing / 4.0;
    const int m = hk_phelicoid_point_count(&fit, step);
    assert_true(m > 4 * (N - 1) - 2 * fit.piece_count && m <= 4 * (N - 1) + 1);
    hk_Vec3 *fine = malloc((size_t)m * sizeof *fine);
    assert_non_null(fine);
    assert_int_equal(hk_phelicoid_trace(&fit, step, NULL, NULL, fine, NULL, NULL), HK_OK);
    hk_FrechetMeasures fm;
    assert_int_equal(hk_frechet_measures(pts, N, fine, m, &fm, NULL), HK_OK);
    print_message("  wavy strand: %d pieces, fit error %.3g m, re-traced 4x finer %.3g m (mean leash)\n",
                  fit.piece_count, report.error, fm.normalized);
    /* The finer trace pairs every target point with a nearer one, so it can only do
     * better, give or take how the traces' last steps fall. */
    assert_true(fm.normalized < 1.2 * report.error + 1e-5);
    free(fine);
}

/* A planar strand that lifts off its root (77 degrees in 8 mm, as the head example's) and
 * falls, fitted on layouts that do not match its pieces. With alpha weighed as a
 * curvature of a radian per sample, the fits make the bends with k_T (before, they drifted
 * to k_T near 0 and alpha in the tens to hundreds, equivalent at the root, and ended 2 to
 * 11 mm off on these layouts). The bounds are this fitter's results with some margin,
 * a regression check; the adaptive fit must meet the tolerance. */
static void test_lift_off_layouts(void **state)
{
    (void)state;
    const hk_Helicoid k[3] = {{168.75, 0, 0, 0}, {20, 0, 0, 0}, {5, 0, 0, 0}};
    const hk_PHelicoid h = three_pieces(hk_helicoid_frame(0.3, 0.2), k, (const double[3]){0.008, 0.05, 0.05});
    enum { N = 55 };
    hk_Vec3 pts[N];
    assert_int_equal(hk_phelicoid_point_count(&h, 0.002), N);
    assert_int_equal(hk_phelicoid_trace(&h, 0.002, NULL, NULL, pts, NULL, NULL), HK_OK);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(N, NULL);
    assert_non_null(f);
    const int layouts[4] = {2, 3, 4, 0};
    const double bound[4] = {1.5e-3, 5e-4, 3e-4, 2e-4};
    for (int l = 0; l < 4; l++) {
        hk_CurveFitDef opt = hk_default_helicoid_fit_def();
        opt.fixed_pieces = layouts[l];
        hk_PHelicoid fit;
        hk_CurveFit report;
        assert_int_equal(hk_helicoid_fit(f, pts, N, &opt, &fit, &report, NULL), HK_OK);
        print_message("  lift-off, %d pieces: error %.3g m\n", fit.piece_count, report.error);
        assert_true(report.error < bound[l]);
    }
    hk_helicoid_fitter_destroy(f);
}

static void test_bad_input(void **state)
{
    (void)state;
    hk_Error err;
    assert_null(hk_helicoid_fitter_create(1, &err));
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(64, &err);
    hk_Vec3 pts[3] = {{0, 0, 0}, {NAN, 0, 0}, {1, 0, 0}};
    hk_PHelicoid out;
    assert_int_not_equal(hk_helicoid_fit(f, pts, 3, NULL, &out, NULL, &err), HK_OK);
    assert_int_not_equal(hk_helicoid_fit(f, pts, 1, NULL, &out, NULL, &err), HK_OK);
    hk_helicoid_fitter_destroy(f);
}

/* The project's own curly example (examples/helicoid/curly.txt: eight pieces of 3 cm,
 * k = (80, 0, 0, 0.4)) traced at its 0.5 mm step and fitted with the defaults: the
 * reference is the file itself, eight pieces whose parameters the fit recovers. Issue 17
 * asks 0.1 mm with about the pieces it was made with; a cut settled only three samples
 * back from the longest acceptable prefix gave 16 pieces and 3.1 mm. */
static void test_curly_example(void **state)
{
    (void)state;
    hk_HelicoidSet set = {0};
    hk_Error err;
    assert_int_equal(hk_helicoid_file_load(HK_SOURCE_DIR "/examples/helicoid/curly.txt", &set, &err), HK_OK);
    const hk_PHelicoid *h = &set.strands[0];
    const int n = hk_phelicoid_point_count(h, set.step);
    hk_Vec3 *pts = malloc((size_t)n * sizeof *pts);
    assert_int_equal(hk_phelicoid_trace(h, set.step, NULL, NULL, pts, NULL, &err), HK_OK);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(n, &err);
    hk_PHelicoid fit;
    hk_CurveFit report;
    assert_int_equal(hk_helicoid_fit(f, pts, n, NULL, &fit, &report, &err), HK_OK);
    print_message("  curly.txt (%d points): %d pieces, error %.2g mm\n", n, fit.piece_count, 1e3 * report.error);
    assert_int_equal(fit.piece_count, h->piece_count);
    assert_true(report.error <= 1e-4);
    for (int p = 0; p < fit.piece_count; p++) {
        assert_true(fabs(fit.length[p] - h->length[p]) <= 1e-6);
        assert_true(fabs(fit.k[p].kt - h->k[p].kt) <= 0.01 * h->k[p].kt);
        assert_true(fabs(fit.k[p].alpha - h->k[p].alpha) <= 0.01);
    }
    hk_helicoid_fitter_destroy(f);
    free(pts);
    hk_helicoid_set_free(&set);
}

/* The project's wisp example (examples/helicoid/wisp.txt: a 2-piece strand of 27 cm and 256
 * more streamlines of its field from roots in a 6 mm disc, fanned out, all with eq. 4's
 * waves of 2 mm at 120 rad/m on top) traced as `helicoid trace` does and fitted with the
 * defaults, every 64th strand. The reference is the traced strand itself, not the fitter's
 * report: each fit is traced again 4 times finer and compared with it both ways (mean
 * distance of each one's points to the other polyline, the larger). Issue 17 asks 0.1 mm;
 * the waves are no p-helicoid and take about 9 pieces a turn, so the fits have 45 pieces,
 * not the file's 2 (docs/helicoid-fitting.md, "Waves"); with the former cap of 16 pieces
 * they came out 2.4 mm off. */
static void test_wisp_example(void **state)
{
    (void)state;
    hk_HelicoidSet set = {0};
    hk_HairFile hair = {0};
    hk_Error err;
    assert_int_equal(hk_helicoid_file_load(HK_SOURCE_DIR "/examples/helicoid/wisp.txt", &set, &err), HK_OK);
    assert_int_equal(hk_helicoid_set_trace(&set, set.step, 1, 1, &hair, &err), HK_OK);
    assert_int_equal(hair.strand_count, 257);
    hk_HelicoidFitter *f = hk_helicoid_fitter_create(4096, &err);
    double sum = 0.0, worst = 0.0;
    int n = 0, pieces = 0;
    for (uint32_t s = 0; s < hair.strand_count; s += 64) {
        const uint32_t a = hair.first_point[s], count = hair.first_point[s + 1] - a;
        hk_Vec3 *p = malloc((size_t)count * sizeof *p);
        for (uint32_t i = 0; i < count; i++)
            p[i] = hk_v3(hair.points[3 * (a + i)], hair.points[3 * (a + i) + 1], hair.points[3 * (a + i) + 2]);
        hk_PHelicoid fit;
        assert_int_equal(hk_helicoid_fit(f, p, (int)count, NULL, &fit, NULL, &err), HK_OK);
        const double step = hk_phelicoid_length(&fit) / (4.0 * (count - 1));
        const int m = hk_phelicoid_point_count(&fit, step);
        hk_Vec3 *traced = malloc((size_t)m * sizeof *traced);
        assert_int_equal(hk_phelicoid_trace(&fit, step, NULL, NULL, traced, NULL, &err), HK_OK);
        const double e = hk_test_polyline_distance(p, (int)count, traced, m);
        sum += e, worst = fmax(worst, e), pieces += fit.piece_count, n++;
        free(traced);
        free(p);
    }
    print_message("  wisp.txt: %d strands, mean %.3f mm, worst %.3f mm, %.1f pieces\n", n, 1e3 * sum / n, 1e3 * worst,
                  (double)pieces / n);
    assert_true(sum / n <= 1e-4);
    hk_helicoid_fitter_destroy(f);
    hk_hair_free(&hair);
    hk_helicoid_set_free(&set);
}

/* Real grooms (../shared/hair-data, in metres): coarse strands that the fitter can cut only
 * in 2 pieces at their own points are fitted again resampled, and the better kept.
 * Issue 17 asks a mean error of at most 0.25 mm and a worst of at most 2 mm; the fit with
 * the retry is never worse than the first one alone (a fitter with room for the strand's
 * own points only cannot retry: the comparison), at no more than max_calls model calls a
 * fit on average. Every 300th Sintel strand, every 10th of Bangs (mm, scaled) and Curly
 * (mm, scaled). */
static void check_groom(const char *name, double scale, uint32_t every, double max_calls)
{
    hk_HairFile h = {0};
    hk_Error err;
    if (hk_hair_read(hk_test_shared_path(name), HK_HAIR_FORMAT_AUTO, &h, &err) != HK_OK)
        fail_msg("%s: %s", name, err.message);
    assert_int_equal(hk_hair_scale(&h, scale, &err), HK_OK);
    hk_HelicoidFitter *with = hk_helicoid_fitter_create(4096, &err);
    double sum = 0.0, worst = 0.0, first_sum = 0.0, calls = 0.0;
    int n = 0;
    for (uint32_t s = 0; s < h.strand_count; s += every) {
        const uint32_t a = h.first_point[s], b = h.first_point[s + 1];
        hk_Vec3 *p = malloc((b - a) * sizeof *p);
        for (uint32_t i = a; i < b; i++) p[i - a] = hk_v3(h.points[3 * i], h.points[3 * i + 1], h.points[3 * i + 2]);
        hk_HelicoidFitter *plain = hk_helicoid_fitter_create((int)(b - a), &err);
        hk_PHelicoid ph;
        hk_CurveFit fit, first;
        assert_int_equal(hk_helicoid_fit(with, p, (int)(b - a), NULL, &ph, &fit, &err), HK_OK);
        assert_int_equal(hk_helicoid_fit(plain, p, (int)(b - a), NULL, &ph, &first, &err), HK_OK);
        assert_true(fit.error <= first.error);
        sum += fit.error, first_sum += first.error, worst = fmax(worst, fit.error), n++;
        calls += (double)fit.evaluations;
        hk_helicoid_fitter_destroy(plain);
        free(p);
    }
    print_message("%s: %d strands, mean %.3f mm (%.3f mm without the retry), worst %.3f mm, %.0f model calls a fit\n",
                  name, n, 1e3 * sum / n, 1e3 * first_sum / n, 1e3 * worst, calls / n);
    assert_true(sum / n <= 2.5e-4);
    assert_true(worst <= 2e-3);
    /* The cost, counted (deterministic, unlike a time): model calls per fit, bounded at a
     * quarter above what the cut search of 6 December 2026 made (1477, 876 and 1733; the
     * search before it made 6750, 3266 and 7902, docs/helicoid-fitting.md §7). */
    assert_true(calls / n <= max_calls);
    hk_helicoid_fitter_destroy(with);
    hk_hair_free(&h);
}

static void test_real_grooms(void **state)
{
    (void)state;
    if (!hk_test_have_shared_data()) skip();
    check_groom("SintelHairOriginal-sintel_hair.16points.tfx", 1.0, 300, 1.25 * 1477);
    check_groom("Bangs_100.hair", 0.001, 10, 1.25 * 876);
    check_groom("Curly_100.ply", 0.001, 10, 1.25 * 1733);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_single_pieces_recovered),
        cmocka_unit_test(test_single_pieces_nelder_mead),
        cmocka_unit_test(test_two_pieces),
        cmocka_unit_test(test_reconstruction),
        cmocka_unit_test(test_reconstruct_own_lengths),
        cmocka_unit_test(test_reconstruct_parting),
        cmocka_unit_test(test_fit_is_a_curve),
        cmocka_unit_test(test_lift_off_layouts),
        cmocka_unit_test(test_bad_input),
        cmocka_unit_test(test_curly_example),
        cmocka_unit_test(test_wisp_example),
        cmocka_unit_test(test_real_grooms),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
