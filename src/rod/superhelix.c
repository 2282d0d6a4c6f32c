/* Super-Helix strands: construction from a hairstyle, natural curliness and the
 * reconstruction of centreline and material frame (Bertails et al. 2006 §3.2 and Appendix A). */
#include "hairkit/rod.h"

#include <string.h>

#include "helix_local.h"
#include "rod/rod_internal.h"

hk_RodMaterial hk_rod_material(double radius1, double radius2, double young, double poisson, double density,
                               hk_Vec3 gravity)
{
    const double a = radius1, b = radius2, pi = HK_PI;
    hk_RodMaterial m;
    const double shear = young / (2.0 * (1.0 + poisson));
    /* kappa1 turns the section about n1: its bending inertia is int y2^2 dA with y2
     * along n2 (semi-axis b), i.e. pi a b^3 / 4; likewise for kappa2. */
    m.stiffness[0] = shear * pi * a * b * (a * a + b * b) / 4.0;
    m.stiffness[1] = young * pi * a * b * b * b / 4.0;
    m.stiffness[2] = young * pi * b * a * a * a / 4.0;
    m.mass_per_length = density * pi * a * b;
    /* Rotary inertia of the section (Bertails et al. 2006 eq. 5b counts only the centreline's
     * kinetic energy; without this term the twist has no inertia and M is singular on a
     * straight rod, DESIGN.md). */
    m.rotary_inertia[1] = density * pi * a * b * b * b / 4.0;
    m.rotary_inertia[2] = density * pi * b * a * a * a / 4.0;
    m.rotary_inertia[0] = m.rotary_inertia[1] + m.rotary_inertia[2];
    m.gravity = gravity;
    return m;
}

void hk_helix_natural_curvature(double helix_radius, double helix_step, double *tau, double *kappa1)
{
    /* Exact helix r(t) = (r_h cos t, r_h sin t, c t), c = Delta_h / 2 pi: curvature
     * r_h / (r_h^2 + c^2), torsion c / (r_h^2 + c^2). The paper's 1/r_h and
     * Delta_h / (2 pi r_h^2) are the small-pitch limit (seeds README). */
    if (helix_radius <= 0.0) {
        *tau = 0.0;
        *kappa1 = 0.0;
        return;
    }
    const double c = helix_step / (2.0 * HK_PI);
    const double den = helix_radius * helix_radius + c * c;
    *kappa1 = helix_radius / den;
    *tau = c / den;
}

hk_Mat3 hk_root_frame(hk_Vec3 dir)
{
    const hk_Vec3 n0 = hk_v3_normalize(dir);
    hk_Vec3 n1 = hk_v3_cross(n0, hk_v3(0.0, 1.0, 0.0));
    double len = hk_v3_norm(n1);
    /* Thesis §4.1.4.1 falls back to (0, 0, 1) for a vertical follicle; we also use it
     * for nearly vertical ones, where the cross product has lost its precision. */
    n1 = len > 1e-9 ? hk_v3_scale(n1, 1.0 / len) : hk_v3(0.0, 0.0, 1.0);
    const hk_Vec3 n2 = hk_v3_cross(n0, n1);
    return hk_m3_from_cols(n0, n1, n2);
}

hk_Status hk_superhelix_create(int n, const double *lengths, hk_SuperHelix **out, hk_Error *err)
{
    *out = NULL;
    if (n < 1 || n > HK_MAX_ELEMENTS)
        return hk_error_set(err, HK_ERR_INVALID, "a strand needs 1 to %d elements, got %d", HK_MAX_ELEMENTS, n);
    for (int i = 0; i < n; i++)
        if (!(lengths[i] > 0.0) || !isfinite(lengths[i]))
            return hk_error_set(err, HK_ERR_INVALID, "element %d has length %g, must be > 0", i + 1, lengths[i]);
    hk_SuperHelix *sh = hk_calloc_array(1, sizeof *sh, err);
    if (!sh) return err ? err->code : HK_ERR_NOMEM;
    /* One block for the per-element arrays: length, s_start (n + 1), q, q_rest. */
    double *block = hk_calloc_array((size_t)n * 8 + 1, sizeof(double), err);
    if (!block) {
        hk_free(sh);
        return err ? err->code : HK_ERR_NOMEM;
    }
    sh->n = n;
    sh->length = block;
    sh->s_start = block + n;
    sh->q = block + 2 * n + 1;
    sh->q_rest = block + 5 * n + 1;
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        sh->length[i] = lengths[i];
        sh->s_start[i] = s;
        s += lengths[i];
    }
    sh->s_start[n] = s;
    sh->total_length = s;
    sh->root = hk_v3_zero();
    sh->root_frame = hk_m3_identity();
    sh->material = hk_rod_material(5e-5, 5e-5, 1e9, 0.48, 1300.0, hk_v3(0.0, -9.81, 0.0));
    *out = sh;
    return HK_OK;
}

