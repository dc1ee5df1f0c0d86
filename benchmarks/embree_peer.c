/* Embree 3 side of the benchmarks (see embree_peer.h). */
#include "benchmarks/embree_peer.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

typedef struct job {
  RTCScene scene;
  const lt_ray *rays;
  lt_hit *hits;
  size_t begin, end;
} job;

static void *trace_range(void *p) {
  job *j = p;
  struct RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  for (size_t i = j->begin; i < j->end; i++) {
    const lt_ray *r = &j->rays[i];
    struct RTCRayHit rh = {0};
    rh.ray.org_x = r->org[0], rh.ray.org_y = r->org[1], rh.ray.org_z = r->org[2];
    rh.ray.dir_x = r->dir[0], rh.ray.dir_y = r->dir[1], rh.ray.dir_z = r->dir[2];
    rh.ray.tnear = r->tmin, rh.ray.tfar = r->tmax, rh.ray.mask = 0xffffffff;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(j->scene, &context, &rh);
    int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    j->hits[i] = (lt_hit){hit ? rh.ray.tfar : INFINITY, hit ? rh.hit.u : 0, hit ? rh.hit.v : 0, hit ? (int32_t)rh.hit.primID : -1};
  }
  return NULL;
}

int lt_embree_run(const lt_scene *scene, const lt_ray *rays, size_t count, int threads, lt_hit *hits,
                  lt_embree_times *times) {
  char config[64];
  snprintf(config, sizeof config, "threads=%d", threads);
  RTCDevice device = rtcNewDevice(config);
  if (!device) return 1;

  /* Build: copy the triangles into Embree's buffers and commit, timed together. */
  double start = lt_now_ms();
  size_t n = lt_scene_triangle_count(scene);
  const float *tris = lt_scene_triangles(scene);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n);
  unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n);
  if (!vertices || !indices) return rtcReleaseDevice(device), 1;
  for (size_t i = 0; i < 9 * n; i++) vertices[i] = tris[i];
  for (size_t i = 0; i < 3 * n; i++) indices[i] = (unsigned)i;
  rtcCommitGeometry(geometry);
  RTCScene rscene = rtcNewScene(device);
  rtcSetSceneFlags(rscene, RTC_SCENE_FLAG_ROBUST);
  rtcAttachGeometry(rscene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(rscene);
  times->build_ms = lt_now_ms() - start;

  /* Trace: one contiguous range of rays per thread. */
  start = lt_now_ms();
  pthread_t workers[64];
  job jobs[64];
  if (threads > 64) threads = 64;
  for (int t = 0; t < threads; t++) {
    jobs[t] = (job){rscene, rays, hits, count * t / threads, count * (t + 1) / threads};
    pthread_create(&workers[t], NULL, trace_range, &jobs[t]);
  }
  for (int t = 0; t < threads; t++) pthread_join(workers[t], NULL);
  times->trace_ms = lt_now_ms() - start;
  rtcReleaseScene(rscene);
  rtcReleaseDevice(device);
  return 0;
}
