/* Private parts of the curve fitting (include/hairkit/curvefit.h, docs/helicoid-fitting.md). */
#ifndef HK_CURVEFIT_INTERNAL_H
#define HK_CURVEFIT_INTERNAL_H

#include "hairkit/curvefit.h"

/* Coupling (sum of leashes) of two polylines of the same count n >= 1; when prefix is not
 * NULL, prefix[k] gets the coupling of the first k + 1 points of both (the diagonal of
 * the dynamic programme), which the split heuristics of §5.3 grow fragments with.
 * row holds n doubles. */
double hk_frechet_coupling_prefix(const hk_Vec3 *a, const hk_Vec3 *b, int n, double *row, double *prefix);

/* Coupling and distance in one pass (the leash lengths are shared): work holds
 * 2 * HK_FRECHET_WORK(p, q) doubles. Unchecked, like the public fast entry points. */
void hk_frechet_both(const hk_Vec3 *a, int p, const hk_Vec3 *b, int q, double *work, double *coupling,
                     double *distance);

/* Intrinsic bend of a polyline at vertex i (0 < i < count - 2): the turning angle between
 * segments i-1 and i (discrete curvature times the spacing) and the signed angle between
 * the osculating planes at vertices i and i+1 about segment i (discrete torsion times the
 * spacing; 0 where either corner is nearly straight). Independent of where the curve is
 * and how it is turned, so a fit that drifted a little still compares well. */
void hk_polyline_bend(const hk_Vec3 *points, int i, double *turn, double *twist);

#endif
