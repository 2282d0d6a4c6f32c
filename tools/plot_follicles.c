/* Follicles sampled on the head's wick, seen from above and from the side, in the
 * manner of the helicoid paper's Fig. 9 (interior follicles green, fixed contour particles
 * red), for docs/follicle-sampling.md (scripts/make-doc-images.sh).
 * Usage: plot_follicles HEAD.obj WICK.obj SPACING OUT.png */
#include <stdio.h>
#include <stdlib.h>

#include "hairkit/canvas.h"
#include "hairkit/follicle_sampling.h"

typedef struct View {
    double x0, y0, scale; /* pixel = (x0 + scale u, y0 - scale v) */
    hk_Vec3 u, v, eye;    /* screen axes and the direction towards the viewer */
} View;

static void dot(hk_Canvas *c, const View *w, hk_Vec3 p, double r, hk_Vec3 color, double opacity)
{
    hk_canvas_disc(c, w->x0 + w->scale * hk_v3_dot(p, w->u), w->y0 - w->scale * hk_v3_dot(p, w->v), r, color, opacity);
}

int main(int argc, char **argv)
{
    if (argc != 5) {
        fprintf(stderr, "usage: plot_follicles HEAD.obj WICK.obj SPACING OUT.png\n");
        return 2;
    }
    hk_Error err;
    hk_Mesh head, wick;
    if (hk_obj_load(argv[1], &head, &err) != HK_OK) goto fail_early;
    if (hk_obj_load(argv[2], &wick, &err) != HK_OK) {
        hk_mesh_free(&head);
        goto fail_early;
    }
    hk_WickSamplingDef def = hk_default_wick_sampling_def();
    def.spacing = strtod(argv[3], NULL);
    def.include_contour = 0;
    hk_FollicleSamples free_part, all;
    hk_Canvas c = {0, 0, NULL};
    if (hk_wick_follicles(&head, &wick, &def, &free_part, &err) != HK_OK) goto fail;
    def.include_contour = 1;
    if (hk_wick_follicles(&head, &wick, &def, &all, &err) != HK_OK) {
        hk_follicle_samples_free(&free_part);
        goto fail;
    }
    if (hk_canvas_alloc(1000, 500, hk_v3(1, 1, 1), &c, &err) != HK_OK) goto fail_samples;
    /* left: from above (x right, face +z down); right: from the side (z right, y up) */
    const View views[2] = {
        {250, 250, 1500, {1, 0, 0}, {0, 0, -1}, {0, 1, 0}},
        {740, 330, 1500, {0, 0, 1}, {0, 1, 0}, {1, 0, 0}},
    };
    for (int k = 0; k < 2; k++) {
        const View *w = &views[k];
        for (int i = 0; i < head.vertex_count; i++)
            if (hk_v3_dot(head.normals[i], w->eye) > 0.0)
                dot(&c, w, head.positions[i], 1.0, hk_v3(0.6, 0.6, 0.65), 0.5);
        for (int i = 0; i < all.count; i++) {
            if (hk_v3_dot(all.normals[i], w->eye) < -0.1) continue;
            const int contour = i >= free_part.count;
            dot(&c, w, all.points[i], contour ? 3.0 : 2.6, contour ? hk_v3(0.85, 0.1, 0.1) : hk_v3(0.1, 0.6, 0.15),
                1.0);
        }
    }
    if (hk_canvas_write_png(&c, argv[4], &err) != HK_OK) goto fail_samples;
    printf("plot_follicles: %d follicles (%d on the contour) at %g m\n", all.count, all.count - free_part.count,
           def.spacing);
    hk_canvas_free(&c);
    hk_follicle_samples_free(&free_part);
    hk_follicle_samples_free(&all);
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
    return 0;
fail_samples:
    hk_canvas_free(&c);
    hk_follicle_samples_free(&free_part);
    hk_follicle_samples_free(&all);
fail:
    hk_mesh_free(&head);
    hk_mesh_free(&wick);
fail_early:
    fprintf(stderr, "plot_follicles: %s\n", err.message);
    return 1;
}
