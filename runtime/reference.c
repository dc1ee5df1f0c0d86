/* The brute-force reference: every ray against every triangle with the same intersection test
 * and tie rule as the kernels. Triangles are visited in number order, so ties keep the lowest
 * number, as lt_hit_better wants. */
#include "runtime/error.h"
#include "runtime/structure_internal.h"
#include "traversal/intersect_triangle.h"

lt_status lt__reference_trace_flags(const lt_scene *scene, const lt_ray *rays, size_t count, int flags,
                                    lt_hit *hits) {
  if (!scene || (count && (!rays || !hits))) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_reference_trace: NULL argument");
  const float *tris = lt_scene_triangles(scene);
  size_t count_tris = lt_scene_triangle_count(scene);
  for (size_t i = 0; i < count; i++) {
    const lt_ray *ray = &rays[i];
    lt_ray_setup r = lt_ray_prepare(ray->org[0], ray->org[1], ray->org[2], ray->tmin, ray->dir[0], ray->dir[1],
                                    ray->dir[2], ray->tmax);
    r.flags = flags;
    lt_hit_record hit = {INFINITY, 0.0f, 0.0f, -1};
    for (size_t p = 0; r.valid && p < count_tris; p++) {
      const float *t = tris + 9 * p;
      if (lt_intersect_triangle(&r, t, t + 3, t + 6, (int)p, &hit) && (flags & LT_QUERY_FLAG_ANY)) break;
    }
    hits[i] = (lt_hit){hit.prim >= 0 ? hit.t : INFINITY, hit.prim >= 0 ? hit.u : 0.0f, hit.prim >= 0 ? hit.v : 0.0f,
                       hit.prim};
  }
  return LT_OK;
}

lt_status lt_reference_trace(const lt_scene *scene, const lt_ray *rays, size_t count, int query, lt_hit *hits) {
  if (query != LT_QUERY_CLOSEST && query != LT_QUERY_ANY)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown query kind %d", query);
  return lt__reference_trace_flags(scene, rays, count, query == LT_QUERY_ANY ? LT_QUERY_FLAG_ANY : 0, hits);
}
