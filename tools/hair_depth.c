/* How far the points of a .hair file lie inside the body shapes of a collision file
 * (docs/grooming.md, "Keeping hair outside the body"): the guides (the first strands of
 * a groom, their count read from the file's "guides=N" information), the other
 * strands and the roots (which sit on the scalp, between the wick's vertices possibly a
 * little inside the true shape) are reported apart. Depth is the thesis's dent (§4.1.2.1) of the true shapes,
 * without their envelopes; styling shapes are not body.
 * Frames of `hairkit simulate` are in world space: with --motion NAME --fps F (the
 * simulation's scripted motion, default amplitude and frequency) frame_kkkk.hair and
 * guides_kkkk.hair are taken back into head space, x = R^T (p - T), with the head's
 * pose at t = k / F.
 * --list MM prints every non-root point more than MM millimetres inside: file, strand,
 * point, the shape it is deepest in, its depth and how far it moved in head space since
 * the same point of the file before (frames given in order: its speed times 1/F), to
 * find which guides go deep, where and how fast they arrive.
 * Usage: hair_depth COLLISION.txt [--motion NAME --fps F] [--list MM] FILE.hair... */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/collide.h"
#include "hairkit/hairfile.h"
#include "hairkit/io.h"
#include "hairkit/motion.h"

typedef struct Tally {
    long points, over1, over2;
    double deepest;
} Tally;

static void add(Tally *t, double depth)
{
    t->points++;
    t->over1 += depth > 0.001;
    t->over2 += depth > 0.002;
    if (depth > t->deepest) t->deepest = depth;
}

static void print(const char *what, const Tally *t)
{
    printf("  %-8s %9ld points: %.4f %% > 1 mm, %.4f %% > 2 mm, deepest %.2f mm\n", what, t->points,
           t->points ? 100.0 * t->over1 / t->points : 0.0, t->points ? 100.0 * t->over2 / t->points : 0.0,
           1e3 * t->deepest);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: hair_depth COLLISION.txt [--motion NAME --fps F] [--list MM] FILE.hair...\n");
        return 2;
    }
    hk_Error err;
    hk_CollisionSet collision;
    if (hk_collision_load(argv[1], &collision, &err) != HK_OK) {
        fprintf(stderr, "hair_depth: %s\n", err.message);
        return 1;
    }
    hk_Shape *shapes = collision.shapes;
    int body = 0;
    for (int i = 0; i < collision.count; i++)
        if (!shapes[i].styling) shapes[body++] = shapes[i];
    int first = 2;
    hk_HeadMotion *motion = NULL;
    double fps = 30.0;
    if (argc > 6 && !strcmp(argv[2], "--motion") && !strcmp(argv[4], "--fps")) {
        fps = strtod(argv[5], NULL);
        /* the defaults of `hairkit simulate --motion` (cli/motion_options.c): 25 degrees,
         * or 0.03 m for the translations */
        const double amplitude = !strcmp(argv[3], "sway") || !strcmp(argv[3], "jump") ? 0.03 : 25.0;
        if (!(fps > 0.0) ||
            hk_head_motion_scripted(argv[3], amplitude, 1.0, hk_default_head_pivot(), &motion, &err) != HK_OK) {
            fprintf(stderr, "hair_depth: bad --motion or --fps\n");
            return 2;
        }
        first = 6;
    }
    double list = -1.0; /* metres; < 0: no listing */
    if (argc > first + 2 && !strcmp(argv[first], "--list")) {
        list = 1e-3 * strtod(argv[first + 1], NULL);
        first += 2;
    }
    float *previous = NULL; /* head-space points of the file before (same layout) */
    uint32_t previous_count = 0;
    Tally all_guides = {0, 0, 0, 0.0}, all_strands = {0, 0, 0, 0.0}, all_roots = {0, 0, 0, 0.0};
    for (int f = first; f < argc; f++) {
        hk_HairFile h;
        if (hk_hair_load(argv[f], &h, &err) != HK_OK) {
            fprintf(stderr, "hair_depth: %s\n", err.message);
            continue;
        }
        char info[HK_HAIR_INFO_SIZE + 1];
        memcpy(info, h.info, HK_HAIR_INFO_SIZE);
        info[HK_HAIR_INFO_SIZE] = '\0';
        const char *g = strstr(info, "guides=");
        const long guides = g ? strtol(g + 7, NULL, 10) : 0;
        hk_RigidState head = hk_rigid_identity();
        /* frame_kkkk.hair or guides_kkkk.hair: frame k, at t = k / fps */
        const char *base = strrchr(argv[f], '/') ? strrchr(argv[f], '/') + 1 : argv[f];
        const char *k = !strncmp(base, "frame_", 6) || !strncmp(base, "guides_", 7) ? strchr(base, '_') : NULL;
        if (motion && k) hk_head_motion_eval(motion, strtol(k + 1, NULL, 10) / fps, &head);
        Tally tg = {0, 0, 0, 0.0}, ts = {0, 0, 0, 0.0}, tr = {0, 0, 0, 0.0};
        const int moved = previous && previous_count == h.point_count;
        for (uint32_t s = 0; s < h.strand_count; s++)
            for (uint32_t p = h.first_point[s]; p < h.first_point[s + 1]; p++) {
                float *q = h.points + 3 * (size_t)p;
                const hk_Vec3 x = hk_m3_tmul_v3(&head.rot, hk_v3_sub(hk_v3(q[0], q[1], q[2]), head.trans));
                double d = 0.0;
                const int shape = hk_collision_deepest(shapes, body, 0.0, x, &d);
                if (list >= 0.0 && d > list && p != h.first_point[s]) {
                    const float *b = moved ? previous + 3 * (size_t)p : NULL;
                    printf("%s strand %u point %u shape %d depth %.2f mm moved %.2f mm\n", argv[f], s,
                           p - h.first_point[s], shape, 1e3 * d,
                           b ? 1e3 * hk_v3_dist(x, hk_v3(b[0], b[1], b[2])) : -1.0);
                }
                q[0] = (float)x.x, q[1] = (float)x.y, q[2] = (float)x.z; /* for the next file's "moved" */
                if (p == h.first_point[s]) {
                    add(&tr, d);
                    add(&all_roots, d);
                    continue;
                }
                add((long)s < guides ? &tg : &ts, d);
                add((long)s < guides ? &all_guides : &all_strands, d);
            }
        printf("%s\n", argv[f]);
        print("roots", &tr);
        print("guides", &tg);
        print("strands", &ts);
        hk_free(previous);
        previous = h.points; /* head space now; kept, the rest freed */
        previous_count = h.point_count;
        h.points = NULL;
        hk_hair_free(&h);
    }
    if (argc > first + 1) {
        printf("all files\n");
        print("roots", &all_roots);
        print("guides", &all_guides);
        print("strands", &all_strands);
    }
    hk_free(previous);
    hk_collision_free(&collision);
    hk_head_motion_destroy(motion);
    return 0;
}
