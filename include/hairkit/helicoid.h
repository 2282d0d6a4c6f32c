/* Generalized helicoids (Piuze, Kry, Siddiqi, "Generalized Helicoids for Modeling Hair
 * Geometry", 2011): the orientation field of eq. 1-2, strands traced along it (§3.1), waviness (§3.2), wisps (§3.3), piecewise helicoids (§3.4)
 * and inverse-distance interpolation between guide strands (§4.1-4.2). docs/helicoids.md
 * has the derivations behind the choices made here.
 *
 * Coordinates. A helicoid field lives in a local frame: x along E_T, y along E_N, z along
 * E_B of the strand's root. A strand with root p0 and root frame Q (a rotation whose columns
 * are E_T, E_N, E_B at the root, in world coordinates) is the streamline of
 *     dp/ds = Q E_T(theta(x), phi(x)),   x = Q^T (p - p0),
 * through p0, s being the arc length. At the root theta = phi = 0, so the strand leaves p0
 * along Q's first column. Units are the caller's: k_T, k_N, k_B are curvatures (1/length),
 * alpha is a pure number, lengths and steps are in the same length unit as positions. */
#ifndef HAIRKIT_HELICOID_H
#define HAIRKIT_HELICOID_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

/* k = (k_T, k_N, k_B, alpha) of eq. 1:
 *     theta(x, y, z) = arg(1 + k_N x - k_T y + i (k_T x + k_N y)) + k_B z,   phi = alpha theta,
 * the argument being continued along the strand (2 pi cycles counted, see hk_helicoid_angles).
 * k_T bends the strand in the E_T-E_N plane (a circle of radius 1/|k_T| when alone), k_N fans
 * neighbouring streamlines out (k_N > 0) or into a sink (k_N < 0), k_B twists the field about
 * E_B, alpha lifts the strand out of the E_T-E_N plane. */
typedef struct hk_Helicoid {
    double kt, kn, kb, alpha;
} hk_Helicoid;

#define HK_HELICOID_MAX_PIECES 64

/* Most points one trace may have (hk_phelicoid_point_count refuses more): a guard against a
 * step absurdly small for the strand's length, not a limit real strands come near. */
#define HK_HELICOID_MAX_POINTS (1 << 20)

/* A p-helicoid strand (§3.1, §3.4): root p0, root frame Q (columns E_T, E_N, E_B at the root;
 * a rotation: orthonormal to 1e-6 with determinant +1), pieces with their parameters and
 * lengths. Piece i+1 starts where piece i ends, its frame being the frame of eq. 2 at that
 * end point (in world coordinates), so the strand's frame is continuous across the joins. */
typedef struct hk_PHelicoid {
    hk_Vec3 root;
    hk_Mat3 frame;
    int piece_count;                       /* 1..HK_HELICOID_MAX_PIECES */
    hk_Helicoid k[HK_HELICOID_MAX_PIECES]; /* finite */
    double length[HK_HELICOID_MAX_PIECES]; /* finite, > 0 */
} hk_PHelicoid;

/* Waviness of eq. 4: the traced point p(s) is offset by a cos(b s + c) E_B(s) + a sin(b s + c)
 * E_N(s), s the arc length from the root (the root itself moves by a cos c E_B + a sin c E_N).
 * amplitude = a >= 0 (0: none), frequency = b in radians per unit length (one helical turn
 * every 2 pi / b), phase = c in radians (the paper's eq. 4 has c = 0; a phase per strand keeps
 * neighbouring strands from waving in step, which renders as a net). */
typedef struct hk_Waviness {
    double amplitude, frequency, phase;
} hk_Waviness;

/* Field angles theta, phi of eq. 1 at the local point x of one helicoid. The arctangent of
 * eq. 1 is the argument of w = 1 + (k_N + i k_T)(x + i y); theta is the value nearest to
 * theta_prev among the 2 pi-spaced ones, so that calling it along a path with theta_prev the
 * previous value (0 at a strand's root) counts the cycles (§3) and keeps phi = alpha theta
 * continuous. theta or phi may be NULL. A NULL k gives NaN. */
HK_API void hk_helicoid_angles(const hk_Helicoid *k, hk_Vec3 x, double theta_prev, double *theta, double *phi);

/* The frame of eq. 2 for the angles theta, phi, as the columns of a rotation:
 *     E_T = (cos phi cos theta, cos phi sin theta, sin phi),  E_N = (-sin theta, cos theta, 0),
 *     E_B = E_T x E_N = (-sin phi cos theta, -sin phi sin theta, cos phi). */
HK_API hk_Mat3 hk_helicoid_frame(double theta, double phi);

/* HK_OK when h is a valid p-helicoid (piece count in range, finite root, parameters and
 * lengths, positive lengths, a rotation as frame); else HK_ERR_INVALID naming the culprit. */
HK_API hk_Status hk_phelicoid_check(const hk_PHelicoid *h, hk_Error *err);

/* Number of points of a trace with step h: the root, then each piece of length L_i split into
 * n_i = ceil(L_i / h) equal steps of L_i / n_i <= h (a ratio within 1e-12 of an integer counts
 * as that integer), one point per step; the last point of a piece lands exactly at its end and
 * the tip is the last point: 1 + sum n_i. -1 when h or step is invalid or the count would
 * exceed HK_HELICOID_MAX_POINTS. */
HK_API int hk_phelicoid_point_count(const hk_PHelicoid *h, double step);

