/* Guide strands of the helicoid hairstyles in examples/helicoid/ (Piuze et al. 2011 §4.3, Fig. 11):
 * planar p-helicoids that leave the scalp along its normal, lie down over the head at a
 * chosen height and fall from where nothing is below them, in the plane of the normal and the
 * way down the head, away from the crown (root frame: E_T = the normal, E_N = that way). Each
 * guide is designed by walking it on the head mesh, then written as pieces of constant
 * curvature with the same structure for every guide (one lift piece, `hug` pieces over the
 * head, `fall` pieces below), so that piece j means the same thing on every guide and the
 * interpolation of §4.2 blends like with like.
 * Usage: make_helicoid_styles HEAD.obj WICK.obj long|bob OUT.txt
 *        make_helicoid_styles --check HEAD.obj HAIR.hair  (strands that go into the head or
 *        hang in front of the face, from a sample of them) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/hairfile.h"
#include "hairkit/helicoid.h"
#include "hairkit/mesh.h"
#include "io/outfile.h"

#define MAX_GUIDES 64
#define DS         0.0005 /* walking step (m) */
#define MAX_STEPS  4000

typedef struct Style {
    const char *name, *comment;
    int guides;                            /* roots: farthest-point samples of the wick's vertices */
    hk_Vec3 crown;                         /* a point of the crown's vertical axis: hair parts radially from it */
    int crown_ring;                        /* guides round the crown ... */
    double crown_radius;                   /* ... this far from its axis (m) */
    double lift_angle, lift;               /* the first piece turns the strand by lift_angle (rad) over lift (m) */
    double volume;                         /* height of the hair over the head (m) */
    double tip_y, fringe_tip_y;            /* tip heights (m): at the sides and back, and of the fringe */
    double fringe_half_width;              /* strands combed forward from roots with |x| below this (m) ... */
    double fringe_blend;                   /* ... have the fringe's length, blending to the full one over this (m) */
    double curl_under;                     /* the last piece turns the tips under by this much (rad) */
    int hug, fall;                         /* pieces over the head and below it */
    double wave_amplitude, wave_frequency; /* eq. 4 (m, rad/m) */
    double wave_jitter;                    /* strands' phase spread (turns, file format) */
} Style;

static const Style STYLES[] = {
    {"long",
     "long wavy hair with a fringe",
     40,
     {0.0, 0.0, -0.03},
     6,
     0.015,
     1.35,
     0.008,
     0.012,
     -0.22,
     0.095,
     0.045,
     0.02,
     0.0,
     4,
     6,
     0.004,
     120.0,
     0.3},
    {"bob",
     "a curly bob with a fringe",
     40,
     {0.0, 0.0, -0.06},
     6,
     0.015,
     1.0,
     0.012,
     0.016,
     -0.045,
     0.095,
     0.045,
     0.02,
     0.5,
     4,
     3,
     0.006,
     250.0,
     0.4},
};

typedef struct Guide {
    hk_PHelicoid h;
    double azimuth; /* from the front (+z), towards +x */
} Guide;

/* Signed distance to the head (outside > 0) and the outward direction at the closest point. */
static double head_distance(const hk_Mesh *head, hk_Vec3 p, hk_Vec3 *out)
{
    hk_Vec3 q, n;
    const double d = hk_mesh_closest_point(head, p, &q, &n);
    const hk_Vec3 r = hk_v3_sub(p, q);
    *out = d > 1e-9 ? hk_v3_scale(r, 1.0 / d) : n;
    return hk_v3_dot(r, n) < 0.0 ? -d : d;
}

/* The highest point of the wick above (x, z): 0 when there is none. */
static int point_above(const hk_Mesh *wick, double x, double z, hk_Vec3 *out)
{
    int found = 0;
    for (int t = 0; t < wick->triangle_count; t++) {
        const int *v = wick->triangles + 3 * t;
        const hk_Vec3 a = wick->positions[v[0]], b = wick->positions[v[1]], c = wick->positions[v[2]];
        /* barycentric coordinates of (x, z) in the triangle's shadow on the x-z plane */
        const double det = (b.x - a.x) * (c.z - a.z) - (c.x - a.x) * (b.z - a.z);
        if (fabs(det) < 1e-18) continue;
        const double u = ((x - a.x) * (c.z - a.z) - (c.x - a.x) * (z - a.z)) / det;
        const double w = ((b.x - a.x) * (z - a.z) - (x - a.x) * (b.z - a.z)) / det;
        if (u < 0.0 || w < 0.0 || u + w > 1.0) continue;
        const double y = a.y + u * (b.y - a.y) + w * (c.y - a.y);
        if (!found || y > out->y) *out = hk_v3(x, y, z);
        found = 1;
    }
    return found;
}

