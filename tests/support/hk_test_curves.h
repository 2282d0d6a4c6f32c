/* Comparing a fitted curve with the polyline it was fitted to, independently of the
 * fitter's own measures (for the fitting tests). */
#ifndef HK_TEST_CURVES_H
#define HK_TEST_CURVES_H

#include "hairkit/vecmath.h"

/* Mean distance from the points of a to the polyline b (each point to its nearest segment)
 * and from the points of b to the polyline a: the larger of the two (m). O(na nb). */
double hk_test_polyline_distance(const hk_Vec3 *a, int na, const hk_Vec3 *b, int nb);

#endif
