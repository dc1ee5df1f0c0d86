/* Morton order of triangles for the top of the on-demand BVH: the HLBVH idea (Pantaleoni and
 * Luebke, "HLBVH: Hierarchical LBVH Construction for Real-Time Ray Tracing of Dynamic
 * Geometry", HPG 2010, section 3) applied on demand: one sort per frame, then the top levels
 * split the sorted range where the codes' highest differing bit turns (Karras 2012). */
#ifndef LT_MORTON_H
#define LT_MORTON_H

#include <stddef.h>
#include <stdint.h>

#include "builders/host/executor.h"
#include "builders/bvh_morton.h"

/* Block boxes lt__morton_order writes for n triangles: every level of the pyramid over blocks
 * of LT_BVH_MORTON_BLOCK sorted positions (builders/bvh_morton.h). */
size_t lt__morton_block_count(size_t n);

/* Sorts n triangles by the 30-bit Morton code of their box centres, quantised over `bounds`
 * (any box holding the centres), stably, so equal codes keep triangle order. boxes holds 8
 * floats per triangle (lo xyz 0, hi xyz 0). Writes the sorted codes, the triangle numbers in
 * that order, and the pyramid of block boxes (2 lt_v4 each, lt__morton_block_count(n) of
 * them); adds n per radix pass to *sort_ops. The loops run on the executor's workers (NULL:
 * the caller); the order is the same whatever their number. */
lt_status lt__morton_order(const float *boxes, size_t n, const lt_box *bounds, const lt__executor *executor,
                           uint32_t *codes, int32_t *index, float *block_boxes, double *sort_ops);

#endif
