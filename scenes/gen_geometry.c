/* Primitives for the scene generators. Every vertex goes through the generator's placement,
 * and a vertex shared by neighbouring triangles is computed from the same inputs each time, so
 * the shapes are closed bit for bit where the tessellation says they are. */
#include "gen_geometry.h"

#include <math.h>
#include <string.h>

#include "scenes/splitmix.h"

uint64_t lt__rng_next(lt__rng *rng) { return lt__splitmix_next(&rng->state); }

float lt__rng_range(lt__rng *rng, float lo, float hi) { return lo + (hi - lo) * lt__splitmix_unit(&rng->state); }

lt__xform lt__xform_identity(void) { return lt__xform_place(0.0f, 0.0f, 0.0f, 0.0f); }

void lt__sincos(double radians, float *c, float *s) {
  *c = (float)cos(radians);
  *s = (float)sin(radians);
}

lt__xform lt__xform_place(float x, float y, float z, float degrees) {
  float c, s;
  double quarters = degrees / 90.0;

  /* Quarter turns are exact, so walls turned to face each way meet without gaps. */
  if (quarters == floor(quarters)) {
    static const float qc[4] = {1, 0, -1, 0}, qs[4] = {0, 1, 0, -1};
    int q = ((int)quarters % 4 + 4) % 4;
    c = qc[q], s = qs[q];
  } else {
    lt__sincos(degrees * LT_GEN_PI / 180.0, &c, &s);
  }
  lt__xform xf = {{{c, 0, s, x}, {0, 1, 0, y}, {-s, 0, c, z}}};
  return xf;
}

lt__xform lt__xform_scale(float sx, float sy, float sz) {
  lt__xform xf = {{{sx, 0, 0, 0}, {0, sy, 0, 0}, {0, 0, sz, 0}}};
  return xf;
}

lt__xform lt__xform_mul(const lt__xform *a, const lt__xform *b) {
  lt__xform out;
  for (int i = 0; i < 3; i++) {
    for (int j = 0; j < 4; j++)
      out.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j];
    out.m[i][3] += a->m[i][3];
  }
  return out;
}

void lt__gen_init(lt__gen *gen, lt_scene *scene) {
  gen->scene = scene;
  gen->xf = lt__xform_identity();
  gen->status = LT_OK;
}

void lt__gen_camera(lt__gen *gen, const char *name, const float eye[3], const float look[3], float fov_deg) {
  lt_camera camera = {{eye[0], eye[1], eye[2]}, {look[0], look[1], look[2]}, {0, 1, 0}, fov_deg};
  if (!gen->status) gen->status = lt__scene_add_camera(gen->scene, name, camera);
}

lt__xform lt__gen_push(lt__gen *gen, lt__xform local) {
  lt__xform saved = gen->xf;
  gen->xf = lt__xform_mul(&saved, &local);
  return saved;
}

static void apply(const lt__xform *xf, const float p[3], float out[3]) {
  for (int i = 0; i < 3; i++) out[i] = xf->m[i][0] * p[0] + xf->m[i][1] * p[1] + xf->m[i][2] * p[2] + xf->m[i][3];
}

void lt__gen_tri(lt__gen *gen, const float a[3], const float b[3], const float c[3]) {
  if (gen->status) return;
  float ta[3], tb[3], tc[3];
  apply(&gen->xf, a, ta);
  apply(&gen->xf, b, tb);
  apply(&gen->xf, c, tc);
  gen->status = lt__scene_add_tri(gen->scene, ta, tb, tc);
}

void lt__gen_quad(lt__gen *gen, const float a[3], const float b[3], const float c[3], const float d[3]) {
  lt__gen_tri(gen, a, b, c);
  lt__gen_tri(gen, a, c, d);
}

void lt__gen_rect(lt__gen *gen, int axis, float at, float u0, float v0, float u1, float v1, int positive) {
  int u = (axis + 1) % 3, v = (axis + 2) % 3;
  float p[4][3];
  for (int i = 0; i < 4; i++) p[i][axis] = at;
  p[0][u] = u0, p[0][v] = v0;
  p[1][u] = u1, p[1][v] = v0;
  p[2][u] = u1, p[2][v] = v1;
  p[3][u] = u0, p[3][v] = v1;

  /* u x v is +axis, so the corners in this order face +axis; reversed they face -axis. */
  if (positive)
    lt__gen_quad(gen, p[0], p[1], p[2], p[3]);
  else
    lt__gen_quad(gen, p[0], p[3], p[2], p[1]);
}

