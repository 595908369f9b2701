/*
 * dtype.c — the sample types of gray volumes (bvox_dtype): names, aliases
 * and sizes, in one table. Used by the readers (format.c's users: nifti.c,
 * tiff.c, raw.c) and the binariser; apart from format.c, which dispatches to
 * those readers, so that no file both serves and calls them.
 */
#include "io.h"

#include <string.h>
#include <strings.h>

static const struct {
    const char *name, *alias1, *alias2;
    size_t size;
} dtypes[BVOX_DT_COUNT] = {
    [BVOX_DT_U8] = {"u8", "uint8", "ubyte", 1},    [BVOX_DT_I8] = {"i8", "int8", "byte", 1},
    [BVOX_DT_U16] = {"u16", "uint16", "ushort", 2}, [BVOX_DT_I16] = {"i16", "int16", "short", 2},
    [BVOX_DT_U32] = {"u32", "uint32", "uint", 4},  [BVOX_DT_I32] = {"i32", "int32", "int", 4},
    [BVOX_DT_U64] = {"u64", "uint64", "ulong", 8}, [BVOX_DT_I64] = {"i64", "int64", "long", 8},
    [BVOX_DT_F32] = {"f32", "float32", "float", 4}, [BVOX_DT_F64] = {"f64", "float64", "double", 8},
};

const char *bvox_dtype_name(bvox_dtype t)
{
    return (unsigned)t < BVOX_DT_COUNT ? dtypes[t].name : "?";
}

size_t bvox_dtype_size(bvox_dtype t) { return (unsigned)t < BVOX_DT_COUNT ? dtypes[t].size : 0; }

int bvox_dtype_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < BVOX_DT_COUNT; i++)
        if (!strcasecmp(name, dtypes[i].name) || !strcasecmp(name, dtypes[i].alias1) ||
            !strcasecmp(name, dtypes[i].alias2))
            return i;
    return -1;
}
