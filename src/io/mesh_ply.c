/* Meshes (heads, wicks) from PLY files, binary little-endian or ASCII (docs/file-formats.md,
 * "PLY heads"), through the PLY reader the strands use (ply.h); the mesh reader that
 * picks OBJ or PLY by the file's extension (the transforms a head made elsewhere needs,
 * units and up axis, are in src/mesh/mesh.c).
 *
 * Read: a `vertex` element with x, y, z (float or double) and optionally nx, ny, nz
 * (float or double: the vertex normals); a `face` element with a list property
 * `vertex_indices` (or `vertex_index`, or its only list) of 0-based integer indices,
 * polygons of 3 or more corners triangulated as fans (as the OBJ reader does). Other
 * properties (s, t, colours, ...) and elements (edges, materials, ...) are read and
 * skipped. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "hairkit/mesh.h"
#include "ply.h"

static hk_Status read_vertices(hk_Ply *ply, const hk_PlyElem *el, hk_Vec3 *pos, hk_Vec3 *nrm, int *has_normals,
                               hk_Error *err)
{
    static const char *const names[6] = {"x", "y", "z", "nx", "ny", "nz"};
    int at[6], keep[HK_PLY_MAX_PROPS];
    for (int i = 0; i < HK_PLY_MAX_PROPS; i++) keep[i] = -1;
    for (int k = 0; k < 6; k++) {
        at[k] = hk_ply_prop_index(el, names[k]);
        const int ok = at[k] >= 0 && !el->props[at[k]].count_type &&
                       (el->props[at[k]].type == HK_PLY_F32 || el->props[at[k]].type == HK_PLY_F64);
        if (k < 3 && !ok) {
            if (at[k] < 0 || el->props[at[k]].count_type)
                return hk_ply_elem_error(ply, el, err, "the vertex element has no property %s", names[k]);
            return hk_ply_elem_error(ply, el, err, "vertex %s is %s (float or double are read)", names[k],
                                     hk_ply_types[el->props[at[k]].type].name);
        }
        if (!ok) at[k] = -1;
    }
    *has_normals = at[3] >= 0 && at[4] >= 0 && at[5] >= 0;
    for (int k = 0; k < (*has_normals ? 6 : 3); k++) keep[at[k]] = k;
    char what[HK_PLY_NAME_SIZE + 32];
    for (uint64_t r = 0; r < el->count; r++) {
        double row[6] = {0, 0, 0, 0, 0, 0};
        snprintf(what, sizeof what, "vertex %llu", (unsigned long long)r);
        for (int i = 0; i < el->nprops; i++) {
            const hk_PlyProp *p = &el->props[i];
            double v;
            hk_Status st;
            if (p->count_type) { /* a list on a vertex: skipped */
                if ((st = hk_ply_read_value(ply, p->count_type, &v, what, err)) != HK_OK) return st;
                if (v < 0 || v > 1e9) return hk_ply_error(ply, err, "list of %g items in %s", v, what);
                for (uint64_t k = 0; k < (uint64_t)v; k++)
                    if ((st = hk_ply_read_value(ply, p->type, &v, what, err)) != HK_OK) return st;
                continue;
            }
            if ((st = hk_ply_read_value(ply, p->type, &v, what, err)) != HK_OK) return st;
            if (keep[i] < 0) continue;
            /* As in the OBJ reader: within a bound past any head in any unit. */
            if (keep[i] < 3 && !(fabs(v) <= HK_MAX_MESH_COORDINATE))
                return hk_ply_error(ply, err, "%s = %g is out of range in %s: coordinates are within +-%g",
                                    names[keep[i]], v, what, HK_MAX_MESH_COORDINATE);
            row[keep[i]] = v;
        }
        pos[r] = hk_v3(row[0], row[1], row[2]);
        if (*has_normals) nrm[r] = hk_v3(row[3], row[4], row[5]);
    }
    return HK_OK;
}

typedef struct Triangles {
    int *v; /* 3 per triangle */
    size_t count, capacity;
} Triangles;

