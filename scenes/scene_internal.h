/* The scene as the library holds it: a flat triangle soup in triangle-number order plus named
 * cameras. Generators and loaders append to it through the helpers below. */
#ifndef LT_SCENE_INTERNAL_H
#define LT_SCENE_INTERNAL_H

#include "lazytrace.h"

#define LT_SCENE_MAX_CAMERAS 8

struct lt_scene {
  float *tris;           /* 9 floats per triangle: v0 v1 v2 */
  size_t count;          /* triangles */
  size_t capacity;       /* triangles the tris buffer holds */
  size_t skipped;        /* triangles dropped for NaN or infinite coordinates */
  int camera_count;
  int active_camera;     /* index into cameras, or -1 for "frame the bounds" */
  char camera_names[LT_SCENE_MAX_CAMERAS][16];
  lt_camera cameras[LT_SCENE_MAX_CAMERAS];
  struct lt__scene_desc *desc; /* materials, lights, effects; NULL: the default description */
  struct lt__motion *motion;   /* how the triangles move with time; NULL: they do not */
};

/* ---- Motion (scene_motion.c) ---- */

/* A rigid pose at a time from 0 to 1: scale, then turn about y (degrees), then translate. */
typedef struct lt__pose {
  float time, translate[3], rotate_y, scale;
} lt__pose;

/* Floats per triangle of an explosion: velocity (3), spin axis (3, unit), spin rate (radians
 * per unit of time), fall (downward acceleration). */
#define LT_BURST_FLOATS 8

/* Triangles first .. first + count - 1 of the scene move together: each starts from its rest
 * shape (mesh space), flies apart by its burst (if any), then takes the interpolated pose. */
typedef struct lt__mover {
  size_t first, count;
  float *rest;    /* 9 floats per triangle */
  float *burst;   /* LT_BURST_FLOATS per triangle, or NULL: no explosion */
  lt__pose *keys; /* by strictly increasing time; at least one */
  int key_count;
} lt__mover;

typedef struct lt__motion {
  lt__mover *movers;
  int count, capacity;
} lt__motion;

/* A pose's turn about y as its cosine and sine, computed once for all the points it moves. */
typedef struct lt__pose_turn {
  float c, s;
} lt__pose_turn;
lt__pose_turn lt__pose_turn_of(const lt__pose *pose);
/* Moves the point p (mesh space) by the pose, whose turn is `turn`, into out; the arithmetic a
 * static instance has always used, so that a pose written once places triangles where it
 * always did. */
void lt__pose_apply(const lt__pose *pose, lt__pose_turn turn, const float p[3], float out[3]);
/* Adds a mover over triangles first .. first + count - 1 with copies of rest (9 floats per
 * triangle), burst (LT_BURST_FLOATS per triangle, or NULL) and keys. */
lt_status lt__motion_add(lt_scene *scene, size_t first, size_t count, const float *rest, const float *burst,
                         const lt__pose *keys, int key_count);
/* Makes every triangle of the scene fly apart from the centre of its bounds over time
 * (explode:BASE); the directions, speeds and spins derive from a fixed seed. */
lt_status lt__motion_explode(lt_scene *scene);
void lt__motion_free(struct lt__motion *motion);

/* The line (from 1) of the value at a key path such as "instances[2].keyframes[1].time" in a
 * JSON text that parsed; where the path leaves the text, the line of the deepest value found. */
int lt__json_line(const char *text, const char *path);

/* What a scene file says beyond the triangles (scene_desc.c holds the defaults). */
typedef struct lt__scene_desc {
  lt_material *materials; /* at least one */
  size_t material_count;
  int *tri_material;      /* one per triangle, or NULL: all material 0 */
  lt_light *lights;
  size_t light_count;
  float background[3];
  int width, height, spp; /* 0: not given */
  lt_effects effects;
} lt__scene_desc;

/* The default description: one grey diffuse material, no lights, primary rays only. */
void lt__scene_desc_defaults(lt__scene_desc *desc);
void lt__scene_desc_free(lt__scene_desc *desc);

/* A new, empty scene; NULL when out of memory. */
lt_scene *lt__scene_new(void);
/* Appends one triangle; a triangle with a non-finite coordinate is counted as skipped. */
lt_status lt__scene_add_tri(lt_scene *scene, const float a[3], const float b[3], const float c[3]);
/* Appends a quad a b c d (counter-clockwise) as triangles (a b c) and (a c d). */
lt_status lt__scene_add_quad(lt_scene *scene, const float a[3], const float b[3], const float c[3],
                             const float d[3]);
/* Adds a named camera (the first added is the default). */
lt_status lt__scene_add_camera(lt_scene *scene, const char *name, lt_camera camera);

/* Generators: name is the part of the spec before ':', args the part after it (or NULL).
 * Appends the generator's triangles and its "outer" and "close" cameras to scene.
 * LT_ERROR_UNKNOWN_GENERATOR for an unknown name, LT_ERROR_INVALID_ARGUMENT for bad args. */
lt_status lt__generate(const char *name, const char *args, lt_scene *scene);

/* Mesh readers. The OBJ and PLY readers are lazytrace's own, so triangle numbering follows the
 * contract (faces in file order, polygons fanned as (v0, vi, vi+1)) and errors name the line
 * (or, in a binary PLY body, the element, item and byte offset). */
lt_status lt__load_obj(const char *path, lt_scene *scene);
lt_status lt__load_ply(const char *path, lt_scene *scene);
/* Other formats through assimp. */
lt_status lt__load_assimp(const char *path, lt_scene *scene);
/* A scene file (.json): meshes placed by instances, materials, lights, camera, image, effects.
 * Errors name the file, the key and what was expected. */
lt_status lt__load_scene_file(const char *path, lt_scene *scene);

#endif
