/* The CPU hair renderer (Lansink 2010 §4.1.5-4.1.6 done on the CPU): a perspective
 * camera, the head rasterised with a z-buffer and Lambert shading, every strand drawn
 * as an anti-aliased curve whose width is the hair's projected diameter (sub-pixel
 * widths become opacity), exact transparency by sorting each pixel's fragments by
 * depth (an A-buffer, per tile of 32 x 32 pixels), Kajiya-Kay or Marschner shading,
 * and self-shadowing by deep opacity maps (Yuksel & Keyser 2008) plus a shadow map of
 * the head. Tiles run in parallel; the picture is bit-identical whatever the thread
 * count. */
#ifndef HAIRKIT_RENDER_H
#define HAIRKIT_RENDER_H

#include "hairkit/canvas.h"
#include "hairkit/export.h"
#include "hairkit/hairfile.h"
#include "hairkit/io.h"
#include "hairkit/mesh.h"

#ifdef __cplusplus
extern "C" {
#endif

#define HK_MAX_OPACITY_LAYERS 16

typedef enum hk_Shading { HK_SHADING_KAJIYA_KAY = 0, HK_SHADING_MARSCHNER = 1 } hk_Shading;

/* Light scattered between fibres: none (single scattering, the light in shadow floored
 * at scatter_floor, as the thesis), or the dual scattering approximation (Zinke et al.
 * 2008; docs/rendering.md), the default. */
typedef enum hk_Scattering { HK_SCATTERING_SINGLE = 0, HK_SCATTERING_DUAL = 1 } hk_Scattering;

typedef struct hk_RenderDef {
    int width, height;        /* pixels of the picture (default 1200 x 900) */
    int threads;              /* 0: OpenMP's default (all cores) */
    int shadows;              /* deep opacity maps and the head's shadow map (default on) */
    hk_Shading shading;       /* default Kajiya-Kay */
    hk_Scattering scattering; /* default HK_SCATTERING_DUAL */
    /* Camera: it looks at the centre of the scene's bounding box from the direction
     * given by azimuth (degrees about +y, 0 = in front of the face, +z; positive turns
     * towards +x) and elevation (degrees above the horizontal), at the distance where
     * everything fits the picture with a small margin. Default: three-quarter front. */
    double azimuth_deg, elevation_deg;
    double fov_deg; /* vertical field of view (default 30) */
    /* A fixed camera instead of the fit (for animations, so that the view does not follow
     * the hair): it looks at camera_target from camera_distance along the direction
     * above. camera_distance <= 0 (default): fit every picture. */
    hk_Vec3 camera_target;
    double camera_distance;
    /* One directional key light, from the direction azimuth/elevation as above. */
    double light_azimuth_deg, light_elevation_deg;
    double light_intensity;                    /* default 1 */
    double ambient_intensity;                  /* multiplies AmbientColor (thesis shader: 0.2); with dual
                                                  scattering the hair also reflects an ambient light of
                                                  twice this (the skin's) with its DiffuseColor */
    int shadow_map_size;                       /* texels per side of the light's maps; 0 (default): from
                                                  the picture's size (hk_render_shadow_map_texels) */
    int opacity_layers;                        /* K layers of the deep opacity map (thesis: 4) */
    double layer_size;                         /* depth of the first layer (m); layer k is 2^k times as deep
                                                  (<= 0: 2 mm) */
    double scatter_floor;                      /* single scattering only: light that reaches the deepest
                                                  hair, as a fraction, a stand-in for multiple scattering
                                                  (thesis: 0.25); dual scattering computes that light */
    double hair_thickness;                     /* strand diameter in scene units; <= 0: from the file */
    double strand_variation;                   /* each strand's brightness varies by up to this fraction
                                                  (default 0.15) */
    int strand_lod;                            /* 1 (default): where strands are much thinner than a pixel,
                                                  one in k of them drawn k times as wide
                                                  (hk_render_strand_stride; docs/rendering.md, "Speed");
                                                  0: every strand */
    hk_Vec3 background_top, background_bottom; /* vertical gradient, linear RGB */
    hk_Vec3 skin;                              /* diffuse colour of the head, linear RGB */
} hk_RenderDef;

HK_API hk_RenderDef hk_default_render_def(void);

/* The texels per side of the light's maps that options draws with: shadow_map_size
 * when it is set, else the picture's: 512 at 1200 x 900 and above, and below that
 * 512 times the larger of width / 1200 and height / 900, rounded up to a multiple of
 * 32, at least 64 (a texel stays about as wide in pixels of the picture, so that a
 * thumbnail does not pay for a full picture's shadows; docs/rendering.md, "Speed"). */
HK_API int hk_render_shadow_map_texels(const hk_RenderDef *options);

/* The level of detail a picture is drawn with (stochastic simplification, Cook,
 * Halstead, Planck and Ryu, "Stochastic Simplification of Aggregate Detail", SIGGRAPH
 * 2007): k >= 1, one strand in k drawn, each k times as wide, so that a pixel's hair
 * covers as much of it on average. k = 1 unless options->strand_lod is set and a
 * strand's projected width at the camera's target is under 1/4 pixel: then the
 * largest k that keeps it under 1/4 (k = 1 for the default head at 1200 x 900), at most
 * 64 and at most strands / 5000. `hair` and `head` as for hk_render. Returns 0 and sets
 * err on bad options or non-finite points. */
HK_API int hk_render_strand_stride(const hk_HairFile *hair, const hk_Mesh *head, const hk_RenderDef *options,
                                   hk_Error *err);

typedef struct hk_RenderStats {
    long long hair_fragments;  /* camera fragments kept (in front of the head) */
    long long light_fragments; /* fragments drawn into the deep opacity map */
    int max_depth_complexity;  /* most fragments in one pixel */
    int strand_stride;         /* the level of detail: one strand in this many drawn */
    double seconds_light;      /* the light's maps */
    double seconds_camera;     /* framing and projecting */
    double seconds_hair;       /* head and hair, tile by tile, with the shading */
} hk_RenderStats;

/* Renders `hair` (the strands of a cyHair file; may have no strands) over `head` (may
 * be NULL) with the colours of `visuality` into `out` (linear RGB, created here; free
 * with hk_canvas_free). options NULL: hk_default_render_def(); visuality NULL:
 * hk_default_visuality(); stats may be NULL. */
HK_API hk_Status hk_render(const hk_HairFile *hair, const hk_Mesh *head, const hk_Visuality *visuality,
                           const hk_RenderDef *options, hk_Canvas *out, hk_RenderStats *stats, hk_Error *err);

/* A renderer that keeps its working memory from one picture to the next: the
 * projected points, the tile bins, the light's maps, the vertex colours and the
 * fragment buffers (several hundred MB on a full head), for the frames of an
 * animation. hk_render is create, draw, destroy. A renderer draws one picture at a
 * time (its draws may not overlap; each draw runs in parallel itself). */
typedef struct hk_Renderer hk_Renderer;

HK_API hk_Status hk_renderer_create(hk_Renderer **out, hk_Error *err);
HK_API void hk_renderer_destroy(hk_Renderer *renderer);

/* Renders as hk_render does, the same bytes, into the renderer's picture (options
 * NULL: hk_default_render_def(); visuality NULL: hk_default_visuality()). */
HK_API hk_Status hk_renderer_draw(hk_Renderer *renderer, const hk_HairFile *hair, const hk_Mesh *head,
                                  const hk_Visuality *visuality, const hk_RenderDef *options, hk_RenderStats *stats,
                                  hk_Error *err);

/* The last picture drawn (linear RGB): valid until the next draw or destroy, empty
 * (0 x 0) after a failed draw. */
HK_API const hk_Canvas *hk_renderer_picture(const hk_Renderer *renderer);

/* The camera hk_render would fit to this hair and head with these options: its target
 * and distance (for a fixed camera over the frames of an animation). */
HK_API hk_Status hk_render_fit_camera(const hk_HairFile *hair, const hk_Mesh *head, const hk_RenderDef *options,
                                      hk_Vec3 *target, double *distance, hk_Error *err);

/* Writes a linear-RGB picture as an 8-bit sRGB PNG (atomically). */
HK_API hk_Status hk_render_write_png(const hk_Canvas *image, const char *path, hk_Error *err);

#ifdef __cplusplus
}
#endif

#endif