static int push_triangle(Triangles *t, int a, int b, int c, hk_Error *err)
{
    if (t->count == t->capacity) {
        const size_t cap = t->capacity ? 2 * t->capacity : 4096;
        int *v = hk_alloc_array(cap, 3 * sizeof(int), err);
        if (!v) return 0;
        if (t->count) memcpy(v, t->v, t->count * 3 * sizeof(int));
        hk_free(t->v);
        t->v = v;
        t->capacity = cap;
    }
    int *d = t->v + 3 * t->count++;
    d[0] = a, d[1] = b, d[2] = c;
    return 1;
}

static hk_Status read_faces(hk_Ply *ply, const hk_PlyElem *el, int list, uint64_t nverts, Triangles *tris,
                            hk_Error *err)
{
    char what[HK_PLY_NAME_SIZE + 32];
    for (uint64_t r = 0; r < el->count; r++) {
        snprintf(what, sizeof what, "face %llu", (unsigned long long)r);
        for (int i = 0; i < el->nprops; i++) {
            const hk_PlyProp *p = &el->props[i];
            double v;
            hk_Status st;
            if (!p->count_type) {
                if ((st = hk_ply_read_value(ply, p->type, &v, what, err)) != HK_OK) return st;
                continue;
            }
            const size_t at = ply->pos;
            if ((st = hk_ply_read_value(ply, p->count_type, &v, what, err)) != HK_OK) return st;
            if (v < 0 || v > 1e9) return hk_ply_error(ply, err, "list of %g items in %s", v, what);
            const uint64_t n = (uint64_t)v;
            if (i == list && n < 3) {
                ply->pos = at;
                return hk_ply_error(ply, err, "%s has %llu corners (a face needs at least 3)", what,
                                    (unsigned long long)n);
            }
            int first = 0, prev = 0;
            for (uint64_t k = 0; k < n; k++) {
                const size_t item = ply->pos;
                if ((st = hk_ply_read_value(ply, p->type, &v, what, err)) != HK_OK) return st;
                if (i != list) continue;
                if (v < 0 || v >= (double)nverts || v != floor(v)) {
                    ply->pos = item;
                    return hk_ply_error(ply, err, "%s: corner %llu is vertex %g (%llu vertices)", what,
                                        (unsigned long long)k, v, (unsigned long long)nverts);
                }
                const int c = (int)v;
                if (k == 0) first = c;
                if (k >= 2) { /* fan triangulation */
                    if (tris->count >= HK_MAX_MESH_TRIANGLES)
                        return hk_ply_error(ply, err, "more than %d triangles", HK_MAX_MESH_TRIANGLES);
                    if (!push_triangle(tris, first, prev, c, err)) return HK_ERR_NOMEM;
                }
                prev = c;
            }
        }
    }
    return HK_OK;
}

/* The face element's list of vertex indices: vertex_indices, vertex_index, or its only
 * list; -1 when none. */
static int face_list(const hk_PlyElem *el)
{
    int at = hk_ply_prop_index(el, "vertex_indices");
    if (at < 0) at = hk_ply_prop_index(el, "vertex_index");
    if (at >= 0) return el->props[at].count_type ? at : -1;
    for (int i = 0; i < el->nprops; i++)
        if (el->props[i].count_type) {
            if (at >= 0) return -1; /* two lists: which one is not known */
            at = i;
        }
    return at;
}

