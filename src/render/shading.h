/* Hair and skin shading models of the renderer: Kajiya-Kay (thesis 004 §4.1.5, the
 * default) and Marschner et al. 2003 (paper 000 renders with it). All directions are
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
    double eta;        /* refractive index of the fibre, 1.55 */
    double alpha_r;    /* longitudinal shift of the R lobe (radians), about -7 degrees;
                          TT is shifted by -alpha_r / 2, TRT by -3 alpha_r / 2 */
    double beta_r;     /* longitudinal width of the R lobe (radians), about 7 degrees;
                          TT: beta_r / 2, TRT: 2 beta_r */
    hk_Vec3 sigma_a;   /* absorption coefficient of the fibre interior per unit of
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

#endif