static void add_root(const hk_Mesh *wick, hk_Vec3 p, hk_Vec3 *roots, int *count, double *dist)
{
    roots[(*count)++] = p;
    for (int i = 0; i < wick->vertex_count; i++) dist[i] = fmin(dist[i], hk_v3_dist(wick->positions[i], p));
}

/* Guide roots, symmetric about the face's plane x = 0: a ring round the crown (the whorl,
 * where neighbouring guides part in all directions: close guides keep the interpolation's
 * mixing zone small), then farthest-point samples of the wick's vertices on the +x side, each
 * with its mirror image on the wick. */
static int pick_roots(const Style *st, const hk_Mesh *wick, hk_Vec3 *roots)
{
    double *dist = malloc(sizeof(double) * (size_t)wick->vertex_count);
    if (!dist) return 0;
    for (int i = 0; i < wick->vertex_count; i++) dist[i] = INFINITY;
    int count = 0;
    for (int k = 0; k < st->crown_ring; k++) {
        const double a = 2.0 * HK_PI * (k + 0.5) / st->crown_ring;
        hk_Vec3 p;
        if (point_above(wick, st->crown.x + st->crown_radius * sin(a), st->crown.z + st->crown_radius * cos(a), &p))
            add_root(wick, p, roots, &count, dist);
    }
    while (count < st->guides && count < MAX_GUIDES - 1) {
        int best = -1;
        for (int i = 0; i < wick->vertex_count; i++)
            if (wick->positions[i].x >= 0.0 && (best < 0 || dist[i] > dist[best])) best = i;
        const hk_Vec3 p = wick->positions[best];
        add_root(wick, p, roots, &count, dist);
        if (p.x > 0.005) {
            hk_Vec3 q;
            hk_mesh_closest_point(wick, hk_v3(-p.x, p.y, p.z), &q, NULL);
            add_root(wick, q, roots, &count, dist);
        }
    }
    free(dist);
    return count;
}

/* Angle that turns a into b about the axis (a, b unit and perpendicular to the axis). */
static double turn(hk_Vec3 a, hk_Vec3 b, hk_Vec3 axis)
{
    return atan2(hk_v3_dot(hk_v3_cross(a, b), axis), hk_v3_dot(a, b));
}

/* Rotates v (perpendicular to the unit axis) by angle about it. */
static hk_Vec3 rotate(hk_Vec3 v, hk_Vec3 axis, double angle)
{
    return hk_v3_add(hk_v3_scale(v, cos(angle)), hk_v3_scale(hk_v3_cross(axis, v), sin(angle)));
}

/* Whether a straight fall from p stays `gap` away from the head over the next 8 cm (the
 * ears stand out below the cranium's widest point). */
static int clear_below(const hk_Mesh *head, hk_Vec3 p, hk_Vec3 down, double gap)
{
    for (double t = 0.005; t <= 0.08; t += 0.005) {
        hk_Vec3 m;
        if (head_distance(head, hk_v3_madd(p, down, t), &m) < gap) return 0;
    }
    return 1;
}

/* Walks one strand in its plane (normal b) from the root: the lift, then along the head at
 * the style's height until falling straight down (the plane's downward direction) clears
 * the head, then down to the tip height, steering round anything in the way. Records the
 * tangents; returns the steps, *fall_start the step where the fall began. */