hk_Status hk_ply_mesh_load(const char *path, hk_Mesh *mesh, hk_Error *err)
{
    memset(mesh, 0, sizeof *mesh);
    hk_Ply ply;
    hk_Status st = hk_ply_open(&ply, path, err);
    if (st != HK_OK) return st;
    const hk_PlyElem *vert = NULL, *face = NULL;
    for (int e = 0; e < ply.nelems; e++) {
        if (!strcmp(ply.elems[e].name, "vertex")) vert = &ply.elems[e];
        if (!strcmp(ply.elems[e].name, "face")) face = &ply.elems[e];
    }
    hk_Vec3 *pos = NULL, *nrm = NULL;
    Triangles tris = {NULL, 0, 0};
    int has_normals = 0, list = -1;
    if (!vert || !face) {
        int strands = 0;
        for (int e = 0; e < ply.nelems; e++)
            strands |= !strcmp(ply.elems[e].name, "strand") || !strcmp(ply.elems[e].name, "edge");
        st = hk_error_set(err, HK_ERR_PARSE, "%s: no %s element in this PLY file%s", path, vert ? "face" : "vertex",
                          vert && strands ? " (it has strands or edges: hair, not a mesh)" : "");
        goto done;
    }
    if (vert->count == 0 || vert->count > HK_MAX_MESH_VERTICES) {
        st = hk_ply_elem_error(&ply, vert, err, "%llu vertices (1 to %d are read)", (unsigned long long)vert->count,
                               HK_MAX_MESH_VERTICES);
        goto done;
    }
    list = face_list(face);
    if (list < 0) {
        st = hk_ply_elem_error(&ply, face, err, "the face element has no list property vertex_indices");
        goto done;
    }
    if (face->props[list].type >= HK_PLY_F32) {
        st = hk_ply_elem_error(&ply, face, err, "face indices are %s (integers are read)",
                               hk_ply_types[face->props[list].type].name);
        goto done;
    }
    for (int e = 0; e < ply.nelems && st == HK_OK; e++) {
        const hk_PlyElem *el = &ply.elems[e];
        /* Every count against what is left of the file before anything is allocated
         * (a face has at least 3 corners). */
        st = hk_ply_check_room(&ply, el, el == face ? 3 : 0, err);
        if (st != HK_OK) break;
        if (el == vert) {
            pos = hk_alloc_array((size_t)el->count, sizeof *pos, err);
            nrm = hk_alloc_array((size_t)el->count, sizeof *nrm, err);
            if (!pos || !nrm)
                st = HK_ERR_NOMEM;
            else
                st = read_vertices(&ply, el, pos, nrm, &has_normals, err);
        } else if (el == face) {
            st = read_faces(&ply, el, list, vert->count, &tris, err);
        } else {
            double row[1];
            st = hk_ply_read_element(&ply, el, NULL, row, 0, NULL, NULL, err);
        }
    }
    if (st == HK_OK) st = hk_ply_check_end(&ply, err);
    if (st == HK_OK && tris.count == 0) st = hk_error_set(err, HK_ERR_PARSE, "%s: no faces in this PLY file", path);
    if (st == HK_OK) st = hk_mesh_alloc(mesh, (int)vert->count, (int)tris.count, err);
    if (st != HK_OK) goto done;
    memcpy(mesh->positions, pos, (size_t)vert->count * sizeof *pos);
    memcpy(mesh->triangles, tris.v, tris.count * 3 * sizeof(int));
    hk_mesh_compute_normals(mesh);
    if (has_normals) /* the file's normals, made unit; the faces' where they are zero */
        for (int i = 0; i < mesh->vertex_count; i++) {
            const double n = hk_v3_norm(nrm[i]);
            if (n > 0 && isfinite(n)) mesh->normals[i] = hk_v3_scale(nrm[i], 1.0 / n);
        }
done:
    hk_free(pos);
    hk_free(nrm);
    hk_free(tris.v);
    hk_ply_close(&ply);
    return st;
}

/* ---- any mesh format ---- */

static int ends_with_ply(const char *path)
{
    const size_t n = strlen(path);
    if (n < 4 || path[n - 4] != '.') return 0;
    const char *e = path + n - 3;
    return (e[0] == 'p' || e[0] == 'P') && (e[1] == 'l' || e[1] == 'L') && (e[2] == 'y' || e[2] == 'Y');
}

static int starts_with_ply(const char *path)
{
    FILE *fp = fopen(path, "rb");
    if (!fp) return 0;
    char head[4] = {0};
    const size_t n = fread(head, 1, sizeof head, fp);
    fclose(fp);
    return n == 4 && memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r');
}

hk_Status hk_mesh_load(const char *path, hk_Mesh *mesh, hk_Error *err)
{
    if (!path) {
        memset(mesh, 0, sizeof *mesh);
        return hk_error_set(err, HK_ERR_INVALID, "no mesh file name");
    }
    /* A device or a FIFO (a collision file may name any path) would be read without end. */
    struct stat sb;
    if (stat(path, &sb) == 0 && !S_ISREG(sb.st_mode)) {
        memset(mesh, 0, sizeof *mesh);
        return hk_error_set(err, HK_ERR_IO, "%s: not a regular file", path);
    }
    if (ends_with_ply(path) || starts_with_ply(path)) return hk_ply_mesh_load(path, mesh, err);
    return hk_obj_load(path, mesh, err);
}
