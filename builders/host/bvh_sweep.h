/* Reference-quality SAH BVH build on the host: full sweep or any number of bins. */
#ifndef LT_BVH_SWEEP_H
#define LT_BVH_SWEEP_H

#include "builders/host/bvh_sah.h"

/* Builds over n triangles of 9 floats each; bins 0 sweeps every primitive boundary, bins >= 2
 * bins the centroids (without the pool builder's limit of LT_MAX_BINS). config gives the leaf
 * size and costs; its bins field is ignored. */
lt_status lt__bvh_build_sweep(const float *tris, size_t n, const lt__sah_config *config, int bins, lt__bvh *out);

#endif
