/* The house generators: a furnished two-storey house of about 100k triangles, and rows and grids
 * of copies. Most triangles are in the furniture, which the walls hide from outside, so that a
 * structure built on demand has much that it never needs to build. Units are metres, y is up,
 * the footprint is x in [-5, 5] by z in [-4, 4] and the front faces -z. */
#include <math.h>

#include "runtime/error.h"
#include "gen_geometry.h"

#define HALF_X    5.0f
#define HALF_Z    4.0f
#define OUTER_T   0.25f /* outer wall thickness */
#define INNER_T   0.12f /* interior wall thickness */
#define STOREY    3.0f  /* floor to floor */
#define SLAB      0.2f  /* floor thickness between storeys */
#define STOREYS   2
#define WALL_TOP  (STOREYS * STOREY)
#define SPACING   14.0f /* between neighbouring houses, in x and in z */
#define MAX_HOLES 8

typedef struct opening {
  float x0, x1, y0, y1;
} opening;

/* The part of a wall column between heights ya and yb: the outer face, then the inner one. */
static void wall_piece(lt__gen *g, float xa, float xb, float ya, float yb, float thickness) {
  lt__gen_rect(g, 2, 0.0f, xa, ya, xb, yb, 0);
  lt__gen_rect(g, 2, thickness, xa, ya, xb, yb, 1);
}

/* One column of a wall between two hole edges: solid pieces between the holes it crosses. */
static void wall_column(lt__gen *g, float xa, float xb, float height, float thickness, const opening *holes,
                        int count) {
  const opening *in[MAX_HOLES];
  int n = 0;
  for (int i = 0; i < count; i++) {
    if (holes[i].x0 > xa || holes[i].x1 < xb) continue;
    int k = n++;
    for (; k > 0 && in[k - 1]->y0 > holes[i].y0; k--) in[k] = in[k - 1];
    in[k] = &holes[i];
  }
  float y = 0.0f;
  for (int k = 0; k < n; k++) {
    if (in[k]->y0 > y) wall_piece(g, xa, xb, y, in[k]->y0, thickness);
    y = fmaxf(y, in[k]->y1);
  }
  if (height > y) wall_piece(g, xa, xb, y, height, thickness);
}

/* A straight wall in its own frame: along +x from 0 to length, up to height, from its outer face
 * at z = 0 to its inner face at z = thickness, with rectangular holes through it. The faces are
 * cut into columns at every hole edge, so that the quads meet the holes exactly. The ends and
 * the bottom are left out because they always abut other walls or a floor. */
static void wall(lt__gen *g, float length, float height, float thickness, const opening *holes, int count, int top) {
  float xs[2 * MAX_HOLES + 2] = {0.0f, length};
  int n = 2;
  for (int i = 0; i < count; i++) {
    float edges[2] = {holes[i].x0, holes[i].x1};
    for (int e = 0; e < 2; e++) {
      int k = n++;
      for (; k > 0 && xs[k - 1] > edges[e]; k--) xs[k] = xs[k - 1];
      xs[k] = edges[e];
    }
  }
  for (int c = 0; c + 1 < n; c++)
    if (xs[c + 1] > xs[c]) wall_column(g, xs[c], xs[c + 1], height, thickness, holes, count);

  /* The reveals line each hole: jambs facing into it, the lintel, and a sill unless it is a door. */
  for (int i = 0; i < count; i++) {
    const opening *h = &holes[i];
    lt__gen_rect(g, 0, h->x0, h->y0, 0.0f, h->y1, thickness, 1);
    lt__gen_rect(g, 0, h->x1, h->y0, 0.0f, h->y1, thickness, 0);
    lt__gen_rect(g, 1, h->y1, 0.0f, h->x0, thickness, h->x1, 0);
    if (h->y0 > 0.0f) lt__gen_rect(g, 1, h->y0, 0.0f, h->x0, thickness, h->x1, 1);
  }
  if (top) lt__gen_rect(g, 1, height, 0.0f, 0.0f, thickness, length, 1);
}

