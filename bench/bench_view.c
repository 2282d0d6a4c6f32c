/* Benchmark of the viewer (`hairkit view`, docs/viewer.md), headless in a hidden window:
 * frames per second of the default head with and without shadows, and of
 * examples/guides200 simulated live (one step of the guides, the head regrown and
 * uploaded every frame), with the OpenGL renderer named. Needs a display (xvfb-run -a
 * gives one); without it, or without the viewer, it says so and measures nothing. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench.h"
#ifdef HK_HAVE_VIEWER
#include "viewer/viewer.h"
#endif

#ifdef HK_HAVE_VIEWER
typedef struct Case {
    const char *example, *label;
    int shadows, simulate, guides_only;
} Case;

/* One headless run of `frames` frames; 0 on success. */
static int run_case(FILE *out, const hk_BenchOptions *options, const Case *c, int width, int height, int frames,
                    char renderer[128])
{
    hk_Scene sc;
    hk_HairFile hair;
    memset(&hair, 0, sizeof hair);
    hk_Error err;
    if (hk_bench_scene_load(options, c->example, "view", HK_SCENE_ALL, &sc)) return 1;
    hk_ViewerInput in;
    memset(&in, 0, sizeof in);
    int rc = 1;
    if (!c->simulate) {
        hk_SceneHairReport report;
        if (hk_scene_hair(&sc, NULL, &hair, &report, &err) != HK_OK) {
            fprintf(stderr, "bench view: %s\n", err.message);
            goto done;
        }
        in.guide_count = report.guides;
    }
    in.hair = &hair;
    in.head = &sc.head;
    in.visuality = sc.visuality;
    in.render = hk_default_render_def();
    in.render.width = width, in.render.height = height, in.render.shadows = c->shadows;
    in.scene = &sc;
    in.simulate = c->simulate;
    in.live = hk_default_live_sim_def();
    in.live.guides_only = c->guides_only;
    in.guides_only = c->guides_only;
    in.frames = frames;
    in.quiet = 1;
    hk_ViewerFigures f;
    memset(&f, 0, sizeof f);
    if (hk_viewer_run_measured(&in, &f) != 0) goto done;
    fprintf(out, "  %-44s %9ld %10ld %12.2f %10.3f %8.2f\n", c->label, f.strands, f.points, f.first_seconds,
            f.frames_per_second, f.simulated);
    memcpy(renderer, f.renderer, sizeof f.renderer);
    rc = 0;
done:
    hk_hair_free(&hair);
    hk_scene_free(&sc);
    return rc;
}
#endif

int hk_bench_view(FILE *out, const hk_BenchOptions *options)
{
#ifndef HK_HAVE_VIEWER
    (void)options;
    fprintf(out, "view: skipped: hairkit was built without the viewer (HK_VIEWER off)\n\n");
    return 0;
#else
    if (!getenv("DISPLAY") && !getenv("WAYLAND_DISPLAY")) {
        fprintf(out, "view: skipped: no display (run it as 'xvfb-run -a hairkit bench view')\n\n");
        return 0;
    }
    const int width = options->quick ? 160 : 960, height = options->quick ? 120 : 720;
    /* the first frame (uploads, light maps, the first step) apart; the frames after it
     * redraw everything but the light's maps of a still head */
    const int frames = options->quick ? 2 : 4, live_frames = options->quick ? 3 : 31;
    static const Case cases[] = {
        {"default", "default head, shadows", 1, 0, 0},
        {"default", "default head, no shadows", 0, 0, 0},
        {"guides200", "guides200 live, guides only (no interpolation)", 1, 1, 1},
        {"guides200", "guides200 live, every strand regrown", 1, 1, 0},
    };
    fprintf(out, "view: headless, %dx%d, hidden window; frames/s after the first frame\n", width, height);
    fprintf(out, "  %-44s %9s %10s %12s %10s %8s\n", "scene", "strands", "points", "first (s)", "frames/s", "sim (s)");
    char renderer[128] = "";
    for (size_t k = 0; k < sizeof cases / sizeof *cases; k++) {
        const int n = cases[k].simulate && cases[k].guides_only ? live_frames : frames;
        if (run_case(out, options, &cases[k], width, height, n, renderer)) return 1;
        fflush(out);
    }
    fprintf(out, "  GL renderer: %s\n", renderer);
    fprintf(out, "  the live runs settle the guides first (not counted); sim: simulated seconds shown\n\n");
    return 0;
#endif
}
