/* Morton order of triangles for the top of the on-demand BVH: the HLBVH idea (Pantaleoni and
 * Luebke, "HLBVH: Hierarchical LBVH Construction for Real-Time Ray Tracing of Dynamic
 * Geometry", HPG 2010, section 3) applied on demand: one sort per frame, then the top levels
 * split the sorted range where the codes' highest differing bit turns (Karras 2012). */
#ifndef LT_MORTON_H
#define LT_MORTON_H

#include <stddef.h>
#include <stdint.h>

#include "builders/bvh_morton.h"
#include "builders/host/executor.h"

/* The 30-bit Morton code of a point: each coordinate as one of 1024 cells from lo[k] on,
 * scale[k] cells per unit length (NaN and below lo in cell 0, past the end in cell 1023), the
 * x bits highest of each triple. Shared with the LBVH (builders/host/lbvh.c). */
uint32_t lt__morton_code(const float p[3], const float lo[3], const float scale[3]);

/* Block boxes lt__morton_order writes for n triangles: every level of the pyramid over blocks
 * of LT_BVH_MORTON_BLOCK sorted positions (builders/bvh_morton.h). */
size_t lt__morton_block_count(size_t n);

/* Bytes of working memory lt__morton_order needs for n triangles (keys and digit counts). */
size_t lt__morton_work_bytes(size_t n);

/* Sorts n triangles by the top 20 bits of the 30-bit Morton code of their box centres,
 * quantised over `bounds` (any box holding the centres), stably, so equal codes keep triangle
 * order; those 20 bits are the codes written. boxes holds 8
 * floats per triangle (lo xyz 0, hi xyz 0). Writes the sorted codes, the triangle numbers in
 * that order, and the pyramid of block boxes (2 lt_v4 each, lt__morton_block_count(n) of
 * them); adds n per radix pass to *sort_ops. `work` is lt__morton_work_bytes(n) bytes, 8-byte
 * aligned, that a caller rebuilding every frame keeps (NULL: allocated here). The loops run on
 * the executor's workers (NULL: the caller); the order is the same whatever their number. */
lt_status lt__morton_order(const float *boxes, size_t n, const lt_box *bounds, const lt__executor *executor, void *work,
                           uint32_t *codes, int32_t *index, float *block_boxes, double *sort_ops);

#endif