static int walk(const Style *st, const hk_Mesh *head, hk_Vec3 p, hk_Vec3 n, hk_Vec3 b, double tip_y, hk_Vec3 *tangent,
                int *fall_start)
{
    hk_Vec3 down = hk_v3_madd(hk_v3(0, -1, 0), b, -hk_v3_dot(hk_v3(0, -1, 0), b));
    down = hk_v3_normalize(down);
    hk_Vec3 t = n;
    const int lift_steps = (int)lround(st->lift / DS);
    const double kmax = 1.0 / 0.012; /* tightest bend over the head */
    *fall_start = -1;
    int k = 0;
    tangent[k++] = t;
    while (k < MAX_STEPS) {
        double kappa;
        if (k <= lift_steps) {
            kappa = st->lift_angle / st->lift;
        } else {
            hk_Vec3 m;
            const double d = head_distance(head, p, &m);
            m = hk_v3_normalize(hk_v3_madd(m, b, -hk_v3_dot(m, b)));
            hk_Vec3 along = hk_v3_normalize(hk_v3_madd(t, m, -hk_v3_dot(t, m)));
            /* along the head, pulled back to the style's height */
            const hk_Vec3 hug = hk_v3_normalize(hk_v3_madd(along, m, (st->volume - d) / 0.004));
            int falling = hk_v3_dot(down, m) >= hk_v3_dot(hug, m);
            if (falling && *fall_start < 0) falling = clear_below(head, p, down, 0.6 * st->volume);
            if (falling && *fall_start < 0) *fall_start = k;
            const hk_Vec3 want = falling ? down : hug;
            kappa = turn(t, want, b) / (4.0 * DS);
            kappa = fmax(-kmax, fmin(kmax, kappa));
            if (p.y <= tip_y) break;
        }
        p = hk_v3_madd(p, t, DS);
        t = hk_v3_normalize(rotate(t, b, kappa * DS));
        tangent[k++] = t;
    }
    if (*fall_start < 0) *fall_start = k - 1;
    return k;
}

/* Pieces of constant curvature over steps [a, b) of the walk: each turns as the walk does. */
static void pieces(const hk_Vec3 *tangent, int a, int b, int count, hk_Vec3 axis, hk_PHelicoid *h)
{
    for (int j = 0; j < count; j++) {
        const int s0 = a + (int)lround((double)(b - a) * j / count);
        const int s1 = a + (int)lround((double)(b - a) * (j + 1) / count);
        const double length = fmax(s1 - s0, 1) * DS;
        const int i = h->piece_count++;
        h->k[i] = (hk_Helicoid){turn(tangent[s0], tangent[s1], axis) / length, 0.0, 0.0, 0.0};
        h->length[i] = length;
    }
}

static void design(const Style *st, const hk_Mesh *head, const hk_Mesh *wick, hk_Vec3 p, Guide *g)
{
    static hk_Vec3 tangent[MAX_STEPS + 1];
    hk_Vec3 n;
    hk_mesh_closest_point(wick, p, NULL, &n);
    /* downhill, and away from the crown's axis where the head is flat on top */
    hk_Vec3 away = hk_v3_normalize(hk_v3(p.x - st->crown.x, 0.0, p.z - st->crown.z));
    if (hk_v3_norm(away) < 0.5) away = hk_v3(0, 0, 1);
    g->azimuth = atan2(away.x, away.z);
    const hk_Vec3 v = hk_v3_madd(hk_v3(0, -1, 0), away, 0.3);
    const hk_Vec3 d = hk_v3_normalize(hk_v3_madd(v, n, -hk_v3_dot(v, n)));
    const hk_Vec3 b = hk_v3_cross(n, d);
    /* the fringe: strands combed forward that would fall in front of the face */
    double u = (fabs(p.x) - st->fringe_half_width) / st->fringe_blend;
    u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u * u * (3.0 - 2.0 * u));
    if (away.z <= 0.0) u = 1.0; /* behind the crown: combed back */
    const double tip_y = st->fringe_tip_y + (st->tip_y - st->fringe_tip_y) * u;
    int fall_start;
    const int steps = walk(st, head, p, n, b, tip_y, tangent, &fall_start);
    const int lift_steps = (int)lround(st->lift / DS);
    if (fall_start < lift_steps + 4) fall_start = lift_steps + 4;
    int end = steps - 1;
    if (end < fall_start + 6) end = fall_start + 6; /* at least 3 mm of fall (straight on) */
    if (end > MAX_STEPS) end = MAX_STEPS, fall_start = end - 6;
    for (int k = steps; k <= end && k <= MAX_STEPS; k++) tangent[k] = tangent[steps - 1];
    memset(&g->h, 0, sizeof g->h);
    g->h.root = p;
    g->h.frame = hk_m3_from_cols(n, d, b);
    pieces(tangent, 0, lift_steps, 1, b, &g->h);
    pieces(tangent, lift_steps, fall_start, st->hug, b, &g->h);
    pieces(tangent, fall_start, end, st->fall, b, &g->h);
    /* the ends turn under, towards the head (E_N's side after the bend) */
    const int last = g->h.piece_count - 1;
    g->h.k[last].kt += st->curl_under * fmin(1.0, g->h.length[last] / 0.02) / g->h.length[last];
}

