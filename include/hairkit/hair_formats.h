/* Hair strands in the file formats other tools use, read into and written from the
 * cyHair model of hairkit/hairfile.h (strands of points, float32 x, y, z):
 *
 *   cyhair  .hair   Cem Yuksel's cyHair (hk_hair_load / hk_hair_save)
 *   tfx     .tfx    AMD TressFX: read v3 and v4, write v4 (every strand the same count)
 *   usc     .data   USC-HairSalon: i32 strands, then per strand i32 n + n float3
 *   ply     .ply    PLY strands, binary little-endian or ASCII: vertex x y z (float or
 *                   double, optional red green blue) with a `strand` element of segment
 *                   counts (CT2Hair / hairutil), or with an `edge` element chained into
 *                   strands
 *   obj     .obj    Wavefront OBJ polylines: `v` points, `l` strands
 *   usda    .usda   USD ascii: one BasisCurves prim, type "linear"
 *
 * docs/file-formats.md describes every layout, what is read and written and the limits.
 * Readers check every count against the file's size before allocating, and refuse
 * malformed or truncated files with "path:offset: ..." (binary) or "path:line: ..."
 * (text) messages. Writers write atomically (a temporary file renamed when complete).
 * Points are kept exactly: a file written and read back gives the same float32 bits
 * (text formats print the shortest decimal that reads back to the same float). */
#ifndef HAIRKIT_HAIR_FORMATS_H
#define HAIRKIT_HAIR_FORMATS_H

#include <stdint.h>

#include "hairkit/core.h"
#include "hairkit/export.h"
#include "hairkit/hairfile.h"
#include "hairkit/vecmath.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum hk_HairFormat {
    HK_HAIR_FORMAT_AUTO = 0, /* from the file name's extension (and, reading, the content) */
    HK_HAIR_FORMAT_CYHAIR,
    HK_HAIR_FORMAT_TFX,
    HK_HAIR_FORMAT_USC,
    HK_HAIR_FORMAT_PLY,
    HK_HAIR_FORMAT_OBJ,
    HK_HAIR_FORMAT_USDA
} hk_HairFormat;

/* The format of a file name's extension, any case (.hair .tfx .data .ply .obj .usda);
 * HK_HAIR_FORMAT_AUTO when the extension is none of them. */
HK_API hk_HairFormat hk_hair_format_from_path(const char *path);

/* The format of a name, any case: "hair" or "cyhair", "tfx" or "tressfx", "usc" or
 * "data", "ply", "obj", "usda" or "usd", "auto"; -1 when unknown. */
HK_API int hk_hair_format_from_name(const char *name);

/* Short name of a format ("cyhair", "tfx", ...; "auto"). */
HK_API const char *hk_hair_format_name(hk_HairFormat format);

/* Reads the strands of a file into `hair` (on error `hair` holds nothing to free).
 * HK_HAIR_FORMAT_AUTO takes the format from the extension or, when the extension is
 * unknown, from the first bytes ("HAIR", "ply", "#usda"). Every reader fills points and
 * segments; PLY colours (0..255 -> 0..1) fill `colors`, USD vertex widths `thickness`
 * (a constant width the default thickness); the defaults are hk_hair_alloc's otherwise. */
HK_API hk_Status hk_hair_read(const char *path, hk_HairFormat format, hk_HairFile *hair, hk_Error *err);

/* How to write (hk_hair_write_defaults() gives the defaults). */
typedef struct hk_HairWriteDef {
    hk_HairFormat format;   /* AUTO (default): from the path's extension */
    uint32_t points;        /* any format: resample the strands by arc length to this many
                               points (2 to 65536; hk_hair_resample); 0 (default): the
                               points as they are, and TressFX refuses strands of
                               different counts */
    int ascii;              /* PLY: ASCII instead of binary little-endian (default 0) */
    double meters_per_unit; /* USD: the stage's metersPerUnit (default 1: metres) */
} hk_HairWriteDef;

HK_API hk_HairWriteDef hk_hair_write_defaults(void);

/* Writes the strands of `hair` (segments or default segments, points; colours to PLY,
 * thickness to USD widths). def NULL: the defaults. */
