/* Hair and skin shading models of the renderer: Kajiya-Kay (Lansink 2010 §4.1.5, the
 * default) and Marschner et al. 2003 (Bertails et al. 2006 render with it). All directions are
 * unit vectors in world space: t the hair tangent, l towards the light, e towards the
 * eye. Results are linear RGB radiance for a unit light intensity, before shadowing. */
#ifndef HK_RENDER_SHADING_H
#define HK_RENDER_SHADING_H

#include "hairkit/io.h"
#include "hairkit/vecmath.h"

/* Kajiya-Kay: diffuse K_d sin(t, l) and specular K_s cos^p of the angle between e and
 * the cone of mirror reflections around t, (sin_tl sin_te - (t.l)(t.e))^p clamped at
 * 0 (Kajiya & Kay 1989; the thesis shader's abs() also lights the transmission cone).
 * Returns diffuse * sin + specular * spec; the ambient term is added by the caller. */
hk_Vec3 hk_shade_kajiya_kay(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_Visuality *v);

/* Parameters of the Marschner model (Marschner, Jensen, Cammarano, Worley, Hanrahan,
 * "Light Scattering from Human Hair Fibers", SIGGRAPH 2003). */
typedef struct hk_MarschnerParams {
    double eta;      /* refractive index of the fibre, 1.55 */
    double alpha_r;  /* longitudinal shift of the R lobe (radians), about -7 degrees;
                        TT is shifted by -alpha_r / 2, TRT by -3 alpha_r / 2 */
    double beta_r;   /* longitudinal width of the R lobe (radians), about 7 degrees;
                        TT: beta_r / 2, TRT: 2 beta_r */
    hk_Vec3 sigma_a; /* absorption coefficient of the fibre interior per unit of
                        fibre diameter, per colour channel */
} hk_MarschnerParams;

/* Default parameters with sigma_a chosen so that the hair's colour is about `diffuse`
 * (the visuality file's DiffuseColor, linear RGB in [0, 1]). */
hk_MarschnerParams hk_marschner_params_from_color(hk_Vec3 diffuse);

/* The fibre scattering function S(wi, wo) = sum over p in {R, TT, TRT} of
 * M_p(theta_h) N_p(phi) / cos^2(theta_d), with wi = l and wo = e, multiplied by
 * cos(theta_i) (the projected irradiance), so that the reflected radiance for a unit
 * light is the returned value. Non-negative and finite for any unit inputs. */
hk_Vec3 hk_shade_marschner(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_MarschnerParams *p);

/* The three terms of hk_shade_marschner, R, TT and TRT (their sum is its value). */
void hk_marschner_lobes(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_MarschnerParams *p, hk_Vec3 lobe[3]);

/* ---- multiple scattering: the dual scattering approximation (dual_scattering.c) ---- */

/* Zinke, Yuksel, Weber, Keyser, "Dual Scattering Approximation for Fast Multiple
 * Scattering in Hair" (SIGGRAPH 2008). Density factors of the paper (§4, fitted there to
 * path-traced hair): d_f scales the light forward-scattered to a fibre through the
 * others, d_b the light backscattered by its neighbours. */
#define HK_DUAL_DF    0.7
#define HK_DUAL_DB    0.7
#define HK_DUAL_THETA 18 /* incidences tabulated: theta_i = -90 + 10 (k + 1/2) degrees */

/* What the dual scattering approximation needs of a fibre at one incidence theta_i
 * (per colour channel): a_f and a_b, the fraction of the light the fibre scatters
 * into the forward half-space (cos(phi) < 0, away from the light) and the backward
 * one (Zinke §4.2, eq. 6), lobe[p] the whole of what lobe p (R, TT, TRT) scatters,
 * beta_f2 the mean variance of the forward lobes (weighted by what each scatters
 * forward), and the local (backward) multiple scattering of §4.3: A_b the light that
 * neighbouring fibres send back (eqs. 11-13, one and three backward scatterings),
 * delta_b its mean longitudinal shift and sigma_b2 its variance (eqs. 14-17). */
typedef struct hk_DualEntry {
    hk_Vec3 a_f, a_b, lobe[3], beta_f2, A_b, delta_b, sigma_b2;
} hk_DualEntry;

/* The table of one fibre (its Marschner parameters), made once per hair colour. */
typedef struct hk_DualScattering {
    hk_MarschnerParams fibre;
    hk_DualEntry at[HK_DUAL_THETA];
} hk_DualScattering;

/* Integrates the fibre's lobes numerically over the outgoing directions (midpoint rule,
 * 60 x 24 directions per half-space) at each tabulated incidence. Deterministic. */
void hk_dual_scattering_init(const hk_MarschnerParams *fibre, hk_DualScattering *ds);

/* The entry for sin(theta_i) = t.l, interpolated linearly between the tabulated ones. */
hk_DualEntry hk_dual_lookup(const hk_DualScattering *ds, double sin_i);

/* The models with multiple scattering, for a unit light, before the head's shadow: the
 * light reaches the fibre through on average `fibres` fibres (the deep opacity map's
 * opacity: the mean number of fibres a ray crosses). Unscattered, with the probability
 * D = exp(-fibres) (the single-scattering models' shadow); forward-scattered through
 * them, d_f (exp(-fibres (1 - a_f)) - D) (the mean of a_f^n over a Poisson count n,
 * less n = 0), its direction spread by the variance fibres x beta_f2 (Zinke §4.2).
 *   Marschner: D (S + d_b B) + G (S_G + pi d_b B_G), with B the local backscattering
 *     lobe of A_b, S_G the lobes widened by the spread and averaged over the azimuth,
 *     B_G widened as well (Zinke §5, "F_direct" and "F_scatter").
 *   Kajiya-Kay: D KK + G KK_G, KK_G with the specular cone widened by the spread; the
 *     diffuse colour of Kajiya-Kay is already the colour of lit hair, local scattering
 *     included, so only the global term is added.
 * The fibre of both is ds->fibre, Marschner's with the absorption of the diffuse
 * colour. Returns the radiance (times cos(theta_i), as the single models). */
hk_Vec3 hk_shade_dual_marschner(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, double fibres);
hk_Vec3 hk_shade_dual_kajiya_kay(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, double fibres,
                                 const hk_Visuality *v);

/* The two parts alone, for the tests: the local backscattering lobe d_b B (times
 * cos(theta_i)) of a fibre in full light, and G of the text above. */
hk_Vec3 hk_dual_local(const hk_DualScattering *ds, hk_Vec3 t, hk_Vec3 l, hk_Vec3 e);
hk_Vec3 hk_dual_global_fraction(const hk_DualEntry *entry, double fibres);

#endif
