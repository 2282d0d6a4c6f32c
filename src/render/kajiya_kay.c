/* Kajiya & Kay, "Rendering Fur with Three Dimensional Textures" (SIGGRAPH 1989), as in
 * Lansink 2010 §4.1.5: the diffuse term is Lambert's law integrated over the lit half
 * of the hair cylinder, K_d sin(t, l); the specular term is K_s cos^p of the angle
 * between the eye and the cone of mirror directions around the tangent.
 *
 * The cone: light arriving along -l leaves mirrored about the surface normal, which
 * is perpendicular to t, so the reflected direction r keeps the tangential component,
 * r.t = -l.t. The eye direction e closest to that cone makes the angle whose cosine
 * is sin(t,l) sin(t,e) - (t.l)(t.e). The thesis shader takes abs() of both dot
 * products, which also lights the mirror image of the cone (the forward, transmitted
 * direction); hairkit uses the reflection cone of the paper. */
#include "shading.h"

hk_Vec3 hk_shade_kajiya_kay(hk_Vec3 t, hk_Vec3 l, hk_Vec3 e, const hk_Visuality *v)
{
    const double tl = hk_v3_dot(t, l), te = hk_v3_dot(t, e);
    const double sin_tl = sqrt(fmax(0.0, 1.0 - tl * tl)), sin_te = sqrt(fmax(0.0, 1.0 - te * te));
    const double cone = sin_tl * sin_te - tl * te;
    const double spec = cone > 0.0 ? pow(cone, v->glossiness) : 0.0;
    return hk_v3_add(hk_v3_scale(v->diffuse, sin_tl), hk_v3_scale(v->specular, spec));
}
