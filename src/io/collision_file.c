/* Collision Info files (Lansink 2010 §4.2.1 and Appendix B): spheres, ellipsoids and
 * cuboids with their envelope Volume and Penalty stiffness (§4.1.2), and hairkit's
 * meshes, whose signed distance fields are body shapes of the same kind
 * (docs/file-formats.md, "Collision file"). */
#include <ctype.h>
#include <math.h>
#include <string.h>

#include "hairkit/hair_formats.h"
#include "hairkit/io.h"
#include "io_internal.h"
#include "keyfile.h"

#define HK_AXIS_TOLERANCE 1e-3 /* largest |cos| between two axes taken as orthogonal */

/* Unit vector along (x, y, z), scaled by its largest component first so that neither
 * (1e300, 1e300, 0) overflows nor (1e-200, 0, 0) underflows; zero stays zero. */
static hk_Vec3 unit(double x, double y, double z)
{
    double m = fmax(fabs(x), fmax(fabs(y), fabs(z)));
    if (!(m > 0.0)) return hk_v3_zero();
    return hk_v3_normalize(hk_v3(x / m, y / m, z / m));
}

/* Axes U, V, W from values 8..16 of an ellipsoid or cuboid line, normalised. */
static hk_Status read_axes(const hk_KeyFile *kf, const hk_KeyLine *kl, const double *v, hk_Vec3 axes[3], hk_Error *err)
{
    static const char *const names[3] = {"U", "V", "W"};
    for (int i = 0; i < 3; i++) {
        axes[i] = unit(v[8 + 3 * i], v[9 + 3 * i], v[10 + 3 * i]);
        if (hk_v3_norm2(axes[i]) == 0.0)
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "axis %s of the %s is zero", names[i], kl->key);
    }
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++) {
            double c = hk_v3_dot(axes[i], axes[j]);
            if (fabs(c) > HK_AXIS_TOLERANCE)
                return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                        "axes %s and %s of the %s are not orthogonal (cosine %.3g, "
                                        "at most %g allowed)",
                                        names[i], names[j], kl->key, c, HK_AXIS_TOLERANCE);
        }
    return HK_OK;
}

/* The optional last word of a shape's line, its role: `Body` (the default, so the
 * thesis's files keep their meaning) or `Styling`, a field that shapes the guides but
 * that hair may enter (docs/file-formats.md). Only a word after the `fixed` values
 * that every line of the kind has is a role. Returns the count of values without it. */
static int strip_role(const hk_KeyLine *kl, int fixed, int *styling)
{
    *styling = 0;
    if (kl->count <= fixed) return kl->count;
    const char *role = kl->values[kl->count - 1];
    if (hk_key_equal(role, "Styling"))
        *styling = 1;
    else if (!hk_key_equal(role, "Body"))
        return kl->count;
    return kl->count - 1;
}

/* A word where a number cannot be is a misspelt role, not a count error. */
static int looks_like_role(const char *word)
{
    return isalpha((unsigned char)word[0]) && !hk_key_equal(word, "nan") && !hk_key_equal(word, "inf");
}