/* Traces the strand: points (hk_phelicoid_point_count entries) in world coordinates; frames
 * (same count; NULL = not wanted) are the helicoid frames Q_i F(theta, phi) of eq. 2 at the
 * points of the unwaved curve (their first column is the tangent). waviness may be NULL.
 * Root offset (for wisps, §3.3): a local offset of the trace's start in the root frame (NULL =
 * none): the trace is then the streamline of the same piecewise field through root + Q offset,
 * switching piece where the strand (by its own arc length) reaches the piece's length; the
 * pieces' fields stay where the unoffset strand puts them.
 * Integration: where alpha = 0 the streamline has a closed form (docs/helicoids.md) used
 * directly (exact; straight lines, circles, logarithmic spirals); elsewhere classical RK4 with
 * the step above (error O(step^4)). A streamline that runs into the singular axis of its
 * field (w = 0, a sink of k_N < 0) ends there in the closed form; RK4 gives finite but
 * meaningless points near it. HK_ERR_INVALID for bad input, HK_ERR_NUMERIC if the result is
 * not finite (absurdly large parameters). */
HK_API hk_Status hk_phelicoid_trace(const hk_PHelicoid *h, double step, const hk_Waviness *waviness,
                                    const hk_Vec3 *root_offset, hk_Vec3 *points, hk_Mat3 *frames, hk_Error *err);

/* Total length (sum of the piece lengths); 0 for NULL or a piece count out of range. */
HK_API double hk_phelicoid_length(const hk_PHelicoid *h);

/* The pi-rotation rule of §4.1, as derived (docs/helicoids.md): turning the root frame by pi
 * about E_T (Q -> Q diag(1, -1, -1)) and negating k_T of every piece leaves the traced curve
 * exactly unchanged (k_N, k_B, alpha unchanged; E_N and E_B of all frames change sign; a
 * waviness offset turns by pi about the curve). The paper's "pi about E_N" would reverse the
 * strand's initial direction. When the first piece has k_T < 0 this applies it, so the first
 * piece ends with k_T >= 0; the later pieces' k_T signs all flip with it (their frames are
 * forced by continuity), so only the first piece's sign can be chosen. NULL: nothing. */
HK_API void hk_phelicoid_canonical(hk_PHelicoid *h);

/* Inverse-distance (Shepard) interpolation of §4.1-4.2 at the root x: weights
 * w_i ~ |x - x_i|^-power over all guides (power 3 in the paper). The guides are taken in their
 * canonical form (hk_phelicoid_canonical). The result has root x; frame the weighted average
 * of the guides' root frames (unit quaternions aligned in sign with the heaviest guide's,
 * averaged and normalised: a rotation even between pi-rotated frames, where an average of
 * matrices degenerates); piece count round(sum w_i n_i); total length sum w_i L_i; first piece
 * length sum w_i L_i1 and k sum w_i k_i1; piece j gets k = sum w_i k_ij, a guide with fewer
 * pieces lending its last; the further pieces share the rest of the length in proportion to
 * their interpolated lengths sum w_i L_ij (the paper's equal shares when the guides' later
 * pieces are equal; all pieces equal when that rest is ~0). normal (NULL = none): the outward surface normal at x (any
 * non-zero length); the frame is then turned by the smallest rotation that keeps E_T from
 * pointing into the surface (E_T . n >= 0), which averaging far-apart guides on a curved
 * scalp can otherwise produce. At x equal to a guide's root the guide itself is returned, in
 * canonical form (the same strand; normal then ignored). out may be one of the guides. No
 * allocation; O(guide_count). */
HK_API hk_Status hk_phelicoid_interpolate(const hk_PHelicoid *guides, int guide_count, hk_Vec3 x, const hk_Vec3 *normal,
                                          double power, hk_PHelicoid *out, hk_Error *err);

/* Interpolation on a surface (§4.3): as hk_phelicoid_interpolate (the same weights, pieces,
 * lengths and parameters), but the root frames are averaged relative to the surface, the
 * paper's frame W "oriented by the normal" combined with the guides' frames. guide_normals[i]
 * is the outward surface normal at guide i's root, normal the one at x (any non-zero finite
 * lengths). Each guide's canonical root frame is first carried to x by the smallest rotation
 * taking guide_normals[i] to normal (the guide's frame W_i to W, transported across the
 * surface), so what is averaged is how each guide sits on the surface (its angle to it and
 * the way it leans), not its orientation in space: guides that leave along their normals give
 * strands that leave along theirs, exactly, all round a head. Then, when E_T . normal <
 * sin(min_elevation), the frame is turned by the smallest rotation that raises E_T to that
 * elevation (keeping its azimuth), so that every interpolated strand leaves the surface
 * (min_elevation in [0, pi/2) radians). At x equal to a guide's root the guide itself is
 * returned in canonical form, as it is. No allocation; O(guide_count). */
HK_API hk_Status hk_phelicoid_interpolate_on_surface(const hk_PHelicoid *guides, const hk_Vec3 *guide_normals,
                                                     int guide_count, hk_Vec3 x, hk_Vec3 normal, double power,
                                                     double min_elevation, hk_PHelicoid *out, hk_Error *err);

/* Wisp (§3.3): count strands around a guide. Strand j's root offset is uniform in the disc of
 * radius `radius` in the guide's E_N-E_B plane at the root, drawn from the counter-based RNG
 * (rng.h) keyed by (seed, j), so strand j does not depend on count or on threads. It is the
 * streamline of the guide's field through that point (hk_phelicoid_trace with root_offset);
 * spread > 0 (radians, <= pi) then tilts the whole strand rigidly about its own root by an
 * angle uniform in [0, spread] about a random axis of the E_N-E_B plane (the "random
 * orientation perturbation" that fans the wisp out). w may be NULL. points holds count x
 * hk_phelicoid_point_count(guide, step) points, strand after strand. */
HK_API hk_Status hk_phelicoid_wisp(const hk_PHelicoid *guide, int count, double radius, double spread, uint64_t seed,
                                   double step, const hk_Waviness *w, hk_Vec3 *points, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_HELICOID_H */
