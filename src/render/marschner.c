/* Marschner, Jensen, Cammarano, Worley and Hanrahan, "Light Scattering from Human
 * Hair Fibers" (SIGGRAPH 2003), the model Bertails et al. 2006 render with: a hair fibre is a
 * dielectric cylinder, light leaves it by three paths, R (reflected at the surface),
 * TT (through the fibre) and TRT (reflected once inside), each a product of a
 * longitudinal lobe M_p(theta_h) and an azimuthal term N_p(phi):
 *     S = sum_p M_p(theta_h) N_p(phi) / cos^2(theta_d)        (Marschner §4, eq. 5)
 * M_p is a Gaussian of width beta_p about the shift alpha_p (§4.3), normalised over
 * the outgoing direction (see longitudinal()). N_R is
 * exact for a smooth cylinder's surface reflection: 1/4 cos(phi/2) F(eta, cos h_R),
 * with the half angle between l and e (as in Karis 2016, "Physically Based Hair
 * Shading in Unreal", eq. for N_R). N_TT and N_TRT use Karis's fitted approximations
 * of Marschner's integrals over the fibre's offsets h: one representative offset
 * per path, the Fresnel and absorption along it, and fitted azimuthal shapes
 * D_TT = exp(-3.65 cos phi - 3.98), D_TRT = exp(17 cos phi - 16.78). Absorption uses
 * the path 2 cos(gamma_t) / cos(theta_t) in fibre radii (Marschner §4.2.1, with
 * gamma_t the refracted offset angle and theta_t the refracted longitudinal angle). */
#include "shading.h"


/* Fresnel reflectance of unpolarised light entering a dielectric of index eta at an
 * angle of incidence whose cosine is cos_i (exact, both polarisations averaged). */
static double fresnel(double eta, double cos_i)
{
    cos_i = fmin(1.0, fmax(0.0, cos_i));
    const double sin_t2 = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin_t2 >= 1.0) return 1.0;
    const double cos_t = sqrt(1.0 - sin_t2);
    const double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    const double rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

/* Longitudinal lobe: Marschner's Gaussian of width beta in theta_h, halved. At a
 * fixed incidence theta_h moves at half the rate of the outgoing theta_o, so the
 * Gaussian integrates to 2 over theta_o; halving it makes each lobe carry the energy
 * of its azimuthal term (the non-conservation noted by d'Eon et al. 2011). */
static double longitudinal(double beta, double x)
{
    return 0.5 * exp(-x * x / (2.0 * beta * beta)) / (beta * sqrt(2.0 * HK_PI));
}

/* Transmittance along a path through the fibre at offset h (|h| < 1). */
static hk_Vec3 absorption(hk_Vec3 sigma_a, double h, double eta_prime, double cos_theta_t, int passes)
{
    const double sin_gamma_t = fmin(1.0, fabs(h) / eta_prime);
    const double path = passes * 2.0 * sqrt(1.0 - sin_gamma_t * sin_gamma_t) / fmax(cos_theta_t, 1e-6);
    return hk_v3(exp(-sigma_a.x * path), exp(-sigma_a.y * path), exp(-sigma_a.z * path));
}

hk_MarschnerParams hk_marschner_params_from_color(hk_Vec3 c)
{
    /* Chiang, Bitterli, Tappan, Burley, "A Practical and Controllable Hair and Fur
     * Model for Production Path Tracing" (2016), eq. 9: the absorption that gives a
     * multiply scattered colour c at azimuthal roughness beta_n (0.3 here). */
    const double bn = 0.3;
    const double d =
        5.969 - 0.215 * bn + 2.532 * bn * bn - 10.73 * pow(bn, 3) + 5.574 * pow(bn, 4) + 0.245 * pow(bn, 5);
    double v[3] = {c.x, c.y, c.z};
    for (int k = 0; k < 3; k++) {
        const double x = fmin(0.999, fmax(1e-3, v[k]));
        v[k] = pow(log(x) / d, 2.0);
    }
    hk_MarschnerParams p;
    p.eta = 1.55;                   /* Marschner Table 1 */
    p.alpha_r = -7.0 * HK_PI / 180; /* the cuticle's tilt: -5 to -10 degrees */
    p.beta_r = 7.0 * HK_PI / 180;   /* 5 to 10 degrees */
    p.sigma_a = hk_v3(v[0], v[1], v[2]);
    return p;
}

