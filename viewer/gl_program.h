/* GLSL programs from files or from the built-in shaders, with the compiler's messages
 * turned into FILE:LINE: lines. */
#ifndef HK_VIEWER_GL_PROGRAM_H
#define HK_VIEWER_GL_PROGRAM_H

#include <epoxy/gl.h>

/* The program of a vertex and a fragment shader: each read from `path` when it is not
 * NULL, else the built-in assets/shaders/`name`. 0 on failure, after printing every
 * message of the compiler or the linker to stderr as "hairkit view: FILE:LINE: ...". */
GLuint hk_gl_program(const char *vert_path, const char *vert_name, const char *frag_path, const char *frag_name);

/* Uniform setters that ignore uniforms a (replaced) shader does not declare. */
void hk_gl_uniform1i(GLuint program, const char *name, int v);
void hk_gl_uniform1f(GLuint program, const char *name, double v);
void hk_gl_uniform3f(GLuint program, const char *name, double x, double y, double z);
void hk_gl_uniform4f(GLuint program, const char *name, double x, double y, double z, double w);
void hk_gl_uniform_mat4(GLuint program, const char *name, const float *m);

#endif