static void placed_wall(lt__gen *g, float x, float y, float z, float degrees, float length, float height,
                        float thickness, const opening *holes, int count, int top) {
  lt__xform saved = lt__gen_push(g, lt__xform_place(x, y, z, degrees));
  wall(g, length, height, thickness, holes, count, top);
  g->xf = saved;
}

/* The outer walls run through both storeys; each is placed so that its inner face looks into
 * the house. Hole positions are along the wall from its placed origin. */
static void outer_walls(lt__gen *g) {
  static const opening front[] = {{6.0f, 7.0f, 0.0f, 2.2f}, {1.5f, 3.0f, 0.9f, 2.2f}, {8.0f, 9.2f, 0.9f, 2.2f},
                                  {1.5f, 3.0f, 3.9f, 5.2f}, {5.5f, 7.0f, 3.9f, 5.2f}, {8.0f, 9.2f, 3.9f, 5.2f}};
  static const opening back[] = {{1.6f, 2.5f, 0.0f, 2.2f}, {4.0f, 5.4f, 0.9f, 2.2f}, {7.0f, 8.4f, 0.9f, 2.2f},
                                 {1.2f, 2.6f, 3.9f, 5.2f}, {4.0f, 5.4f, 3.9f, 5.2f}, {7.0f, 8.4f, 3.9f, 5.2f}};
  static const opening right[] = {
      {1.2f, 2.8f, 0.9f, 2.2f}, {5.2f, 6.6f, 0.9f, 2.2f}, {1.2f, 2.8f, 3.9f, 5.2f}, {5.2f, 6.6f, 3.9f, 5.2f}};
  static const opening left[] = {
      {1.0f, 2.4f, 0.9f, 2.2f}, {4.6f, 6.2f, 0.9f, 2.2f}, {1.0f, 2.4f, 3.9f, 5.2f}, {4.6f, 6.2f, 3.9f, 5.2f}};
  float side = 2.0f * (HALF_Z - OUTER_T);
  placed_wall(g, -HALF_X, 0.0f, -HALF_Z, 0.0f, 2.0f * HALF_X, WALL_TOP, OUTER_T, front, 6, 1);
  placed_wall(g, HALF_X, 0.0f, HALF_Z, 180.0f, 2.0f * HALF_X, WALL_TOP, OUTER_T, back, 6, 1);
  placed_wall(g, HALF_X, 0.0f, -HALF_Z + OUTER_T, -90.0f, side, WALL_TOP, OUTER_T, right, 4, 1);
  placed_wall(g, -HALF_X, 0.0f, HALF_Z - OUTER_T, 90.0f, side, WALL_TOP, OUTER_T, left, 4, 1);
}

/* Per storey: one wall along z at x = -1 and two along x at z = 0.5 split the floor into four
 * rooms, each wall with a door, so that from a doorway one sees into the next rooms. */
static void interior_walls(lt__gen *g, float base) {
  static const opening along_z[] = {{1.25f, 2.15f, 0.0f, 2.1f}, {5.35f, 6.25f, 0.0f, 2.1f}};
  static const opening left[] = {{1.55f, 2.45f, 0.0f, 2.1f}};
  static const opening right[] = {{1.54f, 2.44f, 0.0f, 2.1f}};
  float height = STOREY - SLAB, inner_z = HALF_Z - OUTER_T, inner_x = HALF_X - OUTER_T;
  float x0 = -1.0f - 0.5f * INNER_T, x1 = -1.0f + 0.5f * INNER_T, z0 = 0.5f - 0.5f * INNER_T;
  placed_wall(g, x0, base, inner_z, 90.0f, 2.0f * inner_z, height, INNER_T, along_z, 2, 0);
  placed_wall(g, -inner_x, base, z0, 0.0f, x0 + inner_x, height, INNER_T, left, 1, 0);
  placed_wall(g, x1, base, z0, 0.0f, inner_x - x1, height, INNER_T, right, 1, 0);
}

