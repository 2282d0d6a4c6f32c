/* Side and front views of the strands of a .hair file over the collision shapes, for
 * the documentation (scripts/make-doc-images.sh) and for checking a groom by eye before
 * the renderer. Usage: plot_hair FILE.hair OUT.png [COLLISION.txt] [MAX_STRANDS]
 * MAX_STRANDS (default 401, the guides of hairkit's head) plots the first strands only:
 * a groom stores its guides first. Strands are coloured by the height of their root. */
#include <stdio.h>
#include <stdlib.h>

#include "hairkit/canvas.h"
#include "hairkit/hairfile.h"
#include "hairkit/io.h"

int main(int argc, char **argv)
{
    if (argc < 3 || argc > 5) {
        fprintf(stderr, "usage: plot_hair FILE.hair OUT.png [COLLISION.txt] [MAX_STRANDS]\n");
        return 2;
    }
    hk_Error err;
    hk_HairFile hair;
    hk_CollisionSet collision = {0};
    if (hk_hair_load(argv[1], &hair, &err) != HK_OK) goto fail_early;
    if (argc >= 4 && hk_collision_load(argv[3], &collision, &err) != HK_OK) goto fail;
    long max = argc >= 5 ? strtol(argv[4], NULL, 10) : 401;
    int n = (int)(max > 0 && max < (long)hair.strand_count ? max : (long)hair.strand_count);
    hk_PlotStrand *plot = hk_alloc_array((size_t)n, sizeof *plot, &err);
    hk_Vec3 *points = hk_alloc_array(n ? hair.first_point[n] : 1, sizeof *points, &err);
    if (!plot || !points) {
        hk_free(plot);
        hk_free(points);
        goto fail;
    }
    double ylo = 1e300, yhi = -1e300;
    for (int s = 0; s < n; s++) {
        double y = hair.points[3 * (size_t)hair.first_point[s] + 1];
        ylo = y < ylo ? y : ylo, yhi = y > yhi ? y : yhi;
    }
    for (int s = 0; s < n; s++) {
        const uint32_t a = hair.first_point[s];
        for (uint32_t p = a; p < hair.first_point[s + 1]; p++)
            points[p] =
                hk_v3(hair.points[3 * (size_t)p], hair.points[3 * (size_t)p + 1], hair.points[3 * (size_t)p + 2]);
        double t = yhi > ylo ? (hair.points[3 * (size_t)a + 1] - ylo) / (yhi - ylo) : 1.0;
        plot[s].points = points + a;
        plot[s].count = (int)hk_hair_strand_points(&hair, (uint32_t)s);
        plot[s].color = hk_v3(0.55 - 0.35 * t, 0.30 - 0.10 * t, 0.10 + 0.55 * t); /* low: brown, top: blue */
    }
    hk_Status st = hk_plot_strands_png(argv[2], 800, 400, plot, n, collision.shapes, collision.count, 0.0, &err);
    hk_free(plot);
    hk_free(points);
    if (st != HK_OK) goto fail;
    hk_hair_free(&hair);
    hk_collision_free(&collision);
    return 0;
fail:
    hk_hair_free(&hair);
    hk_collision_free(&collision);
fail_early:
    fprintf(stderr, "plot_hair: %s\n", err.message);
    return 1;
}
