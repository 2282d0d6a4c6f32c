/* The light's maps (thesis 004 §4.1.6): the head's depth, the depth where the hair
 * begins (z0) and the opacity of the hair accumulated to the end of four layers behind
 * it (as deep opacity maps, Yuksel & Keyser 2008), seen along a directional light. */
#ifndef HK_VIEWER_GL_LIGHT_MAPS_H
#define HK_VIEWER_GL_LIGHT_MAPS_H

#include <epoxy/gl.h>

#include "viewer/gl_geometry.h"
#include "viewer/gl_math.h"

typedef struct hk_GlLightMaps {
    int size;
    GLuint head_depth, hair_depth, opacity; /* textures */
    GLuint fbo_head, fbo_hair, fbo_opacity;
    GLuint depth_program, opacity_program;
    hk_Mat4 matrix;     /* world -> [0, 1]^3 (texture coordinates and depth) */
    float layer_end[4]; /* in depth units */
} hk_GlLightMaps;

int hk_gl_light_maps_create(hk_GlLightMaps *m, int size);
/* Draws the maps for light direction `light` (unit, towards the light) around the
 * sphere (centre, radius) holding the scene; hair of diameter `thickness`; layers of
 * `layer_size` metres, each twice as deep as the one before. */
void hk_gl_light_maps_draw(hk_GlLightMaps *m, const hk_GlHair *hair, const hk_GlHead *head, hk_Vec3 light,
                           hk_Vec3 centre, double radius, double thickness, double layer_size, int guides_only);
/* Binds the maps to texture units 1 (HairDepth), 2 (OpacityMap), 3 (HeadDepth) and sets
 * those uniforms, LightMatrix and LayerEnd of `program` (in use). */
void hk_gl_light_maps_bind(const hk_GlLightMaps *m, GLuint program);
void hk_gl_light_maps_destroy(hk_GlLightMaps *m);

#endif