/* A sheet of roof: four top corners counter-clockwise seen from above, dropped by `drop` for the
 * underside; edge faces for the sides in the mask (bit i: corners i to i+1). */
static void roof_sheet(lt__gen *g, const float top[4][3], float drop, int edges) {
  float low[4][3];
  for (int i = 0; i < 4; i++) low[i][0] = top[i][0], low[i][1] = top[i][1] - drop, low[i][2] = top[i][2];
  lt__gen_quad(g, top[0], top[1], top[2], top[3]);
  lt__gen_quad(g, low[0], low[3], low[2], low[1]);
  for (int i = 0; i < 4; i++)
    if (edges & (1 << i)) lt__gen_quad(g, top[i], low[i], low[(i + 1) % 4], top[(i + 1) % 4]);
}

/* Floors, ceilings, the gable roof, a chimney and the yard around the house. */
static void shell(lt__gen *g) {
  float ix = HALF_X - OUTER_T, iz = HALF_Z - OUTER_T, eave = 5.75f, ridge = 8.4f, rx = 5.4f, rz = 4.6f;
  outer_walls(g);
  for (int s = 0; s < STOREYS; s++) interior_walls(g, s * STOREY);

  /* The ground slab shows a plinth; the upper floors have only their top and underside, as
   * their edges are buried in the outer walls. */
  lt__gen_box(g, -HALF_X - 0.1f, -0.15f, -HALF_Z - 0.1f, HALF_X + 0.1f, 0.0f, HALF_Z + 0.1f);
  for (int s = 1; s <= STOREYS; s++) {
    lt__gen_rect(g, 1, s * STOREY - SLAB, -iz, -ix, iz, ix, 0);
    lt__gen_rect(g, 1, s * STOREY, -iz, -ix, iz, ix, 1);
  }

  /* Two roof slopes meeting at the ridge along x, gable triangles closing the attic. */
  const float front[4][3] = {{-rx, eave, -rz}, {-rx, ridge, 0}, {rx, ridge, 0}, {rx, eave, -rz}};
  const float back[4][3] = {{-rx, ridge, 0}, {-rx, eave, rz}, {rx, eave, rz}, {rx, ridge, 0}};
  roof_sheet(g, front, 0.15f, 1 | 4 | 8);
  roof_sheet(g, back, 0.15f, 1 | 2 | 4);
  for (int side = -1; side <= 1; side += 2) {
    float a[3] = {side * HALF_X, WALL_TOP, -HALF_Z}, b[3] = {side * HALF_X, WALL_TOP, HALF_Z};
    float c[3] = {side * HALF_X, ridge - 0.15f, 0.0f};
    lt__gen_tri(g, a, side < 0 ? b : c, side < 0 ? c : b);
  }
  lt__gen_box(g, 2.4f, 6.5f, 1.0f, 3.0f, 9.3f, 1.6f);

  /* The yard: a frame of ground around the plinth, so neighbouring houses' yards tile. */
  float h = 0.5f * SPACING, px = HALF_X + 0.1f, pz = HALF_Z + 0.1f, y = -0.15f;
  lt__gen_rect(g, 1, y, -h, -h, -pz, h, 1);
  lt__gen_rect(g, 1, y, pz, -h, h, h, 1);
  lt__gen_rect(g, 1, y, -pz, -h, pz, -px, 1);
  lt__gen_rect(g, 1, y, -pz, px, pz, h, 1);
}

/* A chair in its own frame: the sitter faces -z, the back is at +z. */
static void chair(lt__gen *g) {
  lt__gen_box(g, -0.22f, 0.44f, -0.22f, 0.22f, 0.48f, 0.22f);
  for (int i = 0; i < 4; i++) {
    float x = (i & 1) ? 0.18f : -0.22f, z = (i & 2) ? 0.18f : -0.22f;
    lt__gen_box(g, x, 0.0f, z, x + 0.04f, 0.44f, z + 0.04f);
  }
  lt__gen_box(g, -0.22f, 0.48f, 0.18f, 0.22f, 0.95f, 0.22f);
}