void hk_marschner_lobes(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_MarschnerParams *p, hk_Vec3 lobe[3])
{
    const double sin_i = fmax(-1.0, fmin(1.0, hk_v3_dot(t, l))), sin_o = fmax(-1.0, fmin(1.0, hk_v3_dot(t, e)));
    const double theta_i = asin(sin_i), theta_o = asin(sin_o);
    const double theta_h = 0.5 * (theta_i + theta_o), theta_d = 0.5 * (theta_o - theta_i);
    const double cos_d = cos(theta_d), cos_i = cos(theta_i);
    /* Azimuth between the projections of l and e on the normal plane (phi = 0: the
     * eye on the light's side; pi: behind the fibre). A direction along the fibre has
     * no azimuth; it is taken as phi = pi / 2, where the terms are smooth. */
    const hk_Vec3 lp = hk_v3_madd(l, t, -sin_i), ep = hk_v3_madd(e, t, -sin_o);
    const double nl = hk_v3_norm(lp), ne = hk_v3_norm(ep);
    const double cos_phi = nl > 1e-9 && ne > 1e-9 ? fmax(-1.0, fmin(1.0, hk_v3_dot(lp, ep) / (nl * ne))) : 0.0;
    const double cos_half_phi = sqrt(0.5 * (1.0 + cos_phi));
    /* Bravais's effective index for the projected problem (Marschner §4.2.1). */
    const double eta = p->eta;
    const double eta_prime = sqrt(fmax(eta * eta - sin(theta_d) * sin(theta_d), 1e-12)) / fmax(cos_d, 1e-6);
    const double sin_t = sin(theta_d) / eta, cos_theta_t = sqrt(fmax(0.0, 1.0 - sin_t * sin_t));
    const double inv_cos2 = 1.0 / fmax(cos_d * cos_d, 1e-6);

    /* R: surface reflection. */
    const double m_r = longitudinal(p->beta_r, theta_h - p->alpha_r);
    const double n_r = 0.25 * cos_half_phi * fresnel(eta, sqrt(fmax(0.0, 0.5 * (1.0 + hk_v3_dot(l, e)))));
    const double r = m_r * n_r;

    /* TT: through the fibre; Karis's offset h_TT for the azimuth phi. */
    const double a = 1.0 / eta_prime;
    const double h_tt = fmax(-1.0, fmin(1.0, (1.0 + a * (0.6 - 0.8 * cos_phi)) * cos_half_phi));
    const double f_tt = fresnel(eta, cos_d * sqrt(fmax(0.0, 1.0 - h_tt * h_tt)));
    const hk_Vec3 t_tt = absorption(p->sigma_a, h_tt, eta_prime, cos_theta_t, 1);
    const double d_tt = exp(-3.65 * cos_phi - 3.98);
    const double m_tt = longitudinal(0.5 * p->beta_r, theta_h + 0.5 * p->alpha_r);
    const double k_tt = m_tt * (1.0 - f_tt) * (1.0 - f_tt) * d_tt;

    /* TRT: one internal reflection, at the offset h = sqrt(3) / 2 of Karis. */
    const double h_trt = sqrt(3.0) / 2.0;
    const double f_trt = fresnel(eta, cos_d * 0.5);
    const hk_Vec3 t_trt = absorption(p->sigma_a, h_trt, eta_prime, cos_theta_t, 2);
    const double d_trt = exp(17.0 * cos_phi - 16.78);
    const double m_trt = longitudinal(2.0 * p->beta_r, theta_h + 1.5 * p->alpha_r);
    const double k_trt = m_trt * (1.0 - f_trt) * (1.0 - f_trt) * f_trt * d_trt;

    const double scale = inv_cos2 * cos_i; /* S times the projected irradiance */
    lobe[0] = hk_v3(scale * r, scale * r, scale * r);
    lobe[1] = hk_v3_scale(t_tt, scale * k_tt);
    lobe[2] = hk_v3_scale(t_trt, scale * k_trt);
}

hk_Vec3 hk_shade_marschner(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_MarschnerParams *p)
{
    hk_Vec3 lobe[3];
    hk_marschner_lobes(t, l, e, p, lobe);
    return hk_v3_add(lobe[0], hk_v3_add(lobe[1], lobe[2]));
}
