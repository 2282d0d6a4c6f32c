/* Stages of the groom pipeline shared between src/groom/ files. */
#ifndef HK_GROOM_INTERNAL_H
#define HK_GROOM_INTERNAL_H

#include "hairkit/groom.h"

/* Reports progress from thread 0 only (OpenMP), at most every 1/200 of the work. */
void hk_groom_report(const hk_GroomDef *o, const char *stage, long done, long total);

/* The threads of the grooming's parallel loops: o->threads, or OpenMP's default. */
int hk_groom_threads(const hk_GroomDef *o);

/* Solves one guide per follicle; fills g->guides, g->points_per_strand, stats. */
hk_Status hk_groom_solve_guides(const hk_StrandDef *strand, const hk_Shape *shapes, int shape_count,
                                const hk_Follicles *f, const hk_GroomDef *o, hk_Groom *g, hk_Error *err);

/* Fills every wick triangle with interpolated strands from its three guides, kept
 * out of the body shapes among shapes[0..shape_count) when o->keep_outside is set. */
hk_Status hk_groom_interpolate(const hk_InterpolationDef *interp, const hk_Shape *shapes, int shape_count,
                               const hk_Mesh *wick, const hk_GroomDef *o, hk_Groom *g, hk_Error *err);

/* Keeping strands out of the body (body_projection.c). hk_groom_body_shapes copies the
 * shapes that are body (not styling) into *body (NULL when there are none; hk_free
 * it). hk_groom_keep_outside moves the points of one strand (point_count x 3 floats,
 * root first) that lie inside a body shape out of it, root to tip, keeping every
 * segment's length and leaving the root where it is; a strand that touches no body
 * shape keeps its bytes. */
hk_Status hk_groom_body_shapes(const hk_Shape *shapes, int count, hk_Shape **body, int *body_count, hk_Error *err);
void hk_groom_keep_outside(const hk_Shape *body, int count, float *points, int point_count);

/* Root and tip barycentric weights of one interpolated strand (interpolate.c),
 * exposed for the tests: uniform roots from two uniform numbers; the thesis's tip
 * weights (§4.1.4.3) from the root weights and two uniform numbers, with its stray-hair
 * assignment (§4.1.4.4, Table 4) when `stray` is set. */
void hk_groom_root_weights(double r1, double r2, double b[3]);
void hk_groom_tip_weights(const double root[3], double clump, double u1, double u2, int stray, double b[3]);

#endif
