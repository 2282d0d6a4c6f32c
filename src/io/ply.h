/* Internal (not installed): the PLY reader shared by the strand reader (hair_ply.c) and
 * the mesh reader (mesh_ply.c). The header is parsed into elements and properties; the
 * body is read value by value, binary little-endian or ASCII, with "path:line:"
 * (header, ASCII body) or "path:offset:" (binary body) messages. */
#ifndef HK_IO_PLY_H
#define HK_IO_PLY_H

#include <stdint.h>

#include "hair_io.h"

/* Value types; hk_ply_types[type] gives the name, its alias and the size in bytes. */
enum { HK_PLY_I8 = 1, HK_PLY_U8, HK_PLY_I16, HK_PLY_U16, HK_PLY_I32, HK_PLY_U32, HK_PLY_F32, HK_PLY_F64 };
typedef struct hk_PlyType {
    const char *name, *alias;
    int size;
} hk_PlyType;
extern const hk_PlyType hk_ply_types[HK_PLY_F64 + 1];

#define HK_PLY_MAX_ELEMS 32
#define HK_PLY_MAX_PROPS 64
#define HK_PLY_NAME_SIZE 64

typedef struct hk_PlyProp {
    char name[HK_PLY_NAME_SIZE];
    int type;       /* of the value (of the items, for a list) */
    int count_type; /* of a list's count; 0 for a scalar */
} hk_PlyProp;

typedef struct hk_PlyElem {
    char name[HK_PLY_NAME_SIZE];
    uint64_t count;
    hk_PlyProp props[HK_PLY_MAX_PROPS];
    int nprops;
    long line; /* of its header line */
} hk_PlyElem;

typedef struct hk_Ply {
    hk_TextIn t;
    int ascii;
    hk_PlyElem elems[HK_PLY_MAX_ELEMS];
    int nelems;
    /* the body cursor */
    size_t pos;
    long line; /* ASCII: line of pos; < 0: -(a header line) the next message names */
} hk_Ply;

/* Reads the whole file and parses its header (the cursor then at the body's start).
 * On error nothing is left to free. */
hk_Status hk_ply_open(hk_Ply *ply, const char *path, hk_Error *err);
void hk_ply_close(hk_Ply *ply);

/* "path:line: message" (header, ASCII body) or "path:offset: message" (binary body);
 * returns HK_ERR_PARSE. */
hk_Status hk_ply_error(const hk_Ply *ply, hk_Error *err, const char *fmt, ...) HK_PRINTF_LIKE(3, 4);
/* The same, naming the header line of element el. */
hk_Status hk_ply_elem_error(hk_Ply *ply, const hk_PlyElem *el, hk_Error *err, const char *fmt, ...)
    HK_PRINTF_LIKE(4, 5);

/* Reads one value of `type` at the cursor into *out (exact for float and double;
 * non-finite numbers refused); `what` names it in messages. */
hk_Status hk_ply_read_value(hk_Ply *ply, int type, double *out, const char *what, hk_Error *err);

/* Fewest bytes a record of el can take (with its lists at `min_items` items). */
uint64_t hk_ply_min_record(const hk_Ply *ply, const hk_PlyElem *el, uint64_t min_items);
/* "truncated: element 'E' announces N records ..." when the rest of the file cannot hold
 * el's records of at least hk_ply_min_record bytes: the check before allocating. */
hk_Status hk_ply_check_room(hk_Ply *ply, const hk_PlyElem *el, uint64_t min_items, hk_Error *err);

/* The index of property `name` in el, -1 when absent. */
int hk_ply_prop_index(const hk_PlyElem *el, const char *name);

/* Reads every record of el, keeping the values `keep` asks for: keep[i] >= 0 stores
 * property i's value into column keep[i] of row (ncol columns, as double), then calls
 * store(ply, user, record, row) when store is not NULL. Lists are read and skipped. */
typedef hk_Status (*hk_PlyStoreFn)(hk_Ply *ply, void *user, uint64_t record, const double *row, hk_Error *err);
hk_Status hk_ply_read_element(hk_Ply *ply, const hk_PlyElem *el, const int *keep, double *row, int ncol,
                              hk_PlyStoreFn store, void *user, hk_Error *err);

/* After the last element: nothing but blanks (ASCII) or nothing at all (binary). */
hk_Status hk_ply_check_end(hk_Ply *ply, hk_Error *err);

#endif
