/* Wavefront OBJ meshes: a streaming reader (v, vn, f; polygons as fans) with file:line
 * errors, and an atomic writer. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hairkit/mesh.h"
#include "io/outfile.h"
#include "keyfile.h"

/* Growable array of fixed-size items with a hard cap. */
typedef struct Array {
    void *data;
    size_t count, capacity, item;
} Array;

static int array_push(Array *a, const void *item, size_t cap, hk_Error *err)
{
    if (a->count >= cap) return 0;
    if (a->count == a->capacity) {
        size_t cap2 = a->capacity ? 2 * a->capacity : 1024;
        void *d = hk_alloc_array(cap2, a->item, err);
        if (!d) return 0;
        if (a->count) memcpy(d, a->data, a->count * a->item);
        hk_free(a->data);
        a->data = d;
        a->capacity = cap2;
    }
    memcpy((char *)a->data + a->count * a->item, item, a->item);
    a->count++;
    return 1;
}

typedef struct Corner {
    int v, vn; /* 0-based; vn = -1 when absent */
} Corner;

/* Parses one face corner "v", "v/vt", "v//vn" or "v/vt/vn" into 0-based indices:
 * 1 when well formed and in range, 0 when malformed, -1 when an index is out of range
 * (0 is never an OBJ index: a normal index of 0, or -(count+1), is as wrong as a vertex
 * index of 0). */
static int parse_corner(const char *tok, long nv, long nn, Corner *c)
{
    char *end;
    long v = strtol(tok, &end, 10);
    if (end == tok) return 0;
    long vn = 0, vt = 1;
    int has_vn = 0;
    if (*end == '/') {
        const char *p = end + 1;
        if (*p != '/') { /* texture index: parsed, checked for 0 and ignored */
            vt = strtol(p, &end, 10);
            if (end == p) return 0;
            p = end;
        }
        if (*p == '/') {
            p++;
            vn = strtol(p, &end, 10);
            if (end == p) return 0;
            has_vn = 1;
        } else {
            end = (char *)p;
        }
    }
    if (*end != '\0') return 0;
    /* Negative indices count back from the last element read so far. */
    if (v < 0) v += nv + 1;
    if (vn < 0) vn += nn + 1;
    if (v < 1 || v > nv || vt == 0 || (has_vn && (vn < 1 || vn > nn))) return -1;
    c->v = (int)(v - 1);
    c->vn = has_vn ? (int)(vn - 1) : -1;
    return 1;
}

