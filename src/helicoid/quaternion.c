/* Rotation <-> unit quaternion, for averaging root frames in interpolation (Piuze et al. 2011 §4.1),
 * and rotations about an axis (wisps' fans, reconstruction's turned guides).
 * Shepperd's method: the square root is taken of the largest of the four candidates
 * (trace or a diagonal entry), so no division by a small number happens for any rotation. */
#include "helicoid_internal.h"

void hk_helicoid_quat_from_rotation(const hk_Mat3 *r, double q[4])
{
    const double(*m)[3] = r->m;
    const double tr = m[0][0] + m[1][1] + m[2][2];
    if (tr >= m[0][0] && tr >= m[1][1] && tr >= m[2][2]) {
        const double s = 2.0 * sqrt(fmax(1.0 + tr, 0.0));
        q[0] = 0.25 * s;
        q[1] = (m[2][1] - m[1][2]) / s;
        q[2] = (m[0][2] - m[2][0]) / s;
        q[3] = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
        const double s = 2.0 * sqrt(fmax(1.0 + m[0][0] - m[1][1] - m[2][2], 0.0));
        q[0] = (m[2][1] - m[1][2]) / s;
        q[1] = 0.25 * s;
        q[2] = (m[0][1] + m[1][0]) / s;
        q[3] = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] >= m[2][2]) {
        const double s = 2.0 * sqrt(fmax(1.0 + m[1][1] - m[0][0] - m[2][2], 0.0));
        q[0] = (m[0][2] - m[2][0]) / s;
        q[1] = (m[0][1] + m[1][0]) / s;
        q[2] = 0.25 * s;
        q[3] = (m[1][2] + m[2][1]) / s;
    } else {
        const double s = 2.0 * sqrt(fmax(1.0 + m[2][2] - m[0][0] - m[1][1], 0.0));
        q[0] = (m[1][0] - m[0][1]) / s;
        q[1] = (m[0][2] + m[2][0]) / s;
        q[2] = (m[1][2] + m[2][1]) / s;
        q[3] = 0.25 * s;
    }
    const double n = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (int i = 0; i < 4; i++) q[i] /= n;
}

hk_Mat3 hk_helicoid_rotation_from_quat(const double q[4])
{
    const double w = q[0], x = q[1], y = q[2], z = q[3];
    hk_Mat3 r = {{{1.0 - 2.0 * (y * y + z * z), 2.0 * (x * y - w * z), 2.0 * (x * z + w * y)},
                  {2.0 * (x * y + w * z), 1.0 - 2.0 * (x * x + z * z), 2.0 * (y * z - w * x)},
                  {2.0 * (x * z - w * y), 2.0 * (y * z + w * x), 1.0 - 2.0 * (x * x + y * y)}}};
    return r;
}

hk_Mat3 hk_helicoid_axis_angle(hk_Vec3 a, double angle)
{
    const hk_Mat3 k = hk_m3_skew(a), k2 = hk_m3_mul(&k, &k), i = hk_m3_identity();
    const hk_Mat3 ks = hk_m3_scale(&k, sin(angle)), k2s = hk_m3_scale(&k2, 1.0 - cos(angle));
    hk_Mat3 r = hk_m3_add(&i, &ks);
    return hk_m3_add(&r, &k2s);
}
