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
};

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