/* A hollow vase on the table: outer wall up, lip, inner wall down to a floor. */
static void vase(lt__gen *g, lt__rng *rng) {
  enum { STEPS = 12 };
  float profile[2 * STEPS + 3][2], h = lt__rng_range(rng, 0.25f, 0.4f), r = lt__rng_range(rng, 0.05f, 0.08f);
  float bulge = lt__rng_range(rng, 0.3f, 0.7f), wall_t = 0.008f;
  int n = 0;
  profile[n][0] = 0.0f, profile[n++][1] = 0.0f;
  for (int i = 0; i <= STEPS; i++) {
    float t = (float)i / STEPS, c, s;
    lt__sincos(3.0 * t, &c, &s);
    profile[n][0] = r * (0.6f + bulge * s * (1.0f - 0.5f * t)), profile[n++][1] = h * t;
  }
  for (int i = STEPS; i >= 1; i--) profile[n][0] = profile[i + 1][0] - wall_t, profile[n++][1] = profile[i + 1][1];
  profile[n][0] = 0.0f, profile[n][1] = profile[n - 1][1], n++;
  lt__gen_lathe(g, (const float(*)[2])profile, n, 32);
}

/* A bowl of fruit: a hemispherical shell with five small spheres in it. */
static void fruit_bowl(lt__gen *g) {
  enum { STEPS = 6 };
  float profile[2 * STEPS + 2][2], R = 0.12f;
  int n = 0;
  profile[n][0] = 0.0f, profile[n++][1] = 0.0f;
  for (int i = 1; i <= STEPS; i++) {
    float c, s;
    lt__sincos(0.5 * LT_GEN_PI * ((double)i / STEPS - 1.0), &c, &s);
    profile[n][0] = R * c, profile[n++][1] = R + R * s;
  }
  for (int i = STEPS; i >= 1; i--)
    profile[n][0] = profile[i][0] * 0.92f, profile[n++][1] = profile[i][1] * 0.92f + 0.01f;
  profile[n][0] = 0.0f, profile[n][1] = profile[n - 1][1], n++;
  lt__gen_lathe(g, (const float(*)[2])profile, n, 32);
  lt__gen_uv_sphere(g, 0.0f, 0.05f, 0.0f, 0.035f, 10, 14);
  for (int i = 0; i < 4; i++) {
    float c, s;
    lt__sincos(0.5 * LT_GEN_PI * i, &c, &s);
    lt__gen_uv_sphere(g, 0.055f * c, 0.065f, 0.055f * s, 0.035f, 10, 14);
  }
}

/* A table with four chairs facing it, a vase and a fruit bowl. */
static void dining(lt__gen *g, lt__rng *rng) {
  lt__gen_box(g, -0.7f, 0.72f, -0.4f, 0.7f, 0.77f, 0.4f);
  for (int i = 0; i < 4; i++) {
    lt__xform saved = lt__gen_push(g, lt__xform_place((i & 1) ? 0.62f : -0.62f, 0.0f, (i & 2) ? 0.32f : -0.32f, 0));
    lt__gen_cylinder(g, 0.03f, 0.0f, 0.72f, 16);
    g->xf = saved;
  }
  for (int i = 0; i < 4; i++) {
    float z = (i & 2) ? 0.75f : -0.75f;
    lt__xform saved = lt__gen_push(g, lt__xform_place((i & 1) ? 0.35f : -0.35f, 0.0f, z, z < 0 ? 180.0f : 0.0f));
    chair(g);
    g->xf = saved;
  }

  /* Random numbers are drawn one statement at a time: the order in which a call's arguments
   * are evaluated differs between compilers, and so would the scene. */
  float x = lt__rng_range(rng, -0.45f, -0.2f), z = lt__rng_range(rng, -0.15f, 0.15f);
  lt__xform saved = lt__gen_push(g, lt__xform_place(x, 0.77f, z, 0.0f));
  vase(g, rng);
  g->xf = saved;
  x = lt__rng_range(rng, 0.2f, 0.45f);
  z = lt__rng_range(rng, -0.15f, 0.15f);
  lt__gen_push(g, lt__xform_place(x, 0.77f, z, 0.0f));
  fruit_bowl(g);
  g->xf = saved;
}