HK_API hk_Status hk_hair_write(const char *path, const hk_HairFile *hair, const hk_HairWriteDef *def, hk_Error *err);

/* ---- one format each (what hk_hair_read and hk_hair_write call) ---- */
HK_API hk_Status hk_tfx_load(const char *path, hk_HairFile *hair, hk_Error *err);
/* points: as hk_HairWriteDef.points. */
HK_API hk_Status hk_tfx_save(const char *path, const hk_HairFile *hair, uint32_t points, hk_Error *err);
HK_API hk_Status hk_usc_load(const char *path, hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_usc_save(const char *path, const hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_ply_hair_load(const char *path, hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_ply_hair_save(const char *path, const hk_HairFile *hair, int ascii, hk_Error *err);
HK_API hk_Status hk_obj_hair_load(const char *path, hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_obj_hair_save(const char *path, const hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_usda_hair_load(const char *path, hk_HairFile *hair, hk_Error *err);
HK_API hk_Status hk_usda_hair_save(const char *path, const hk_HairFile *hair, double meters_per_unit, hk_Error *err);

/* ---- transforms ---- */

/* Multiplies every coordinate by s (> 0 and finite), and the thickness (array and
 * default), which is a length too: 0.001 turns millimetres into metres. */
HK_API hk_Status hk_hair_scale(hk_HairFile *hair, double s, hk_Error *err);

/* The six axes a file may have as its up direction: hk_Axis (hairkit/vecmath.h). */
/* "+x" "-x" "+y" "-y" "+z" "-z" ("x" means "+x"; any case); -1 when unknown. */
HK_API int hk_axis_from_name(const char *name);
HK_API const char *hk_axis_name(hk_Axis axis);

/* Rotates the points so that `up` becomes +y, by the smallest rotation: the one of
 * hk_v3_up_to_y (hairkit/vecmath.h), which only swaps and negates coordinates, so it is
 * exact (hk_mesh_up_to_y does the same to a head). */
HK_API void hk_hair_up_to_y(hk_HairFile *hair, hk_Axis up);

/* A copy of `in` whose strands each have `points` (2 to 65536) points, placed at equal
 * arc length along the strand's polyline (the root and the tip are kept exactly; a
 * strand of zero length repeats its root). A strand that has `points` points already is
 * copied as it is. Only points and segments are kept; the defaults and information are
 * copied. */
HK_API hk_Status hk_hair_resample(const hk_HairFile *in, uint32_t points, hk_HairFile *out, hk_Error *err);

/* ---- units and strand width of a groom made elsewhere ---- */

/* The diameter of a human hair, 70 micrometres, in metres: what `hairkit render` draws
 * when a file's strand width is not a hair's. */
#define HK_HUMAN_HAIR_DIAMETER 70e-6

/* The largest side of the points' bounding box (0 with no points). */
HK_API double hk_hair_extent(const hk_HairFile *hair);

/* The units a groom's extent suggests, in metres per file unit: a head of hair spans
 * tens of centimetres, so an extent of 200 to 20,000 suggests millimetres (0.001), 5 to
 * 200 centimetres (0.01), anything else metres (1). A guess (`hairkit info` prints it). */
HK_API double hk_hair_guess_meters_per_unit(const hk_HairFile *hair);

/* The widest strand hk_hair_thickness_implausible takes for hair: 0.5 mm, in metres
 * (human hair is 17 to 181 micrometres across). */
#define HK_MAX_HAIR_DIAMETER 0.5e-3

/* Whether the strand width a file gives cannot be hair's: it has no per-point thickness
 * and its default thickness is more than 1 % of the groom's extent, or more than
 * HK_MAX_HAIR_DIAMETER in metres with `meters_per_unit` metres per file unit (<= 0:
 * hk_hair_guess_meters_per_unit). Other tools write 1.0 there whatever the units;
 * hairkit writes the hair's diameter. */
HK_API int hk_hair_thickness_implausible(const hk_HairFile *hair, double meters_per_unit);

/* Whether every strand has the same number of points (also true with no strands). */
HK_API int hk_hair_uniform_strands(const hk_HairFile *hair);

#ifdef __cplusplus
}
#endif

#endif /* HAIRKIT_HAIR_FORMATS_H */
