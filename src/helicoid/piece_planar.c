/* The closed-form streamline of a helicoid piece with alpha = 0 (docs/helicoids.md, "closed
 * forms"). Then phi = 0, so z stays z0 and theta = arg w + beta with beta = k_B z0 constant.
 * With w = 1 + c (x + i y), c = k_N + i k_T and c' = c e^{i beta}, the tangent e^{i theta} is
 * e^{i beta} w / |w|, hence
 *     dw/ds = c' w / |w|:   |w| = r0 + Re(c') s,   log(w / w0) = c' g(s),
 *     g(s) = log(1 + Re(c') s / r0) / Re(c')   (s / r0 when Re(c') = 0),
 *     theta = theta0 + Im(c') g,   (x + i y) - (x0 + i y0) = r0 e^{i theta0} expm1(c' g) / c'.
 * Logarithmic spirals about the singular axis w = 0; circles of radius 1/|k_T| when
 * k_N = k_B = 0; straight lines when c = 0. When Re(c') < 0 the streamline reaches the axis
 * (a sink) at s = r0 / -Re(c') and ends there. */
#include "helicoid_internal.h"

void hk_helicoid_piece_planar(const hk_HelicoidPiece *pc, hk_Vec3 *p, hk_HelicoidAngles *a, const hk_HelicoidSink *out)
{
    const hk_Helicoid *k = pc->k;
    const double h = pc->length / pc->steps;
    const double x0 = p->x, y0 = p->y, z0 = p->z, th0 = a->theta, ct0 = a->ct, st0 = a->st;
    const double beta = k->kb * z0, cb = cos(beta), sb = sin(beta);
    const double ar = k->kn * cb - k->kt * sb, ai = k->kt * cb + k->kn * sb; /* c' */
    const double cc = k->kn * k->kn + k->kt * k->kt;                         /* |c'|^2 */
    const double r0 = hypot(1.0 + k->kn * x0 - k->kt * y0, k->kt * x0 + k->kn * y0);
    double x = x0, y = y0;
    hk_HelicoidAngles cur = *a;
    for (int j = 1; j <= pc->steps; j++) {
        const double s = j == pc->steps ? pc->length : j * h;
        const double u = ar * s / r0;
        if (!(r0 > 0.0) || u <= -1.0) {
            /* On the axis (w = 0, reached or started on): the field has no direction there.
             * theta stays at its last value so that frames and waviness stay finite. */
            x = -k->kn / cc;
            y = k->kt / cc;
        } else {
            const double g = u == 0.0 ? s / r0 : log1p(u) / ar;
            const double vr = ar * g, vi = ai * g; /* v = c' g = log(w / w0) */
            const double sh = sin(0.5 * vi), ch = cos(0.5 * vi);
            const double cv = 1.0 - 2.0 * sh * sh, sv = 2.0 * sh * ch; /* cos, sin vi */
            double qr, qi; /* expm1(v) / c', accurate for small v and small c' */
            if (vr * vr + vi * vi < 1e-16) {
                const double v2r = vr * vr - vi * vi, v2i = 2.0 * vr * vi;
                qr = g * (1.0 + 0.5 * vr + v2r / 6.0);
                qi = g * (0.5 * vi + v2i / 6.0);
            } else {
                const double em = expm1(vr);
                const double er = em * cv - 2.0 * sh * sh, ei = (em + 1.0) * sv;
                qr = (er * ar + ei * ai) / cc;
                qi = (ei * ar - er * ai) / cc;
            }
            x = x0 + r0 * (ct0 * qr - st0 * qi);
            y = y0 + r0 * (ct0 * qi + st0 * qr);
            /* theta = theta0 + vi; its sine and cosine by rotating theta0's (no new sine). */
            cur.theta = th0 + vi;
            cur.ct = ct0 * cv - st0 * sv;
            cur.st = st0 * cv + ct0 * sv;
        }
        hk_helicoid_emit(pc, out, j, x, y, z0, &cur, out->s_start + s);
    }
    *p = hk_v3(x, y, z0);
    *a = cur;
}