hk_StrandDef hk_default_strand_def(void)
{
    hk_StrandDef d;
    memset(&d, 0, sizeof d);
    d.visuality_step = 0.0025;
    d.collision_step = 0.005;
    d.max_iter = 20;
    d.epsilon = 1e-4;
    d.poisson = 0.48;
    d.density = 1300.0; /* real hair; the thesis's sample says 13000 (seeds README) */
    d.gravity = 9.81;
    d.gravity_dir = hk_v3(0.0, -1.0, 0.0);
    return d;
}

double hk_strand_def_length(const hk_StrandDef *def)
{
    double s = 0.0;
    for (int i = 0; i < def->element_count; i++) s += def->element_lengths[i];
    return s;
}

hk_Status hk_superhelix_from_def(const hk_StrandDef *def, hk_Vec3 root, hk_Vec3 dir, hk_SuperHelix **out, hk_Error *err)
{
    if (!(hk_v3_norm(dir) > 0.0) || !hk_v3_isfinite(dir))
        return hk_error_set(err, HK_ERR_INVALID, "root direction must be a non-zero vector");
    hk_Status st = hk_superhelix_create(def->element_count, def->element_lengths, out, err);
    if (st != HK_OK) return st;
    hk_SuperHelix *sh = *out;
    sh->root = root;
    sh->root_frame = hk_root_frame(dir);
    sh->material = hk_rod_material(def->radius1, def->radius2, def->young, def->poisson, def->density,
                                   hk_v3_scale(def->gravity_dir, def->gravity));
    double tau, kappa1;
    hk_helix_natural_curvature(def->helix_radius, def->helix_step, &tau, &kappa1);
    hk_superhelix_set_uniform_rest(sh, tau, kappa1, 0.0);
    return HK_OK;
}

void hk_superhelix_destroy(hk_SuperHelix *sh)
{
    if (!sh) return;
    hk_free(sh->length);
    hk_free(sh);
}

void hk_superhelix_set_uniform_rest(hk_SuperHelix *sh, double tau, double kappa1, double kappa2)
{
    for (int i = 0; i < sh->n; i++) {
        sh->q_rest[3 * i + 0] = tau;
        sh->q_rest[3 * i + 1] = kappa1;
        sh->q_rest[3 * i + 2] = kappa2;
    }
    memcpy(sh->q, sh->q_rest, (size_t)sh->n * 3 * sizeof(double));
}

static hk_Vec3 element_k(const double *q, int i) { return hk_v3(q[3 * i], q[3 * i + 1], q[3 * i + 2]); }

/* Moves the start pose (r, p) of element i to its end (the start of element i + 1). */
static void advance_element(const hk_SuperHelix *sh, const double *q, int i, hk_Mat3 *r, hk_Vec3 *p)
{
    hk_ElementLocal el;
    hk_element_local(element_k(q, i), sh->length[i], 0, 0, &el);
    *p = hk_v3_add(*p, hk_m3_mul_v3(r, hk_m3_col(&el.lam, 0)));
    *r = hk_m3_mul(r, &el.rot);
}

void hk_superhelix_nodes(const hk_SuperHelix *sh, const double *q, hk_Vec3 *pos, hk_Mat3 *frame)
{
    if (!q) q = sh->q;
    hk_Mat3 r = sh->root_frame;
    hk_Vec3 p = sh->root;
    for (int i = 0; i <= sh->n; i++) {
        if (pos) pos[i] = p;
        if (frame) frame[i] = r;
        if (i == sh->n) break;
        advance_element(sh, q, i, &r, &p);
    }
}

/* Pose at offset u into element i whose start pose is (r, p). */
static void element_pose(const double *q, int i, double u, const hk_Mat3 *r, hk_Vec3 p, hk_Vec3 *pos, hk_Mat3 *frame)
{
    if (!frame) { /* the offset alone (the same bits as the element's), without its rotation */
        if (pos) *pos = hk_v3_add(p, hk_m3_mul_v3(r, hk_element_offset(element_k(q, i), u, NULL, NULL)));
        return;
    }
    hk_ElementLocal el;
    hk_element_local(element_k(q, i), u, 0, 0, &el);
    if (pos) *pos = hk_v3_add(p, hk_m3_mul_v3(r, hk_m3_col(&el.lam, 0)));
    *frame = hk_m3_mul(r, &el.rot);
}

