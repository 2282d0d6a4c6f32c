/* GLSL programs (gl_program.h). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "viewer/gl_program.h"
#include "viewer/shader_sources.h"

/* The text of a shader file (malloc'd), or NULL with a message. */
static char *read_text(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "hairkit view: %s: cannot be read\n", path);
        return NULL;
    }
    size_t cap = 4096, n = 0;
    char *text = malloc(cap);
    while (text) {
        n += fread(text + n, 1, cap - n - 1, f);
        if (n < cap - 1) break;
        char *bigger = realloc(text, cap *= 2);
        if (!bigger) free(text);
        text = bigger;
    }
    fclose(f);
    if (text)
        text[n] = '\0';
    else
        fprintf(stderr, "hairkit view: %s: out of memory\n", path);
    return text;
}

static const char *builtin(const char *name)
{
    for (const hk_ShaderSource *s = hk_viewer_shaders; s->path; s++)
        if (!strcmp(s->name, name)) return s->text;
    return NULL;
}

/* The compiler's log, one message a line, as FILE:LINE: message. The drivers write
 * "0:12(5): error: ..." (Mesa), "0(12) : error ..." (NVIDIA) or "ERROR: 0:12: ..." . */
static void print_log(const char *label, const char *log)
{
    while (*log) {
        const char *end = strchr(log, '\n');
        const size_t len = end ? (size_t)(end - log) : strlen(log);
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)(len < sizeof line - 1 ? len : sizeof line - 1), log);
        const char *p = line;
        if (!strncmp(p, "ERROR: ", 7)) p += 7;
        long number = -1;
        const char *rest = line;
        if (p[0] == '0' && (p[1] == ':' || p[1] == '(')) {
            char *after;
            number = strtol(p + 2, &after, 10);
            while (*after && (*after == ')' || *after == '(' || (*after >= '0' && *after <= '9'))) after++;
            while (*after == ' ' || *after == ':') after++;
            rest = after;
        }
        if (len > 0) {
            if (number >= 0)
                fprintf(stderr, "hairkit view: %s:%ld: %s\n", label, number, rest);
            else
                fprintf(stderr, "hairkit view: %s: %s\n", label, line);
        }
        log += len;
        if (*log == '\n') log++;
    }
}

static GLuint compile(GLenum kind, const char *path, const char *name)
{
    char *owned = NULL;
    const char *text, *label;
    if (path) {
        text = owned = read_text(path);
        label = path;
    } else {
        text = builtin(name);
        label = name;
    }
    if (!text) {
        if (!path) fprintf(stderr, "hairkit view: no built-in shader %s\n", name);
        return 0;
    }
    GLuint s = glCreateShader(kind);
    glShaderSource(s, 1, &text, NULL);
    glCompileShader(s);
    free(owned);
    GLint ok = 0, size = 0;
    glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (ok) return s;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &size);
    char *log = malloc((size_t)size + 1);
    if (log) {
        glGetShaderInfoLog(s, size, NULL, log);
        log[size] = '\0';
        fprintf(stderr, "hairkit view: %s: the shader does not compile:\n", label);
        print_log(label, log);
        free(log);
    }
    glDeleteShader(s);
    return 0;
}

GLuint hk_gl_program(const char *vert_path, const char *vert_name, const char *frag_path, const char *frag_name)
{
    GLuint v = compile(GL_VERTEX_SHADER, vert_path, vert_name);
    GLuint f = v ? compile(GL_FRAGMENT_SHADER, frag_path, frag_name) : 0;
    if (!f) {
        if (v) glDeleteShader(v);
        return 0;
    }
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0, size = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (ok) return p;
    glGetProgramiv(p, GL_INFO_LOG_LENGTH, &size);
    char *log = malloc((size_t)size + 1);
    char label[1024];
    snprintf(label, sizeof label, "%s + %s", vert_path ? vert_path : vert_name, frag_path ? frag_path : frag_name);
    if (log) {
        glGetProgramInfoLog(p, size, NULL, log);
        log[size] = '\0';
        fprintf(stderr, "hairkit view: %s: the shaders do not link:\n", label);
        print_log(label, log);
        free(log);
    }
    glDeleteProgram(p);
    return 0;
}

void hk_gl_uniform1i(GLuint p, const char *name, int v)
{
    const GLint at = glGetUniformLocation(p, name);
    if (at >= 0) glUniform1i(at, v);
}

void hk_gl_uniform1f(GLuint p, const char *name, double v)
{
    const GLint at = glGetUniformLocation(p, name);
    if (at >= 0) glUniform1f(at, (float)v);
}

void hk_gl_uniform3f(GLuint p, const char *name, double x, double y, double z)
{
    const GLint at = glGetUniformLocation(p, name);
    if (at >= 0) glUniform3f(at, (float)x, (float)y, (float)z);
}

void hk_gl_uniform4f(GLuint p, const char *name, double x, double y, double z, double w)
{
    const GLint at = glGetUniformLocation(p, name);
    if (at >= 0) glUniform4f(at, (float)x, (float)y, (float)z, (float)w);
}

void hk_gl_uniform_mat4(GLuint p, const char *name, const float *m)
{
    const GLint at = glGetUniformLocation(p, name);
    if (at >= 0) glUniformMatrix4fv(at, 1, GL_FALSE, m);
}
