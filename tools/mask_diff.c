/* mask_diff A.png B.png: how much two pictures of hairkit's renderers differ in what they
 * cover. A pixel is foreground when it differs from the renderers' background gradient
 * (hk_default_render_def: background_top to background_bottom, row by row) by more than
 * THRESHOLD 8-bit levels in some channel (default 12). Prints the foreground fraction of
 * each picture and the fraction of pixels that are foreground in one only
 * (tests/cli/view.sh: the viewer frames the same hair as the CPU renderer).
 * mask_diff --box W,H A.png B.png: the pixels whose bytes differ at all, inside the
 * picture's top left W x H pixels and outside (view.sh: the text overlay's corner). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/image.h"
#include "hairkit/render.h"

static double encode(double c)
{
    c = c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c;
    return 255.0 * (c <= 0.0031308 ? 12.92 * c : 1.055 * pow(c, 1.0 / 2.4) - 0.055);
}

/* Pixels differing in any byte, in the top left box and outside it. */
static void box_diff(const uint8_t *a, const uint8_t *b, int w, int h, int box_w, int box_h)
{
    long inside = 0, outside = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const size_t at = 3 * ((size_t)y * (size_t)w + (size_t)x);
            if (a[at] == b[at] && a[at + 1] == b[at + 1] && a[at + 2] == b[at + 2]) continue;
            if (x < box_w && y < box_h)
                inside++;
            else
                outside++;
        }
    printf("inside %ld outside %ld\n", inside, outside);
}

int main(int argc, char **argv)
{
    int box_w = -1, box_h = -1;
    if (argc > 2 && !strcmp(argv[1], "--box")) {
        if (sscanf(argv[2], "%d,%d", &box_w, &box_h) != 2 || box_w < 0 || box_h < 0) {
            fprintf(stderr, "mask_diff: --box expects W,H in pixels, got '%s'\n", argv[2]);
            return 2;
        }
        argv += 2, argc -= 2;
    }
    if (argc < 3) {
        fprintf(stderr, "usage: mask_diff [--box W,H] A.png B.png [THRESHOLD]\n");
        return 2;
    }
    const double threshold = argc > 3 ? atof(argv[3]) : 12.0;
    int w[2], h[2];
    uint8_t *rgb[2];
    hk_Error err;
    for (int k = 0; k < 2; k++)
        if (hk_png_read_rgb8(argv[1 + k], &w[k], &h[k], &rgb[k], &err) != HK_OK) {
            fprintf(stderr, "mask_diff: %s\n", err.message);
            return 1;
        }
    if (w[0] != w[1] || h[0] != h[1]) {
        fprintf(stderr, "mask_diff: sizes differ: %dx%d and %dx%d\n", w[0], h[0], w[1], h[1]);
        return 1;
    }
    if (box_w >= 0) {
        box_diff(rgb[0], rgb[1], w[0], h[0], box_w, box_h);
        hk_free(rgb[0]);
        hk_free(rgb[1]);
        return 0;
    }
    const hk_RenderDef o = hk_default_render_def();
    long cover[2] = {0, 0}, differ = 0;
    for (int y = 0; y < h[0]; y++) {
        const double f = h[0] > 1 ? (double)y / (h[0] - 1) : 0.0;
        const hk_Vec3 bg = hk_v3_add(hk_v3_scale(o.background_top, 1.0 - f), hk_v3_scale(o.background_bottom, f));
        const double b[3] = {encode(bg.x), encode(bg.y), encode(bg.z)};
        for (int x = 0; x < w[0]; x++) {
            int fg[2];
            for (int k = 0; k < 2; k++) {
                const uint8_t *p = rgb[k] + 3 * ((size_t)y * (size_t)w[0] + (size_t)x);
                fg[k] = 0;
                for (int c = 0; c < 3; c++)
                    if (fabs(p[c] - b[c]) > threshold) fg[k] = 1;
                cover[k] += fg[k];
            }
            differ += fg[0] != fg[1];
        }
    }
    const double n = (double)w[0] * h[0];
    printf("cover %.4f %.4f differ %.4f\n", cover[0] / n, cover[1] / n, differ / n);
    hk_free(rgb[0]);
    hk_free(rgb[1]);
    return 0;
}
