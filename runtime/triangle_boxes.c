/* Triangle boxes computed in parallel on the host (see triangle_boxes.h). */
#include "runtime/triangle_boxes.h"

#include "runtime/context_internal.h"

#define MAX_BOX_THREADS 64

/* Each triangle's box, written where `boxes` points (8 floats: lo xyz 0, hi xyz 0), by one
 * host thread per slice of the scene, each bounding its slice. */
typedef struct box_job {
  const float *tris;
  size_t count;
  float *boxes;
  int threads;
  lt_box bounds[MAX_BOX_THREADS];
} box_job;

static void box_slice(void *arg) {
  box_job *job = arg;
  int t = lt__native_group_id;
  size_t n = job->count, begin = n * t / job->threads, end = n * (t + 1) / job->threads;
  lt_v4 inf = lt_v4_splat(INFINITY), ninf = lt_v4_splat(-INFINITY);
  lt_v4 blo = inf, bhi = ninf;
  lt_v4 *boxes = (lt_v4 *)job->boxes;
  for (size_t i = begin; i < end; i++) {
    lt_v4 lo, hi;
    lt_tri_box4(job->tris + 9 * i, &lo, &hi);
    boxes[2 * i] = lo, boxes[2 * i + 1] = hi;
    blo = lt_v4_min(lo, blo), bhi = lt_v4_max(hi, bhi);
  }
  job->bounds[t] = lt_box_of4(blo, bhi);
}

/* The boxes and the root's bounds. */
lt_status lt__triangle_boxes(const lt_scene *scene, float *boxes, lt_box *bounds) {
  box_job job;
  int threads = lt__native_threads();
  job.tris = lt_scene_triangles(scene), job.count = lt_scene_triangle_count(scene), job.boxes = boxes;
  job.threads = threads < 1 ? 1 : threads > MAX_BOX_THREADS ? MAX_BOX_THREADS : threads;
  if (job.count < 65536) job.threads = 1;
  lt_status status = lt__native_run(job.threads, box_slice, &job);
  *bounds = lt_box_empty();
  for (int t = 0; !status && t < job.threads; t++) lt_box_grow(bounds, &job.bounds[t]);
  return status;
}