/* Nearest approach to the head of the traced guide beyond its first centimetre. */
static double clearance(const hk_PHelicoid *h, const hk_Mesh *head, const hk_Waviness *w)
{
    const int n = hk_phelicoid_point_count(h, 0.002);
    hk_Vec3 *pts = malloc(sizeof(hk_Vec3) * (size_t)n);
    double worst = INFINITY, s = 0.0;
    if (!pts || hk_phelicoid_trace(h, 0.002, w, NULL, pts, NULL, NULL) != HK_OK) {
        free(pts);
        return -INFINITY;
    }
    for (int i = 1; i < n; i++) {
        s += hk_v3_dist(pts[i], pts[i - 1]);
        hk_Vec3 m;
        if (s > 0.01) worst = fmin(worst, head_distance(head, pts[i], &m));
    }
    free(pts);
    return worst;
}

static int write_style(const Style *st, const Guide *g, int count, const char *path, hk_Error *err)
{
    hk_OutFile of;
    if (hk_outfile_open(&of, path, err) != HK_OK) return 0;
    FILE *fp = of.fp;
    fprintf(fp,
            "# %s: %d guides on the wick of assets/head.obj for `hairkit helicoid interpolate`\n"
            "# (Piuze et al. 2011 §4.3, Fig. 11; docs/helicoids.md), made by tools/make_helicoid_styles.c.\n"
            "# Each guide leaves the scalp along its normal (Frame: E_T = the normal, E_N down the head,\n"
            "# away from the crown), lies down over the head about a centimetre above it and falls\n"
            "# where nothing is below: %d lift piece, %d over the head, %d falling%s, all in one plane.\n"
            "# The fringe stops above the brows. Waviness (eq. 4) makes the %s.\n",
            st->comment, count, 1, st->hug, st->fall, st->curl_under > 0.0 ? " (the ends turned under)" : "",
            st->wave_frequency > 200.0 ? "curls" : "waves");
    fprintf(fp, "Step 0.002\nWaviness %.4g %.4g %.4g\n", st->wave_amplitude, st->wave_frequency, st->wave_jitter);
    for (int i = 0; i < count; i++) {
        const hk_PHelicoid *h = &g[i].h;
        const hk_Vec3 t = hk_m3_col(&h->frame, 0), nn = hk_m3_col(&h->frame, 1);
        fprintf(fp,
                "\nStrand  # %.0f degrees from the front\nRoot  %.6f %.6f %.6f\n"
                "Frame %.6f %.6f %.6f   %.6f %.6f %.6f\n",
                g[i].azimuth * (180.0 / HK_PI), h->root.x, h->root.y, h->root.z, t.x, t.y, t.z, nn.x, nn.y, nn.z);
        for (int j = 0; j < h->piece_count; j++) fprintf(fp, "Piece %.6g 0 0 0 %.6g\n", h->k[j].kt, h->length[j]);
    }
    return hk_outfile_commit(&of, err) == HK_OK;
}

/* Checks an interpolated head of hair on a sample of its strands (one in `every`): those that go
 * more than 2 mm into the head beyond their first centimetre, and those that hang in front of
 * the face (below the brows, within its width, in front of the ears). Prints the first few. */
