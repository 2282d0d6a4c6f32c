/* Small fixed-size vector and matrix algebra in double precision (header only).
 *
 * hk_Mat3 is row-major: m[row][col]. A material frame (n0, n1, n2) is stored as the
 * columns of a rotation matrix, so that world = R * local. */
#ifndef HAIRKIT_VECMATH_H
#define HAIRKIT_VECMATH_H

#include <math.h>

/* pi to the precision of a long double literal, defined once for the whole library (math.h
 * has M_PI only as a POSIX extension). */
#define HK_PI 3.14159265358979323846

#ifdef __cplusplus
extern "C" {
#endif

typedef struct hk_Vec3 {
    double x, y, z;
} hk_Vec3;

typedef struct hk_Mat3 {
    double m[3][3];
} hk_Mat3;

static inline hk_Vec3 hk_v3(double x, double y, double z)
{
    hk_Vec3 v = {x, y, z};
    return v;
}
static inline hk_Vec3 hk_v3_zero(void) { return hk_v3(0.0, 0.0, 0.0); }
static inline hk_Vec3 hk_v3_add(hk_Vec3 a, hk_Vec3 b) { return hk_v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline hk_Vec3 hk_v3_sub(hk_Vec3 a, hk_Vec3 b) { return hk_v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline hk_Vec3 hk_v3_scale(hk_Vec3 a, double s) { return hk_v3(a.x * s, a.y * s, a.z * s); }
static inline hk_Vec3 hk_v3_neg(hk_Vec3 a) { return hk_v3(-a.x, -a.y, -a.z); }
/* a + s*b */
static inline hk_Vec3 hk_v3_madd(hk_Vec3 a, hk_Vec3 b, double s)
{
    return hk_v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}
static inline double hk_v3_dot(hk_Vec3 a, hk_Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline hk_Vec3 hk_v3_cross(hk_Vec3 a, hk_Vec3 b)
{
    return hk_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double hk_v3_norm2(hk_Vec3 a) { return hk_v3_dot(a, a); }
static inline double hk_v3_norm(hk_Vec3 a) { return sqrt(hk_v3_dot(a, a)); }
static inline double hk_v3_dist(hk_Vec3 a, hk_Vec3 b) { return hk_v3_norm(hk_v3_sub(a, b)); }
/* Unit vector along a; returns the zero vector when |a| == 0. */
static inline hk_Vec3 hk_v3_normalize(hk_Vec3 a)
{
    double n = hk_v3_norm(a);
    return n > 0.0 ? hk_v3_scale(a, 1.0 / n) : hk_v3_zero();
}
static inline double hk_v3_get(hk_Vec3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }
static inline void hk_v3_set(hk_Vec3 *a, int i, double v)
{
    if (i == 0)
        a->x = v;
    else if (i == 1)
        a->y = v;
    else
        a->z = v;
}
static inline int hk_v3_isfinite(hk_Vec3 a) { return isfinite(a.x) && isfinite(a.y) && isfinite(a.z); }
/* Unit basis vector e_i. */
static inline hk_Vec3 hk_v3_unit(int i) { return hk_v3(i == 0, i == 1, i == 2); }

static inline hk_Mat3 hk_m3_identity(void)
{
    hk_Mat3 r = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    return r;
}
static inline hk_Mat3 hk_m3_zero(void)
{
    hk_Mat3 r = {{{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}};
    return r;
}
static inline hk_Mat3 hk_m3_from_cols(hk_Vec3 c0, hk_Vec3 c1, hk_Vec3 c2)
{
    hk_Mat3 r = {{{c0.x, c1.x, c2.x}, {c0.y, c1.y, c2.y}, {c0.z, c1.z, c2.z}}};
    return r;
}
static inline hk_Vec3 hk_m3_col(const hk_Mat3 *a, int j) { return hk_v3(a->m[0][j], a->m[1][j], a->m[2][j]); }
static inline hk_Vec3 hk_m3_row(const hk_Mat3 *a, int i) { return hk_v3(a->m[i][0], a->m[i][1], a->m[i][2]); }
static inline hk_Vec3 hk_m3_mul_v3(const hk_Mat3 *a, hk_Vec3 v)
{
    return hk_v3(a->m[0][0] * v.x + a->m[0][1] * v.y + a->m[0][2] * v.z,
                 a->m[1][0] * v.x + a->m[1][1] * v.y + a->m[1][2] * v.z,
                 a->m[2][0] * v.x + a->m[2][1] * v.y + a->m[2][2] * v.z);
}
/* a^T v */
static inline hk_Vec3 hk_m3_tmul_v3(const hk_Mat3 *a, hk_Vec3 v)
{
    return hk_v3(a->m[0][0] * v.x + a->m[1][0] * v.y + a->m[2][0] * v.z,
                 a->m[0][1] * v.x + a->m[1][1] * v.y + a->m[2][1] * v.z,
                 a->m[0][2] * v.x + a->m[1][2] * v.y + a->m[2][2] * v.z);
}
/* The 3 x 3 loops carry `#pragma GCC unroll`: GCC 12's -O2 keeps them rolled; written out
 * they are the same operations in the same order (the same bits), without the counters. */
static inline hk_Mat3 hk_m3_mul(const hk_Mat3 *a, const hk_Mat3 *b)
{
    hk_Mat3 r;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j];
    return r;
}
static inline hk_Mat3 hk_m3_transpose(const hk_Mat3 *a)
{
    hk_Mat3 r;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) r.m[i][j] = a->m[j][i];
    return r;
}
static inline hk_Mat3 hk_m3_add(const hk_Mat3 *a, const hk_Mat3 *b)
{
    hk_Mat3 r;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) r.m[i][j] = a->m[i][j] + b->m[i][j];
    return r;
}
static inline hk_Mat3 hk_m3_scale(const hk_Mat3 *a, double s)
{
    hk_Mat3 r;
#pragma GCC unroll 3
    for (int i = 0; i < 3; i++)
#pragma GCC unroll 3
        for (int j = 0; j < 3; j++) r.m[i][j] = a->m[i][j] * s;
    return r;
}
/* a b^T */
static inline hk_Mat3 hk_m3_outer(hk_Vec3 a, hk_Vec3 b)
{
    hk_Mat3 r = {
        {{a.x * b.x, a.x * b.y, a.x * b.z}, {a.y * b.x, a.y * b.y, a.y * b.z}, {a.z * b.x, a.z * b.y, a.z * b.z}}};
    return r;
}
/* [a]x, the matrix with [a]x v = a x v */
static inline hk_Mat3 hk_m3_skew(hk_Vec3 a)
{
    hk_Mat3 r = {{{0, -a.z, a.y}, {a.z, 0, -a.x}, {-a.y, a.x, 0}}};
    return r;
}
static inline double hk_m3_trace(const hk_Mat3 *a) { return a->m[0][0] + a->m[1][1] + a->m[2][2]; }

/* The six axes a file (hair or mesh) may have as its up direction; hairkit's up is +y.
 * Names: hk_axis_from_name, hk_axis_name (hairkit/hair_formats.h). */
typedef enum hk_Axis {
    HK_AXIS_POS_X,
    HK_AXIS_NEG_X,
    HK_AXIS_POS_Y,
    HK_AXIS_NEG_Y,
    HK_AXIS_POS_Z,
    HK_AXIS_NEG_Z
} hk_Axis;

/* p rotated by the smallest rotation that takes `up` onto +y. Every case only swaps and
 * negates coordinates, so it is exact (docs/file-formats.md, "Units and axes"):
 *   +y  none:                     (x, y, z) -> ( x,  y,  z)
 *   +x  +90 degrees about z:      (x, y, z) -> (-y,  x,  z)
 *   -x  -90 degrees about z:      (x, y, z) -> ( y, -x,  z)
 *   +z  -90 degrees about x:      (x, y, z) -> ( x,  z, -y)
 *   -z  +90 degrees about x:      (x, y, z) -> ( x, -z,  y)
 *   -y  180 degrees about x:      (x, y, z) -> ( x, -y, -z)
 *       (a half turn about any axis in the xz plane is as small; x is the one chosen) */
static inline hk_Vec3 hk_v3_up_to_y(hk_Vec3 p, hk_Axis up)
{
    switch (up) {
    case HK_AXIS_POS_X:
        return hk_v3(-p.y, p.x, p.z);
    case HK_AXIS_NEG_X:
        return hk_v3(p.y, -p.x, p.z);
    case HK_AXIS_POS_Z:
        return hk_v3(p.x, p.z, -p.y);
    case HK_AXIS_NEG_Z:
        return hk_v3(p.x, -p.z, p.y);
    case HK_AXIS_NEG_Y:
        return hk_v3(p.x, -p.y, -p.z);
    case HK_AXIS_POS_Y:
        break;
    }
    return p;
}

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_VECMATH_H */
