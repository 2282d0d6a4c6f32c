/* A k-d tree over 3-D points for k-nearest-neighbour queries (Bentley 1975; Friedman,
 * Bentley and Finkel 1977). Internal to hairkit (not installed, not exported): included
 * as "core/kd_tree.h". The answer is exactly the brute force's: the k points with the
 * smallest (hk_v3_dist, index) in lexicographic order, the distances computed by the same
 * hk_v3_dist, so ties and duplicates come out as a scan over increasing index keeps them
 * (the lower index first) and the result does not depend on the tree's shape or threads. */
#ifndef HK_CORE_KD_TREE_H
#define HK_CORE_KD_TREE_H

#include "hairkit/core.h"
#include "hairkit/vecmath.h"

typedef struct hk_KdTree {
    hk_Vec3 *points;     /* the points in tree order (a balanced tree, implicit in the array) */
    int *index;          /* their indices in the input */
    unsigned char *axis; /* the splitting axis of the node whose median sits at that place */
    int count;
} hk_KdTree;

/* Builds the tree of points[0..count) (count >= 1, every coordinate finite: a point that
 * is not is refused with HK_ERR_INVALID naming it). The points are copied. */
hk_Status hk_kd_tree_build(hk_KdTree *tree, const hk_Vec3 *points, int count, hk_Error *err);
void hk_kd_tree_free(hk_KdTree *tree);

/* The min(k, count) points nearest to x into index[] and dist[] (k >= 1), nearest first,
 * equal distances by increasing index; returns how many. A query point that is not finite
 * gets what the brute force gives it (the lowest indices, its distances being NaN). */
int hk_kd_tree_nearest(const hk_KdTree *tree, hk_Vec3 x, int k, int *index, double *dist);

/* The definition the tree answers to: every point scanned in index order, the k nearest kept
 * in a sorted list, a point placed after those at an equal distance (the reconstruction's
 * search before the tree; kept for the tests and the benchmark to compare with). */
int hk_nearest_by_scan(const hk_Vec3 *points, int count, hk_Vec3 x, int k, int *index, double *dist);

#endif /* HK_CORE_KD_TREE_H */
