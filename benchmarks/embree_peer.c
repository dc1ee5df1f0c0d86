/* Embree 3 side of the benchmarks (see embree_peer.h). */
#include "benchmarks/embree_peer.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

struct lt_embree {
  RTCDevice device; /* borrowed from the devices below */
  RTCScene scene;
  int threads;
};

/* One Embree device per thread count, made on first use and kept for the program's life, as a
 * program that rebuilds its scene every frame keeps its device (its threads and memory pools):
 * a scene's build time then never includes starting Embree. */
#define DEVICES 8
static struct {
  int threads;
  RTCDevice device;
} devices[DEVICES];

static RTCDevice device_for(int threads) {
  for (int d = 0; d < DEVICES; d++) {
    if (devices[d].device && devices[d].threads == threads) return devices[d].device;
    if (!devices[d].device) {
      char config[64];
      snprintf(config, sizeof config, "threads=%d", threads);
      devices[d].device = rtcNewDevice(config);
      devices[d].threads = threads;
      return devices[d].device;
    }
  }
  return NULL;
}

typedef struct job {
  RTCScene scene;
  const lt_ray *rays;
  lt_hit *hits;
  size_t begin, end;
  int any;
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
    if (j->any) {
      rtcOccluded1(j->scene, &context, &rh.ray);
      j->hits[i] = (lt_hit){rh.ray.tfar, 0, 0, rh.ray.tfar < 0 ? 0 : -1}; /* Embree marks occlusion by tfar = -inf */
      continue;
    }
    rtcIntersect1(j->scene, &context, &rh);
    int hit = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    j->hits[i] = (lt_hit){hit ? rh.ray.tfar : INFINITY, hit ? rh.hit.u : 0, hit ? rh.hit.v : 0, hit ? (int32_t)rh.hit.primID : -1};
  }
  return NULL;
}

const char *lt_embree_quality_name(lt_embree_quality quality) {
  return quality == LT_EMBREE_LOW ? "low" : quality == LT_EMBREE_HIGH ? "high" : "medium";
}

static enum RTCBuildQuality embree_quality(lt_embree_quality quality) {
  return quality == LT_EMBREE_LOW    ? RTC_BUILD_QUALITY_LOW
         : quality == LT_EMBREE_HIGH ? RTC_BUILD_QUALITY_HIGH
                                     : RTC_BUILD_QUALITY_MEDIUM;
}

lt_embree *lt_embree_build(const lt_scene *scene, int threads, double *build_ms) {
  return lt_embree_build_quality(scene, threads, LT_EMBREE_MEDIUM, build_ms);
}

lt_embree *lt_embree_build_quality(const lt_scene *scene, int threads, lt_embree_quality quality, double *build_ms) {
  lt_embree *e = calloc(1, sizeof *e);
  if (!e || !(e->device = device_for(threads))) return free(e), NULL;
  e->threads = threads < 64 ? threads : 64;

  /* Build: copy the triangles into Embree's buffers and commit, timed together. */
  double start = lt_now_ms();
  size_t n = lt_scene_triangle_count(scene);
  const float *tris = lt_scene_triangles(scene);
  RTCGeometry geometry = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *vertices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), 3 * n);
  unsigned *indices = rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), n);
  if (!vertices || !indices) return rtcReleaseGeometry(geometry), free(e), NULL;
  for (size_t i = 0; i < 9 * n; i++) vertices[i] = tris[i];
  for (size_t i = 0; i < 3 * n; i++) indices[i] = (unsigned)i;
  /* The quality is set on both the geometry (its BVH over triangles) and the scene. */
  rtcSetGeometryBuildQuality(geometry, embree_quality(quality));
  rtcCommitGeometry(geometry);
  e->scene = rtcNewScene(e->device);
  rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(e->scene, embree_quality(quality));
  rtcAttachGeometry(e->scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(e->scene);
  *build_ms = lt_now_ms() - start;
  return e;
}

double lt_embree_trace(lt_embree *e, const lt_ray *rays, size_t count, int any, lt_hit *hits) {
  /* One contiguous range of rays per thread. */
  double start = lt_now_ms();
  pthread_t workers[64];
  job jobs[64];
  for (int t = 0; t < e->threads; t++) {
    jobs[t] = (job){e->scene, rays, hits, count * t / e->threads, count * (t + 1) / e->threads, any};
    pthread_create(&workers[t], NULL, trace_range, &jobs[t]);
  }
  for (int t = 0; t < e->threads; t++) pthread_join(workers[t], NULL);
  return lt_now_ms() - start;
}

void lt_embree_release(lt_embree *e) {
  if (!e) return;
  rtcReleaseScene(e->scene);
  free(e);
}

int lt_embree_run(const lt_scene *scene, const lt_ray *rays, size_t count, int threads, lt_hit *hits,
                  lt_embree_times *times) {
  lt_embree *e = lt_embree_build(scene, threads, &times->build_ms);
  if (!e) return 1;
  times->trace_ms = lt_embree_trace(e, rays, count, 0, hits);
  lt_embree_release(e);
  return 0;
}