static int check(const char *head_path, const char *hair_path)
{
    hk_Error err;
    hk_Mesh head;
    hk_HairFile hair;
    if (hk_obj_load(head_path, &head, &err) != HK_OK) {
        fprintf(stderr, "make_helicoid_styles: %s\n", err.message);
        return 1;
    }
    if (hk_hair_load(hair_path, &hair, &err) != HK_OK) {
        fprintf(stderr, "make_helicoid_styles: %s\n", err.message);
        hk_mesh_free(&head);
        return 1;
    }
    const uint32_t every = hair.strand_count / 600 + 1;
    int inside = 0, face = 0, seen = 0, shown = 0;
    double worst = INFINITY;
    for (uint32_t s = 0; s < hair.strand_count; s += every) {
        seen++;
        int in = 0, fc = 0;
        double len = 0.0;
        const float *r = hair.points + 3 * (size_t)hair.first_point[s];
        for (uint32_t i = hair.first_point[s] + 1; i < hair.first_point[s + 1]; i++) {
            const float *q = hair.points + 3 * (size_t)i;
            const hk_Vec3 p = hk_v3(q[0], q[1], q[2]);
            len += hk_v3_dist(p, hk_v3(q[-3], q[-2], q[-1]));
            if (len < 0.01 || (i - hair.first_point[s]) % 3) continue;
            hk_Vec3 m;
            const double d = head_distance(&head, p, &m);
            const int f = p.y < 0.065 && p.y > -0.09 && fabs(p.x) < 0.06 && p.z > 0.06;
            if (((d < -0.002 && !in) || (f && !fc)) && shown++ < 8)
                printf("  strand %u (root %.3f %.3f %.3f) at %.3f %.3f %.3f, %.3f m from its root: %s\n", s, r[0], r[1],
                       r[2], p.x, p.y, p.z, len, f ? "in front of the face" : "inside the head");
            worst = fmin(worst, d);
            in |= d < -0.002, fc |= f;
        }
        inside += in, face += fc;
    }
    printf("%s: of %d strands, %d go into the head, %d hang in front of the face; deepest %.1f mm\n", hair_path, seen,
           inside, face, -1e3 * fmin(worst, 0.0));
    hk_hair_free(&hair);
    hk_mesh_free(&head);
    return 0;
}

int main(int argc, char **argv)
{
    if (argc == 4 && !strcmp(argv[1], "--check")) return check(argv[2], argv[3]);
    if (argc != 5) {
        fprintf(stderr, "usage: make_helicoid_styles HEAD.obj WICK.obj long|bob OUT.txt\n");
        return 2;
    }
    const Style *st = NULL;
    for (size_t i = 0; i < sizeof STYLES / sizeof STYLES[0]; i++)
        if (!strcmp(argv[3], STYLES[i].name)) st = &STYLES[i];
    if (!st) {
        fprintf(stderr, "make_helicoid_styles: unknown style '%s' (long, bob)\n", argv[3]);
        return 2;
    }
    hk_Error err;
    hk_Mesh head, wick;
    if (hk_obj_load(argv[1], &head, &err) != HK_OK) {
        fprintf(stderr, "make_helicoid_styles: %s\n", err.message);
        return 1;
    }
    if (hk_obj_load(argv[2], &wick, &err) != HK_OK) {
        fprintf(stderr, "make_helicoid_styles: %s\n", err.message);
        hk_mesh_free(&head);
        return 1;
    }
    static Guide g[MAX_GUIDES];
    hk_Vec3 roots[MAX_GUIDES];
    const int count = pick_roots(st, &wick, roots);
    if (count < 1) {
        fprintf(stderr, "make_helicoid_styles: out of memory\n");
        hk_mesh_free(&head), hk_mesh_free(&wick);
        return 1;
    }
    const hk_Waviness w = {st->wave_amplitude, st->wave_frequency, 0.0};
    double worst = INFINITY;
    for (int i = 0; i < count; i++) {
        design(st, &head, &wick, roots[i], &g[i]);
        const double c = clearance(&g[i].h, &head, &w), c0 = clearance(&g[i].h, &head, NULL);
        worst = fmin(worst, c);
        printf("guide %2d: azimuth %5.0f, %2d pieces, length %.3f m, clearance %.1f mm (%.1f mm without waves)\n",
               i + 1, g[i].azimuth * (180.0 / HK_PI), g[i].h.piece_count, hk_phelicoid_length(&g[i].h), 1e3 * c,
               1e3 * c0);
    }
    printf("closest approach to the head: %.1f mm\n", 1e3 * worst);
    const int ok = write_style(st, g, count, argv[4], &err);
    if (!ok) fprintf(stderr, "make_helicoid_styles: %s\n", err.message);
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
    return ok ? 0 : 1;
}
