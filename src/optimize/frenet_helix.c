/* A discrete Frenet helix as a curve model for curvefit.h: the simplest model with a
 * frame, traced the way the paper traces helicoids (forward Euler, eq. 3). The tests and
 * `hairkit bench curvefit` fit it; it is an example of the model callback too. */
#include <math.h>

#include "hairkit/curvefit.h"

int hk_curve_model_frenet_helix(void *user, const double *params, const hk_CurveStart *start, double length, int count,
                                hk_Vec3 *out_points, hk_CurveStart *end)
{
    (void)user;
    if (count < 2) return 1;
    const double h = length / (double)(count - 1);
    const double ca = cos(params[0] * h), sa = sin(params[0] * h), cb = cos(params[1] * h), sb = sin(params[1] * h);
    /* M = Rz(kappa h) Rx(tau h): turn by kappa h about B, then twist by tau h about the new T */
    const hk_Mat3 m = {{{ca, -sa * cb, sa * sb}, {sa, ca * cb, -ca * sb}, {0.0, sb, cb}}};
    hk_Mat3 r = start->frame;
    hk_Vec3 p = start->pos;
    out_points[0] = p;
    for (int i = 1; i < count; i++) {
        p = hk_v3_madd(p, hk_m3_col(&r, 0), h);
        out_points[i] = p;
        r = hk_m3_mul(&r, &m);
    }
    end->pos = p;
    end->frame = r;
    return 0;
}
