/* Internal knobs of structures and the reference, for tests and the accuracy report: the query
 * flags that pick the numerics (traversal/ray.h), including ones the public API does not
 * offer because they only exist to be measured. */
#ifndef LT_STRUCTURE_INTERNAL_H
#define LT_STRUCTURE_INTERNAL_H

#include "lazytrace.h"

/* The brute-force reference with query flags (LT_QUERY_FLAG_*) instead of a query kind. */
lt_status lt__reference_trace_flags(const lt_scene *scene, const lt_ray *rays, size_t count, int flags,
                                    lt_hit *hits);
/* Flags added to every later trace of the structure (LT_QUERY_FLAG_PLAIN_SLABS, ...). */
void lt__structure_set_flags(lt_structure *structure, int flags);
/* The query flags a trace of this structure uses for a query kind. */
int lt__structure_flags(const lt_structure *structure, int query);

#endif