hk_Status hk_obj_load(const char *path, hk_Mesh *mesh, hk_Error *err)
{
    memset(mesh, 0, sizeof *mesh);
    FILE *fp = fopen(path, "rb");
    if (!fp) return hk_error_set(err, HK_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    Array pos = {NULL, 0, 0, sizeof(hk_Vec3)}, nrm = {NULL, 0, 0, sizeof(hk_Vec3)};
    Array tris = {NULL, 0, 0, 3 * sizeof(int)}, tri_normals = {NULL, 0, 0, 3 * sizeof(int)};
    hk_Status st = HK_OK;
    char *line = NULL;
    size_t cap = 0;
    long line_no = 0;
    int any_normals = 0;
    ssize_t len;
    while ((len = getline(&line, &cap, fp)) >= 0) {
        line_no++;
        if (memchr(line, '\0', (size_t)len)) {
            st = hk_error_set(err, HK_ERR_PARSE, "%s:%ld: not a text file (binary data)", path, line_no);
            break;
        }
        char *save = NULL, *key = strtok_r(line, " \t\r\n", &save);
        if (!key || key[0] == '#') continue;
        if (!strcmp(key, "v") || !strcmp(key, "vn")) {
            double xyz[3];
            for (int i = 0; i < 3 && st == HK_OK; i++) {
                char *tok = strtok_r(NULL, " \t\r\n", &save);
                if (!tok) {
                    st = hk_error_set(err, HK_ERR_PARSE, "%s:%ld: '%s' needs three finite numbers", path, line_no, key);
                    break;
                }
                /* Decimal only, as in the key files (no hex, nan or inf), and within a
                 * bound past any head in any unit: a wick vertex at 1e39 made areas, and
                 * the strand counts from them, overflow. */
                const int r = hk_parse_decimal(tok, &xyz[i]);
                if (r == HK_NUM_SYNTAX)
                    st = hk_error_set(err, HK_ERR_PARSE, "%s:%ld: '%s' is not a decimal number (value %d of '%s')",
                                      path, line_no, tok, i + 1, key);
                else if (r != HK_NUM_OK || !(fabs(xyz[i]) <= HK_MAX_MESH_COORDINATE))
                    st = hk_error_set(err, HK_ERR_PARSE,
                                      "%s:%ld: '%s' is out of range (value %d of '%s'): coordinates are within "
                                      "+-%g",
                                      path, line_no, tok, i + 1, key, HK_MAX_MESH_COORDINATE);
            }
            if (st != HK_OK) break;
            hk_Vec3 v = hk_v3(xyz[0], xyz[1], xyz[2]);
            if (!array_push(key[1] ? &nrm : &pos, &v, HK_MAX_MESH_VERTICES, err)) {
                st = hk_error_set(err, HK_ERR_NOMEM, "%s:%ld: more than %d vertices or normals", path, line_no,
                                  HK_MAX_MESH_VERTICES);
                break;
            }
        } else if (!strcmp(key, "f")) {
            Corner first = {0, 0}, prev = {0, 0}, c;
            int n = 0;
            char *tok;
            while ((tok = strtok_r(NULL, " \t\r\n", &save)) != NULL) {
                int r = parse_corner(tok, (long)pos.count, (long)nrm.count, &c);
                if (r <= 0) {
                    st = hk_error_set(err, HK_ERR_PARSE, "%s:%ld: %s face corner '%s'", path, line_no,
                                      r < 0 ? "index out of range in" : "malformed", tok);
                    break;
                }
                if (c.vn >= 0) any_normals = 1;
                if (n >= 2) { /* fan triangulation */
                    int t[3] = {first.v, prev.v, c.v}, tn[3] = {first.vn, prev.vn, c.vn};
                    if (!array_push(&tris, t, HK_MAX_MESH_TRIANGLES, err) ||
                        !array_push(&tri_normals, tn, HK_MAX_MESH_TRIANGLES, err)) {
                        st = hk_error_set(err, HK_ERR_NOMEM, "%s:%ld: more than %d triangles", path, line_no,
                                          HK_MAX_MESH_TRIANGLES);
                        break;
                    }
                }
                if (n == 0) first = c;
                prev = c;
                n++;
            }
            if (st != HK_OK) break;
            if (n < 3) {
                st = hk_error_set(err, HK_ERR_PARSE, "%s:%ld: a face needs at least 3 corners, got %d", path, line_no,
                                  n);
                break;
            }
        }
        /* vt, o, g, s, usemtl, mtllib, l, p ...: not needed here. */
    }
    free(line);
    if (st == HK_OK && ferror(fp)) st = hk_error_set(err, HK_ERR_IO, "%s: read error", path);
    fclose(fp);
    if (st == HK_OK && (pos.count == 0 || tris.count == 0))
        st = hk_error_set(err, HK_ERR_PARSE, "%s: no %s in this OBJ file", path, pos.count == 0 ? "vertices" : "faces");
    if (st == HK_OK) st = hk_mesh_alloc(mesh, (int)pos.count, (int)tris.count, err);
    if (st == HK_OK) {
        memcpy(mesh->positions, pos.data, pos.count * sizeof(hk_Vec3));
        memcpy(mesh->triangles, tris.data, tris.count * 3 * sizeof(int));
        if (any_normals) {
            /* Per-vertex normal: average of the normals its corners name; vertices
             * without any fall back to face normals below. */
            const int *tn = tri_normals.data;
            const hk_Vec3 *nv = nrm.data;
            for (size_t i = 0; i < 3 * tris.count; i++)
                if (tn[i] >= 0)
                    mesh->normals[mesh->triangles[i]] =
                        hk_v3_add(mesh->normals[mesh->triangles[i]], hk_v3_normalize(nv[tn[i]]));
            hk_Mesh faces = *mesh;
            hk_Vec3 *fallback = hk_alloc_array((size_t)mesh->vertex_count, sizeof(hk_Vec3), err);
            if (!fallback) {
                st = HK_ERR_NOMEM;
            } else {
                faces.normals = fallback;
                hk_mesh_compute_normals(&faces);
                for (int i = 0; i < mesh->vertex_count; i++) {
                    double n = hk_v3_norm(mesh->normals[i]);
                    mesh->normals[i] = n > 0 ? hk_v3_scale(mesh->normals[i], 1.0 / n) : fallback[i];
                }
                hk_free(fallback);
            }
        } else {
            hk_mesh_compute_normals(mesh);
        }
        if (st != HK_OK) hk_mesh_free(mesh);
    }
    hk_free(pos.data);
    hk_free(nrm.data);
    hk_free(tris.data);
    hk_free(tri_normals.data);
    return st;
}

hk_Status hk_obj_save(const char *path, const hk_Mesh *mesh, const char *comment, hk_Error *err)
{
    hk_OutFile out;
    hk_Status st = hk_outfile_open(&out, path, err);
    if (st != HK_OK) return st;
    if (comment) fprintf(out.fp, "# %s\n", comment);
    for (int i = 0; i < mesh->vertex_count; i++)
        fprintf(out.fp, "v %.9g %.9g %.9g\n", mesh->positions[i].x, mesh->positions[i].y, mesh->positions[i].z);
    for (int i = 0; i < mesh->vertex_count; i++)
        fprintf(out.fp, "vn %.6f %.6f %.6f\n", mesh->normals[i].x, mesh->normals[i].y, mesh->normals[i].z);
    for (int t = 0; t < mesh->triangle_count; t++) {
        const int *tri = mesh->triangles + 3 * t;
        fprintf(out.fp, "f %d//%d %d//%d %d//%d\n", tri[0] + 1, tri[0] + 1, tri[1] + 1, tri[1] + 1, tri[2] + 1,
                tri[2] + 1);
    }
    return hk_outfile_commit(&out, err);
}