/* A floor lamp: weighted base, thin stem, open conical shade with a bulb inside. */
static void floor_lamp(lt__gen *g) {
  static const float shade[5][2] = {{0.22f, 1.35f}, {0.12f, 1.6f}, {0.115f, 1.6f}, {0.215f, 1.35f}, {0.22f, 1.35f}};
  lt__gen_cylinder(g, 0.16f, 0.0f, 0.03f, 32);
  lt__gen_cylinder(g, 0.012f, 0.03f, 1.45f, 12);
  lt__gen_lathe(g, shade, 5, 48);
  lt__gen_uv_sphere(g, 0.0f, 1.42f, 0.0f, 0.05f, 12, 16);
}

/* A potted plant: a pot with a rolled rim, soil, and a bush of overlapping spheres. */
static void potted_plant(lt__gen *g, lt__rng *rng) {
  static const float pot[6][2] = {{0, 0}, {0.14f, 0}, {0.2f, 0.35f}, {0.185f, 0.35f}, {0.175f, 0.3f}, {0, 0.3f}};
  lt__gen_lathe(g, pot, 6, 48);
  lt__xform saved = lt__gen_push(g, lt__xform_place(0.0f, 0.35f, 0.0f, 0.0f));
  lt__gen_torus(g, 0.195f, 0.02f, 48, 12);
  g->xf = saved;
  for (int i = 0; i < 4; i++) {
    float x = lt__rng_range(rng, -0.1f, 0.1f), y = lt__rng_range(rng, 0.5f, 0.8f);
    float z = lt__rng_range(rng, -0.1f, 0.1f), r = lt__rng_range(rng, 0.15f, 0.22f);
    lt__gen_uv_sphere(g, x, y, z, r, 14, 20);
  }
}

/* A low cabinet against a wall with books, a torus sculpture and a globe on a stand on top. */
static void cabinet(lt__gen *g, lt__rng *rng) {
  lt__gen_box(g, -0.2f, 0.0f, -0.6f, 0.2f, 0.9f, 0.6f);
  float z = -0.55f;
  for (int i = 0; i < 10; i++) {
    float w = lt__rng_range(rng, 0.02f, 0.05f), h = lt__rng_range(rng, 0.18f, 0.28f);
    lt__gen_box(g, -0.1f, 0.9f, z, 0.1f, 0.9f + h, z + w);
    z += w + 0.002f;
  }
  lt__xform saved = lt__gen_push(g, lt__xform_place(0.0f, 0.93f, 0.15f, 0.0f));
  lt__gen_torus(g, 0.09f, 0.03f, 64, 16);
  g->xf = saved;
  lt__gen_push(g, lt__xform_place(0.0f, 0.0f, 0.4f, 0.0f));
  lt__gen_cylinder(g, 0.01f, 0.9f, 1.1f, 12);
  lt__gen_uv_sphere(g, 0.0f, 1.2f, 0.0f, 0.1f, 24, 32);
  g->xf = saved;
}

/* Furnishes the room x0..x1 by z0..z1 on the floor at height y; the layout is turned half round
 * in some rooms so that the houses do not all look alike from a doorway. */
