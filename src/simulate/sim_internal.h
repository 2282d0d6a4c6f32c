/* Shared by the parts of a simulation: the regrowth of the interpolated hair out of the
 * posed body (the same code for a run, a rebuild and hk_hair_sim_groom, so that the
 * first two give the same bytes) and the video. */
#ifndef HK_SIM_INTERNAL_H
#define HK_SIM_INTERNAL_H

#include "hairkit/simulate.h"

/* The guides as a .hair stores them: every coordinate rounded to float (the file's
 * precision), so that the hair grown from them can be grown again from the file. */
void hk_sim_round_guides(double *guides, size_t values);

/* The time of frame k, k / fps, computed alike by the run and the rebuild. */
double hk_sim_frame_time(long frame, double fps);

/* The head's rigid state at time t (motion NULL: at rest). */
hk_RigidState hk_sim_head_pose(const hk_HeadMotion *motion, double t);

/* Where the last step left the head (at rest before the first). */
hk_RigidState hk_sim_head_now(const hk_HairSim *sim);

/* hk_groom_interpolate_guides with the body shapes (head space) posed where the head
 * is (hk_shapes_posed): world-space guides give world-space strands, kept out of the
 * body where it is now. */
hk_Status hk_sim_interpolate_posed(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                                   const hk_RigidState *head, const hk_Mesh *wick, const hk_GroomDef *go, hk_Groom *g,
                                   hk_Error *err);

/* The groom's cyHair data (guides, then interpolated strands unless guides_only) from
 * the rounded guides in g (g->guides, guide_count, points_per_strand set), the strands
 * kept out of the shapes posed at the frame's head state; g's strands are replaced.
 * reuse: out holds an earlier frame's hair (or is zeroed), whose arrays are reused
 * (hk_groom_to_hair_again); else out is filled anew. */
hk_Status hk_sim_grow_hair(const hk_Hairstyle *style, const hk_Shape *shapes, int shape_count,
                           const hk_RigidState *head, const hk_Mesh *wick, uint64_t seed, int threads, int guides_only,
                           int reuse, hk_Groom *g, hk_HairFile *out, hk_Error *err);

/* ffmpeg -framerate F -i DIR/frame_%04d.png ... DIR/hair.mp4 when ffmpeg is on the
 * PATH: 1 made, 0 not installed, -1 ffmpeg failed. */
int hk_sim_make_video(const char *dir, double fps);

/* Size of a file in bytes, 0 when it cannot be read. */
long long hk_sim_file_size(const char *path);

#endif