static hk_Status read_shape(const hk_KeyFile *kf, const hk_KeyLine *kl, hk_Shape *shape, hk_Error *err)
{
    /* Appendix B's sample spells "Elipsoid"; files written after it keep working. */
    const int sphere = hk_key_equal(kl->key, "Sphere");
    const int ellipsoid = hk_key_equal(kl->key, "Ellipsoid") || hk_key_equal(kl->key, "Elipsoid");
    const int cuboid = hk_key_equal(kl->key, "Cuboid");
    if (!sphere && !ellipsoid && !cuboid)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "unknown shape '%s' (expected Sphere, Ellipsoid, Cuboid or Mesh)", kl->key);
    const int numbers = sphere ? 6 : 17;
    hk_KeyLine nums = *kl;
    int styling = 0;
    if (kl->count == numbers + 1) nums.count = strip_role(kl, numbers, &styling);
    if (kl->count == numbers + 1 && nums.count == kl->count && looks_like_role(kl->values[numbers]))
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "unknown role '%s' after the %s's numbers (expected Body or Styling)",
                                kl->values[numbers], kl->key);
    double v[17];
    hk_Status st = hk_keyline_doubles(kf, &nums, numbers, v, err);
    if (st != HK_OK) return st;
    /* v[0] is the Volume (envelope thickness, §4.1.2.2): any finite value, negative
     * shrinks the shape. */
    if (!(v[1] >= 0.0))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Penalty must be >= 0, got %s", kl->values[1]);
    const hk_Vec3 centre = hk_v3(v[2], v[3], v[4]);
    if (sphere) {
        if (!(v[5] > 0.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "sphere radius must be > 0, got %s",
                                    kl->values[5]);
        *shape = hk_shape_sphere(centre, v[5], v[0], v[1]);
        shape->styling = styling;
        return HK_OK;
    }
    if (!(v[5] > 0.0) || !(v[6] > 0.0) || !(v[7] > 0.0))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "%s dimensions must be > 0, got %s %s %s", kl->key,
                                kl->values[5], kl->values[6], kl->values[7]);
    hk_Vec3 axes[3];
    st = read_axes(kf, kl, v, axes, err);
    if (st != HK_OK) return st;
    const hk_Vec3 dims = hk_v3(v[5], v[6], v[7]);
    *shape = ellipsoid ? hk_shape_ellipsoid(centre, dims, axes, v[0], v[1])
                       : hk_shape_cuboid(centre, dims, axes, v[0], v[1]);
    shape->styling = styling;
    return HK_OK;
}

/* A `Mesh Volume Penalty PATH [Scale [Up]] [Role]` line, read in the first pass; its
 * field is built once every line has been read, so that a mistake on a later line is
 * told before the seconds a field takes. */
typedef struct MeshLine {
    int index; /* its place among the shapes */
    int line;
    char *path; /* resolved against the collision file's folder */
    double volume, penalty, scale;
    hk_Axis up;
    int styling;
} MeshLine;

static hk_Status read_mesh_line(const hk_KeyFile *kf, const hk_KeyLine *kl, MeshLine *m, hk_Error *err)
{
    m->line = kl->line;
    m->scale = 1.0;
    m->up = HK_AXIS_POS_Y;
    const int values = strip_role(kl, 3, &m->styling);
    if (values < 3 || values > 5)
        return hk_keyfile_error(kf, kl->line, HK_ERR_PARSE, err,
                                "expected 'Mesh Volume Penalty PATH [Scale [Up]] [Body|Styling]', got %d values after "
                                "'%s'",
                                kl->count, kl->key);
    hk_KeyLine nums = *kl;
    nums.count = 2;
    double v[2];
    hk_Status st = hk_keyline_doubles(kf, &nums, 2, v, err);
    if (st != HK_OK) return st;
    if (!(v[1] >= 0.0))
        return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err, "Penalty must be >= 0, got %s", kl->values[1]);
    m->volume = v[0];
    m->penalty = v[1];
    if (values >= 4) {
        const char *word = kl->values[3];
        if (hk_parse_decimal(word, &m->scale) != HK_NUM_OK || !(m->scale > 0.0))
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                    looks_like_role(word) && values == 4
                                        ? "unknown role '%s' after the mesh's path (expected Body or Styling)"
                                        : "the mesh's Scale must be a number > 0, got '%s'",
                                    word);
    }
    if (values == 5) {
        const int up = hk_axis_from_name(kl->values[4]);
        if (up < 0)
            return hk_keyfile_error(kf, kl->line, HK_ERR_INVALID, err,
                                    "unknown up axis '%s' (expected +x, -x, +y, -y, +z or -z)", kl->values[4]);
        m->up = (hk_Axis)up;
    }
    m->path = hk_keyfile_resolve_path(kf, kl->values[2], err);
    return m->path ? HK_OK : HK_ERR_NOMEM;
}

