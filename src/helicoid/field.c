/* The generalized helicoid field (Piuze et al. 2011 §3, eq. 1) and its frame (eq. 2), public forms of
 * the inline evaluation the tracers use. */
#include "helicoid_internal.h"

void hk_helicoid_angles(const hk_Helicoid *k, hk_Vec3 x, double theta_prev, double *theta, double *phi)
{
    double t = NAN, f = NAN;
    if (k) {
        hk_HelicoidAngles a;
        hk_helicoid_eval(k, x.x, x.y, x.z, theta_prev, &a);
        t = a.theta;
        f = k->alpha * a.theta;
    }
    if (theta) *theta = t;
    if (phi) *phi = f;
}

hk_Mat3 hk_helicoid_frame(double theta, double phi)
{
    const hk_HelicoidAngles a = {theta, cos(theta), sin(theta), cos(phi), sin(phi)};
    return hk_helicoid_frame_of(&a);
}
