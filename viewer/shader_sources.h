/* The default shaders of assets/shaders, built into the program (cmake/embed_shaders.cmake). */
#ifndef HK_VIEWER_SHADER_SOURCES_H
#define HK_VIEWER_SHADER_SOURCES_H

typedef struct hk_ShaderSource {
    const char *path; /* as in the source tree, for messages */
    const char *name; /* file name: "hair.frag" */
    const char *text;
} hk_ShaderSource;

extern const hk_ShaderSource hk_viewer_shaders[]; /* ends with a NULL path */

#endif