/* The mesh of a Mesh line read, scaled and turned to y up, its field added to set. */
static hk_Status add_mesh(const hk_KeyFile *kf, const MeshLine *m, hk_CollisionSet *set, hk_Error *err)
{
    hk_Mesh mesh;
    hk_Error sub;
    /* The readers refuse a mesh without faces ("no faces in this OBJ file"). */
    hk_Status st = hk_mesh_load(m->path, &mesh, &sub);
    if (st == HK_OK && m->scale != 1.0) st = hk_mesh_scale(&mesh, m->scale, &sub);
    int building = 0;
    if (st == HK_OK) {
        hk_mesh_up_to_y(&mesh, m->up);
        building = 1;
        st = hk_collision_add_mesh(set, &mesh, NULL, m->volume, m->penalty, &sub);
    }
    hk_mesh_free(&mesh);
    /* A grid too large for its 2 mm spacing is most often a mesh in other units. */
    if (st != HK_OK && building)
        return hk_keyfile_error(kf, m->line, st, err,
                                "Mesh: %s (the grid is in metres: Scale 0.001 reads a mesh in "
                                "millimetres)",
                                sub.message);
    if (st != HK_OK) return hk_keyfile_error(kf, m->line, st, err, "Mesh: %s", sub.message);
    set->shapes[set->count - 1].styling = m->styling;
    return HK_OK;
}

/* The shapes of the lines (meshes left out), then the meshes' fields, in file order. */
static hk_Status read_lines(const hk_KeyFile *kf, hk_Shape *shapes, MeshLine *meshes, hk_CollisionSet *out,
                            hk_Error *err)
{
    int mesh_count = 0;
    hk_Status st = HK_OK;
    for (int i = 0; i < kf->line_count && st == HK_OK; i++) {
        const hk_KeyLine *kl = &kf->lines[i];
        if (hk_key_equal(kl->key, "Mesh")) {
            meshes[mesh_count].index = i;
            st = read_mesh_line(kf, kl, &meshes[mesh_count++], err);
        } else {
            st = read_shape(kf, kl, &shapes[i], err);
        }
    }
    hk_CollisionSet fields = {0};
    for (int k = 0; k < mesh_count && st == HK_OK; k++) st = add_mesh(kf, &meshes[k], &fields, err);
    for (int k = 0; k < mesh_count; k++) hk_free(meshes[k].path);
    if (st != HK_OK) {
        hk_collision_free(&fields);
        return st;
    }
    /* The set takes the fields; the mesh shapes go to their lines' places. */
    for (int k = 0; k < mesh_count; k++) shapes[meshes[k].index] = fields.shapes[k];
    hk_free(fields.shapes);
    out->shapes = shapes;
    out->count = kf->line_count;
    out->fields = fields.fields;
    out->field_count = fields.field_count;
    return HK_OK;
}

hk_Status hk_collision_load(const char *path, hk_CollisionSet *out, hk_Error *err)
{
    memset(out, 0, sizeof *out);
    hk_KeyFile kf;
    hk_Status st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    /* Every non-empty line is one shape: count before allocating. */
    if (kf.line_count > HK_MAX_SHAPES) {
        st = hk_keyfile_error(&kf, kf.lines[HK_MAX_SHAPES].line, HK_ERR_INVALID, err, "more than %d collision shapes",
                              HK_MAX_SHAPES);
        hk_keyfile_free(&kf);
        return st;
    }
    if (kf.line_count > 0) {
        hk_Shape *shapes = hk_alloc_array((size_t)kf.line_count, sizeof *shapes, err);
        MeshLine *meshes = hk_calloc_array((size_t)kf.line_count, sizeof *meshes, err);
        st = shapes && meshes ? read_lines(&kf, shapes, meshes, out, err) : HK_ERR_NOMEM;
        if (st != HK_OK) hk_free(shapes);
        hk_free(meshes);
    }
    hk_keyfile_free(&kf);
    return st;
}

hk_Status hk_collision_fingerprint(const char *path, uint64_t *out, hk_Error *err)
{
    hk_Status st = hk_file_fingerprint(path, out, err);
    hk_KeyFile kf;
    if (st == HK_OK) st = hk_keyfile_read(path, &kf, err);
    if (st != HK_OK) return st;
    for (int i = 0; i < kf.line_count && st == HK_OK; i++) {
        const hk_KeyLine *kl = &kf.lines[i];
        if (!hk_key_equal(kl->key, "Mesh") || kl->count < 3) continue;
        char *mesh = hk_keyfile_resolve_path(&kf, kl->values[2], err);
        st = mesh ? hk_file_fingerprint_more(mesh, out, err) : HK_ERR_NOMEM;
        hk_free(mesh);
    }
    hk_keyfile_free(&kf);
    return st;
}