static void furnish(lt__gen *g, lt__rng *rng, float x0, float z0, float x1, float z1, float y) {
  float hw = 0.5f * (x1 - x0), hd = 0.5f * (z1 - z0), turn = (lt__rng_next(rng) & 1) ? 180.0f : 0.0f;
  lt__xform room = lt__gen_push(g, lt__xform_place(0.5f * (x0 + x1), y, 0.5f * (z0 + z1), turn));
  lt__xform saved = lt__gen_push(g, lt__xform_place(lt__rng_range(rng, -0.2f, 0.2f), 0.0f, 0.0f, 0.0f));
  dining(g, rng);
  g->xf = saved;
  lt__gen_push(g, lt__xform_place(-hw + 0.35f, 0.0f, -hd + 0.35f, 0.0f));
  floor_lamp(g);
  g->xf = saved;
  lt__gen_push(g, lt__xform_place(-hw + 0.35f, 0.0f, hd - 0.35f, 0.0f));
  potted_plant(g, rng);
  g->xf = saved;
  lt__gen_push(g, lt__xform_place(hw - 0.25f, 0.0f, lt__rng_range(rng, -0.5f, 0.5f), 0.0f));
  cabinet(g, rng);
  g->xf = room;
}

/* One house at the current placement; seed varies the furnishing between copies. */
static void house(lt__gen *g, uint64_t seed) {
  lt__rng rng = {seed * 0x2545f4914f6cdd1dull + 1};
  float ix = HALF_X - OUTER_T, iz = HALF_Z - OUTER_T, a = -1.0f - 0.5f * INNER_T, b = -1.0f + 0.5f * INNER_T;
  float c = 0.5f - 0.5f * INNER_T, d = 0.5f + 0.5f * INNER_T;
  shell(g);
  for (int s = 0; s < STOREYS; s++) {
    float y = s * STOREY;
    furnish(g, &rng, -ix, -iz, a, c, y);
    furnish(g, &rng, b, -iz, ix, c, y);
    furnish(g, &rng, -ix, d, a, iz, y);
    furnish(g, &rng, b, d, ix, iz, y);
  }
}

lt_status lt__gen_houses(lt_scene *scene, int rows, int columns, int style) {
  lt__gen g;
  lt__gen_init(&g, scene);
  float left = -0.5f * (columns - 1) * SPACING, door_x = 1.5f;
  int middle = (columns - 1) / 2;

  /* The outer camera comes first, so that it is the default. A row is seen level along +z, so
   * the first house hides the rest; a grid from far enough and high enough to frame the front
   * row whole (assuming an image at least as wide as tall) with roofs behind it. */
  if (style == LT_HOUSES_ROW) {
    const float eye[3] = {0.0f, 3.0f, -20.0f}, look[3] = {0.0f, 3.5f, 0.0f};
    lt__gen_camera(&g, "outer", eye, look, 50.0f);
  } else {
    float dist = fmaxf(20.0f, (0.5f * SPACING * columns) / tanf(25.0f * (float)LT_GEN_PI / 180.0f));
    const float eye[3] = {0.0f, 4.0f + 0.25f * dist, -HALF_Z - dist}, look[3] = {0.0f, 2.0f, HALF_Z};
    lt__gen_camera(&g, "outer", eye, look, 50.0f);
  }
  const float close_eye[3] = {left + middle * SPACING + door_x, 1.6f, -3.4f};
  const float close_look[3] = {left + middle * SPACING - 0.5f, 1.1f, 2.5f};
  lt__gen_camera(&g, "close", close_eye, close_look, 70.0f);

  /* Houses row by row from the front, so that triangle numbers grow away from the camera. */
  for (int r = 0; r < rows; r++)
    for (int c = 0; c < columns; c++) {
      lt__xform saved = lt__gen_push(&g, lt__xform_place(left + c * SPACING, 0.0f, r * SPACING, 0.0f));
      house(&g, (uint64_t)r * (uint64_t)columns + (uint64_t)c);
      g.xf = saved;
    }
  return g.status;
}