void lt__gen_box(lt__gen *gen, float x0, float y0, float z0, float x1, float y1, float z1) {
  lt__gen_rect(gen, 0, x0, y0, z0, y1, z1, 0);
  lt__gen_rect(gen, 0, x1, y0, z0, y1, z1, 1);
  lt__gen_rect(gen, 1, y0, z0, x0, z1, x1, 0);
  lt__gen_rect(gen, 1, y1, z0, x0, z1, x1, 1);
  lt__gen_rect(gen, 2, z0, x0, y0, x1, y1, 0);
  lt__gen_rect(gen, 2, z1, x0, y0, x1, y1, 1);
}

void lt__gen_lathe(lt__gen *gen, const float (*profile)[2], int points, int slices) {
  if (slices < 3 || slices > LT_GEN_MAX_SLICES || points < 2) return;
  float cs[LT_GEN_MAX_SLICES + 1], sn[LT_GEN_MAX_SLICES + 1];
  for (int j = 0; j < slices; j++) lt__sincos(2.0 * LT_GEN_PI * j / slices, &cs[j], &sn[j]);
  cs[slices] = cs[0], sn[slices] = sn[0];

  for (int i = 0; i + 1 < points; i++) {
    float r0 = profile[i][0], y0 = profile[i][1], r1 = profile[i + 1][0], y1 = profile[i + 1][1];
    if (r0 == 0.0f && r1 == 0.0f) continue;
    for (int j = 0; j < slices; j++) {
      float a[3] = {r0 * cs[j], y0, r0 * sn[j]}, b[3] = {r1 * cs[j], y1, r1 * sn[j]};
      float c[3] = {r1 * cs[j + 1], y1, r1 * sn[j + 1]}, d[3] = {r0 * cs[j + 1], y0, r0 * sn[j + 1]};

      /* A point on the axis makes the quad a triangle; emitting it whole would add a
       * zero-area triangle. */
      if (r0 == 0.0f)
        lt__gen_tri(gen, a, b, c);
      else if (r1 == 0.0f)
        lt__gen_tri(gen, a, b, d);
      else
        lt__gen_quad(gen, a, b, c, d);
    }
  }
}

void lt__gen_cylinder(lt__gen *gen, float radius, float y0, float y1, int sides) {
  const float profile[4][2] = {{0, y0}, {radius, y0}, {radius, y1}, {0, y1}};
  lt__gen_lathe(gen, profile, 4, sides);
}

void lt__gen_uv_sphere(lt__gen *gen, float cx, float cy, float cz, float radius, int stacks, int slices) {
  float profile[LT_GEN_MAX_PROFILE][2];
  if (stacks < 2 || stacks >= LT_GEN_MAX_PROFILE) return;
  for (int i = 0; i <= stacks; i++) {
    float c, s;
    lt__sincos(LT_GEN_PI * i / stacks, &c, &s);
    profile[i][0] = (i == 0 || i == stacks) ? 0.0f : radius * s;
    profile[i][1] = -radius * c;
  }
  lt__xform saved = lt__gen_push(gen, lt__xform_place(cx, cy, cz, 0.0f));
  lt__gen_lathe(gen, (const float(*)[2])profile, stacks + 1, slices);
  gen->xf = saved;
}

void lt__gen_torus(lt__gen *gen, float major, float minor, int major_segments, int minor_segments) {
  float profile[LT_GEN_MAX_PROFILE][2];
  if (minor_segments < 3 || minor_segments >= LT_GEN_MAX_PROFILE) return;

  /* The cross section starts at the bottom and turns outward first, so the outside stays on
   * the right; the last point repeats the first to close the ring exactly. */
  for (int i = 0; i < minor_segments; i++) {
    float c, s;
    lt__sincos(2.0 * LT_GEN_PI * i / minor_segments - 0.5 * LT_GEN_PI, &c, &s);
    profile[i][0] = major + minor * c;
    profile[i][1] = minor * s;
  }
  profile[minor_segments][0] = profile[0][0];
  profile[minor_segments][1] = profile[0][1];
  lt__gen_lathe(gen, (const float(*)[2])profile, minor_segments + 1, major_segments);
}