void hk_superhelix_eval(const hk_SuperHelix *sh, const double *q, double s, hk_Vec3 *pos, hk_Mat3 *frame)
{
    if (!q) q = sh->q;
    if (!(s > 0.0)) s = 0.0;
    if (s > sh->total_length) s = sh->total_length;
    hk_Mat3 r = sh->root_frame;
    hk_Vec3 p = sh->root;
    int i = 0;
    while (i < sh->n - 1 && s >= sh->s_start[i + 1]) advance_element(sh, q, i++, &r, &p);
    element_pose(q, i, s - sh->s_start[i], &r, p, pos, frame);
}

/* s clamped to [0, L] */
static double clamp_s(const hk_SuperHelix *sh, double s)
{
    return s > 0.0 ? (s < sh->total_length ? s : sh->total_length) : 0.0;
}

void hk_superhelix_points_nodes(const hk_SuperHelix *sh, const double *q, const double *s, int count, hk_Vec3 *pos,
                                hk_Vec3 *nodes)
{
    if (!q) q = sh->q;
    hk_Mat3 r = sh->root_frame;
    hk_Vec3 p = sh->root;
    int elem = 0;
    if (nodes) nodes[0] = p;
    for (int j = 0; j < count; j++) {
        const double sj = clamp_s(sh, s[j]);
        while (elem < sh->n - 1 && sj >= sh->s_start[elem + 1]) {
            advance_element(sh, q, elem++, &r, &p);
            if (nodes) nodes[elem] = p;
        }
        /* with the next point when it lies in the same element: two at a time */
        const double next = j + 1 < count ? clamp_s(sh, s[j + 1]) : 0.0;
        if (j + 1 < count && !(elem < sh->n - 1 && next >= sh->s_start[elem + 1])) {
            const double u[2] = {sj - sh->s_start[elem], next - sh->s_start[elem]};
            hk_Vec3x2 offset;
            hk_element_slide2(element_k(q, elem), u, hk_v3_zero(), &offset, NULL);
            const hk_Vec3x2 x = add_x2(lanes3(p), mul_v3_x2(&r, offset));
            pos[j] = lane_v3(x, 0);
            pos[++j] = lane_v3(x, 1);
            continue;
        }
        element_pose(q, elem, sj - sh->s_start[elem], &r, p, &pos[j], NULL);
    }
    if (!nodes) return;
    /* the nodes beyond the last point: the same walk as hk_superhelix_nodes */
    while (elem < sh->n) {
        advance_element(sh, q, elem++, &r, &p);
        nodes[elem] = p;
    }
}

void hk_superhelix_points(const hk_SuperHelix *sh, const double *q, const double *s, int count, hk_Vec3 *pos)
{
    hk_superhelix_points_nodes(sh, q, s, count, pos, NULL);
}

int hk_superhelix_sample_count(const hk_SuperHelix *sh, double step)
{
    const double len = sh->total_length;
    if (!(step > 0.0)) return 2;
    double m = floor(len / step);
    if (m > (double)HK_MAX_SAMPLES_PER_STRAND) m = (double)HK_MAX_SAMPLES_PER_STRAND;
    int count = (int)m + 1; /* s = 0 .. m step */
    /* The tip is always last: a last regular sample closer than 1e-9 L to it is the tip. */
    if (len - m * step > 1e-9 * len) count++;
    return count;
}

void hk_superhelix_sample(const hk_SuperHelix *sh, const double *q, double step, double *s, hk_Vec3 *pos,
                          hk_Vec3 *tangent)
{
    if (!q) q = sh->q;
    const int count = hk_superhelix_sample_count(sh, step);
    hk_Mat3 r = sh->root_frame;
    hk_Vec3 p = sh->root;
    int elem = 0;
    for (int j = 0; j < count; j++) {
        double sj = j == count - 1 ? sh->total_length : j * step;
        /* Advance the element start pose incrementally: O(N + samples) overall. */
        while (elem < sh->n - 1 && sj >= sh->s_start[elem + 1]) advance_element(sh, q, elem++, &r, &p);
        hk_Vec3 pj;
        hk_Mat3 fj;
        element_pose(q, elem, sj - sh->s_start[elem], &r, p, &pj, &fj);
        if (s) s[j] = sj;
        if (pos) pos[j] = pj;
        if (tangent) tangent[j] = hk_m3_col(&fj, 0);
    }
}