static void normalize(float v[3]) {
  float len = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (len > 0.0f)
    for (int k = 0; k < 3; k++) v[k] /= len;
}

static void cross(const float a[3], const float b[3], float out[3]) {
  out[0] = a[1] * b[2] - a[2] * b[1];
  out[1] = a[2] * b[0] - a[0] * b[2];
  out[2] = a[0] * b[1] - a[1] * b[0];
}

/* The tangent at path point i: central differences inside, one-sided at the ends. */
static void tangent_at(const float (*path)[3], int points, int i, float t[3]) {
  int lo = i > 0 ? i - 1 : 0, hi = i + 1 < points ? i + 1 : points - 1;
  for (int k = 0; k < 3; k++) t[k] = path[hi][k] - path[lo][k];
  normalize(t);
}

/* Turns the previous normal into the plane across tangent t (parallel transport), falling back
 * to any perpendicular when the path doubles back on itself. */
static void transport_normal(const float t[3], float n[3]) {
  float d = n[0] * t[0] + n[1] * t[1] + n[2] * t[2];
  for (int k = 0; k < 3; k++) n[k] -= d * t[k];
  if (n[0] * n[0] + n[1] * n[1] + n[2] * n[2] < 1e-8f) {
    float axis[3] = {0, 0, 0};
    axis[fabsf(t[0]) < 0.6f ? 0 : 1] = 1.0f;
    cross(t, axis, n);
  }
  normalize(n);
}

/* The cross section of the tube at path point i, in the frame (n, t x n). */
static void ring_at(const float p[3], const float t[3], const float n[3], float radius, int sides, const float *cs,
                    const float *sn, float (*ring)[3]) {
  float b[3];
  cross(t, n, b);
  for (int j = 0; j < sides; j++)
    for (int k = 0; k < 3; k++) ring[j][k] = p[k] + radius * (cs[j] * n[k] + sn[j] * b[k]);
  memcpy(ring[sides], ring[0], sizeof ring[0]);
}

/* A fan over one end of the tube; the far end is wound the other way round. */
static void cap(lt__gen *gen, const float (*ring)[3], int sides, int far_end) {
  for (int j = 1; j + 1 < sides; j++) {
    if (far_end)
      lt__gen_tri(gen, ring[0], ring[j], ring[j + 1]);
    else
      lt__gen_tri(gen, ring[0], ring[j + 1], ring[j]);
  }
}

void lt__gen_tube(lt__gen *gen, const float (*path)[3], int points, float radius, int sides, int capped) {
  enum { MAX_SIDES = 64 };
  if (points < 2 || sides < 3 || sides > MAX_SIDES) return;
  float cs[MAX_SIDES], sn[MAX_SIDES], rings[2][MAX_SIDES + 1][3], t[3], n[3] = {0, 0, 0};
  for (int j = 0; j < sides; j++) lt__sincos(2.0 * LT_GEN_PI * j / sides, &cs[j], &sn[j]);

  /* Walk the path, keeping the previous cross section to join to the next one. */
  for (int i = 0; i < points; i++) {
    float(*ring)[3] = rings[i & 1];
    const float(*prev)[3] = (const float(*)[3])rings[(i + 1) & 1];
    tangent_at(path, points, i, t);
    transport_normal(t, n);
    ring_at(path[i], t, n, radius, sides, cs, sn, ring);
    if (i == 0 && capped) cap(gen, (const float(*)[3])ring, sides, 0);
    if (i > 0)
      for (int j = 0; j < sides; j++) lt__gen_quad(gen, prev[j], prev[j + 1], ring[j + 1], ring[j]);
  }
  if (capped) cap(gen, (const float(*)[3])rings[(points - 1) & 1], sides, 1);
}
