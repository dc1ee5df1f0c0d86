/* Scene files (.json, read with cJSON): meshes from files or generators, instances that place
 * them with a transform and a material, materials, lights, camera, image and the effects to
 * simulate. Every error names the file, the key (as a path: "instances[2].translate") and what
 * was expected, and unknown keys are refused, so that a typo never passes silently. */
#include <cjson/cJSON.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"
#include "scenes/scene_internal.h"

#define KEY_SIZE 96
#define FILE_MAX (256u << 20) /* a scene file larger than this is surely not one */

typedef struct reader {
  const char *path;
  const char *text; /* the file's text, for the line of a key in messages */
  char dir[1024]; /* the scene file's directory, for mesh paths relative to it */
  lt_scene *scene;
  lt__scene_desc *desc;
  size_t tri_capacity; /* entries desc->tri_material holds */
} reader;

/* ---- Messages ---- */

/* What a JSON value is, for "expected X, got Y". */
static const char *describe(const cJSON *v, char *buf, size_t size) {
  if (!v) return "nothing";
  if (cJSON_IsNumber(v)) return snprintf(buf, size, "the number %g", v->valuedouble), buf;
  if (cJSON_IsString(v)) return snprintf(buf, size, "the string \"%.40s\"", v->valuestring), buf;
  if (cJSON_IsArray(v)) return snprintf(buf, size, "an array of %d", cJSON_GetArraySize(v)), buf;
  if (cJSON_IsObject(v)) return "an object";
  if (cJSON_IsBool(v)) return cJSON_IsTrue(v) ? "true" : "false";
  return "null";
}

/* The line of a key path in the file. */
static int line_of(const reader *r, const char *key) { return lt__json_line(r->text, key); }

static lt_status expected(const reader *r, const char *key, const char *what, const cJSON *got) {
  char buf[96];
  return lt__fail(LT_ERROR_PARSE, "%s:%d: %s: expected %s, got %s", r->path, line_of(r, key), key, what,
                  describe(got, buf, sizeof buf));
}

/* Refuses keys of obj that are not in known (a NULL-terminated list). */
static lt_status known_keys(const reader *r, const cJSON *obj, const char *where, const char *const *known) {
  const cJSON *item;
  cJSON_ArrayForEach(item, obj) {
    int found = 0;
    for (int i = 0; known[i]; i++) found |= strcmp(item->string, known[i]) == 0;
    if (found) continue;
    char list[256] = "";
    for (int i = 0; known[i]; i++)
      snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", known[i]);
    char key[KEY_SIZE];
    snprintf(key, sizeof key, "%s%s%s", where, *where ? "." : "", item->string);
    return lt__fail(LT_ERROR_PARSE, "%s:%d: %s%sunknown key '%s' (expected one of: %s)", r->path, line_of(r, key),
                    where, *where ? ": " : "", item->string, list);
  }
  return LT_OK;
}

/* where.name (or name at the top level) into key, cut to KEY_SIZE. */
static const char *join(char key[KEY_SIZE], const char *where, const char *name) {
  size_t n = 0;
  for (const char *parts[3] = {where, *where ? "." : "", name}, **part = parts; part < parts + 3; part++)
    for (const char *c = *part; *c && n + 1 < KEY_SIZE; c++) key[n++] = *c;
  key[n] = '\0';
  return key;
}

/* ---- Values ---- */

/* A number in [lo, hi] under name, or the default when absent. */
static lt_status number(const reader *r, const cJSON *obj, const char *where, const char *name, double lo, double hi,
                        double fallback, double *out) {
  char key[KEY_SIZE], what[96];
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
  *out = fallback;
  if (!v) return LT_OK;
  join(key, where, name);
  snprintf(what, sizeof what, "a number from %g to %g", lo, hi);
  if (!cJSON_IsNumber(v) || !(v->valuedouble >= lo && v->valuedouble <= hi)) return expected(r, key, what, v);
  *out = v->valuedouble;
  return LT_OK;
}

/* A whole number in [lo, hi] under name, or the default when absent. */
static lt_status integer(const reader *r, const cJSON *obj, const char *where, const char *name, int lo, int hi,
                         int fallback, int *out) {
  char key[KEY_SIZE], what[96];
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
  *out = fallback;
  if (!v) return LT_OK;
  join(key, where, name);
  snprintf(what, sizeof what, "a whole number from %d to %d", lo, hi);
  if (!cJSON_IsNumber(v) || v->valuedouble != floor(v->valuedouble) || v->valuedouble < lo || v->valuedouble > hi)
    return expected(r, key, what, v);
  *out = (int)v->valuedouble;
  return LT_OK;
}

/* Three finite numbers (each in [lo, hi]) under name; the default when absent unless required. */
static lt_status vec3(const reader *r, const cJSON *obj, const char *where, const char *name, double lo, double hi,
                      const float *fallback, float out[3]) {
  char key[KEY_SIZE], what[128];
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(obj, name);
  join(key, where, name);
  if (isinf(lo)) snprintf(what, sizeof what, "an array of 3 finite numbers");
  else snprintf(what, sizeof what, "an array of 3 numbers from %g to %g", lo, hi);
  if (!v) {
    if (!fallback) return expected(r, key, what, v);
    memcpy(out, fallback, 3 * sizeof *out);
    return LT_OK;
  }
  if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != 3) return expected(r, key, what, v);
  for (int k = 0; k < 3; k++) {
    const cJSON *x = cJSON_GetArrayItem(v, k);
    if (!cJSON_IsNumber(x) || !isfinite(x->valuedouble) || x->valuedouble < lo || x->valuedouble > hi)
      return expected(r, key, what, v);
    out[k] = (float)x->valuedouble;
  }
  return LT_OK;
}

static const cJSON *array_of(const reader *r, const cJSON *root, const char *name, lt_status *status) {
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, name);
  *status = LT_OK;
  if (v && !cJSON_IsArray(v)) *status = expected(r, name, "an array of objects", v);
  return v;
}

static lt_status element_object(const reader *r, const cJSON *item, const char *key) {
  return cJSON_IsObject(item) ? LT_OK : expected(r, key, "an object", item);
}

/* ---- Meshes and instances ---- */

/* A loader's or generator's error, prefixed with the scene file and the key. */
static lt_status wrap(const reader *r, const char *key, lt_status status) {
  char inner[512];
  snprintf(inner, sizeof inner, "%s", lt_last_error());
  return lt__fail(status, "%s:%d: %s: %s", r->path, line_of(r, key), key, inner);
}

/* One mesh as a scene of its own: a generator spec or a file relative to the scene file. */
static lt_status load_mesh(const reader *r, const cJSON *item, int index, lt_scene **out) {
  static const char *const keys[] = {"generator", "file", NULL};
  char key[KEY_SIZE];
  snprintf(key, sizeof key, "meshes[%d]", index);
  lt_status status = element_object(r, item, key);
  if (!status) status = known_keys(r, item, key, keys);
  if (status) return status;
  const cJSON *gen = cJSON_GetObjectItemCaseSensitive(item, "generator");
  const cJSON *file = cJSON_GetObjectItemCaseSensitive(item, "file");
  if (!!gen == !!file) return expected(r, key, "an object with either \"generator\" or \"file\"", item);

  lt_scene *mesh = lt__scene_new();
  if (!mesh) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
  if (gen) {
    snprintf(key, sizeof key, "meshes[%d].generator", index);
    if (!cJSON_IsString(gen) || strchr(gen->valuestring, '@'))
      status = expected(r, key, "a generator spec such as \"house-grid:3x3\" (without @camera)", gen);
    char name[256];
    if (!status) {
      snprintf(name, sizeof name, "%s", gen->valuestring);
      char *colon = strchr(name, ':');
      if (colon) *colon = '\0';
      status = lt__generate(name, colon ? colon + 1 : NULL, mesh);
      if (status) status = wrap(r, key, status);
    }
  } else {
    snprintf(key, sizeof key, "meshes[%d].file", index);
    if (!cJSON_IsString(file) || !*file->valuestring)
      status = expected(r, key, "a mesh file name (.obj, .ply, .gltf, ...)", file);
    size_t n = status ? 0 : strlen(file->valuestring);
    if (!status && n >= 5 && strcmp(file->valuestring + n - 5, ".json") == 0)
      status = expected(r, key, "a mesh file, not a scene file", file);
    if (!status) {
      char path[2048];
      if (file->valuestring[0] == '/') snprintf(path, sizeof path, "%s", file->valuestring);
      else snprintf(path, sizeof path, "%s%s", r->dir, file->valuestring);
      n = strlen(path);
      int obj = n >= 4 && (strcmp(path + n - 4, ".obj") == 0 || strcmp(path + n - 4, ".OBJ") == 0);
      int ply = n >= 4 && (strcmp(path + n - 4, ".ply") == 0 || strcmp(path + n - 4, ".PLY") == 0);
      status = obj ? lt__load_obj(path, mesh) : ply ? lt__load_ply(path, mesh) : lt__load_assimp(path, mesh);
      if (status) status = wrap(r, key, status);
    }
  }
  if (status) return lt_scene_destroy(mesh), status;
  *out = mesh;
  return LT_OK;
}

/* Keyframes an instance may have; enough for any hand-written animation. */
#define KEYS_MAX 1024

typedef struct placement {
  int mesh, material;
  float translate[3], rotate_y, scale;
  lt__pose *keys; /* "keyframes", by increasing time; NULL: the instance stands still */
  int key_count;
} placement;

static int is_identity(const placement *p) {
  return !p->keys && p->translate[0] == 0 && p->translate[1] == 0 && p->translate[2] == 0 && p->rotate_y == 0 &&
         p->scale == 1;
}

/* An instance's "keyframes": poses at times from 0 to 1, strictly increasing; a key's
 * translate, rotate_y and scale default to the instance's own. */
static lt_status read_keyframes(const reader *r, const cJSON *list, const char *where, placement *p) {
  static const char *const keys[] = {"time", "translate", "rotate_y", "scale", NULL};
  char key[KEY_SIZE], at[KEY_SIZE + 16];
  join(key, where, "keyframes");
  if (!cJSON_IsArray(list) || cJSON_GetArraySize(list) < 1 || cJSON_GetArraySize(list) > KEYS_MAX) {
    char what[96];
    snprintf(what, sizeof what, "an array of 1 to %d keyframes ({\"time\": 0, \"translate\": [0,0,0], ...})",
             KEYS_MAX);
    return expected(r, key, what, list);
  }
  p->key_count = cJSON_GetArraySize(list);
  p->keys = calloc((size_t)p->key_count, sizeof *p->keys);
  if (!p->keys) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
  lt_status status = LT_OK;
  for (int i = 0; i < p->key_count && !status; i++) {
    const cJSON *item = cJSON_GetArrayItem(list, i);
    lt__pose *k = &p->keys[i];
    double time, angle, scale;
    snprintf(at, sizeof at, "%s[%d]", key, i);
    status = element_object(r, item, at);
    if (!status) status = known_keys(r, item, at, keys);
    if (!status && !cJSON_GetObjectItemCaseSensitive(item, "time")) {
      char time_key[KEY_SIZE];
      status = expected(r, join(time_key, at, "time"), "the keyframe's time, a number from 0 to 1", NULL);
    }
    if (!status) status = number(r, item, at, "time", 0.0, 1.0, 0.0, &time);
    if (!status) status = vec3(r, item, at, "translate", -INFINITY, INFINITY, p->translate, k->translate);
    if (!status) status = number(r, item, at, "rotate_y", -1e6, 1e6, p->rotate_y, &angle);
    if (!status) status = number(r, item, at, "scale", 1e-6, 1e6, p->scale, &scale);
    k->time = (float)time, k->rotate_y = (float)angle, k->scale = (float)scale;

    /* Times must rise, or the interpolation between two keys would divide by nothing. */
    if (!status && i > 0 && !(k->time > k[-1].time)) {
      char time_key[KEY_SIZE], what[96];
      snprintf(what, sizeof what, "a time after the previous keyframe's (%g)", k[-1].time);
      status = expected(r, join(time_key, at, "time"), what, cJSON_GetObjectItemCaseSensitive(item, "time"));
    }
  }
  return status;
}

static lt_status read_instance(const reader *r, const cJSON *item, int index, int meshes, placement *p) {
  static const char *const keys[] = {"mesh", "translate", "rotate_y", "scale", "material", "keyframes", NULL};
  static const float zero[3] = {0, 0, 0};
  char where[KEY_SIZE];
  double angle, scale;
  snprintf(where, sizeof where, "instances[%d]", index);
  lt_status status = element_object(r, item, where);
  if (!status) status = known_keys(r, item, where, keys);
  if (!status && !cJSON_GetObjectItemCaseSensitive(item, "mesh"))
    return lt__fail(LT_ERROR_PARSE, "%s:%d: %s.mesh: expected the index of a mesh (0 to %d), got nothing", r->path,
                    line_of(r, where), where, meshes - 1);
  if (!status) status = integer(r, item, where, "mesh", 0, meshes - 1, 0, &p->mesh);
  if (!status) status = vec3(r, item, where, "translate", -INFINITY, INFINITY, zero, p->translate);
  if (!status) status = number(r, item, where, "rotate_y", -1e6, 1e6, 0.0, &angle);
  /* Scales beyond 1e6 either way push ordinary meshes to where float products overflow or
   * vanish (a blank render); such a scale is refused rather than silently served. */
  if (!status) status = number(r, item, where, "scale", 1e-6, 1e6, 1.0, &scale);
  if (!status) status = integer(r, item, where, "material", 0, (int)r->desc->material_count - 1, 0, &p->material);
  p->rotate_y = (float)angle, p->scale = (float)scale;
  const cJSON *keyframes = cJSON_GetObjectItemCaseSensitive(item, "keyframes");
  if (!status && keyframes) status = read_keyframes(r, keyframes, where, p);
  return status;
}

/* Appends the mesh's triangles moved by the placement: scaled, turned about y, translated. An
 * instance with keyframes, or of a mesh that moves by itself (explode:BASE), becomes a mover
 * of the scene; its triangles are placed at time 0 once the whole file is read. */
static lt_status place(reader *r, const lt_scene *mesh, const placement *p, int index) {
  lt__pose pose = {0.0f, {p->translate[0], p->translate[1], p->translate[2]}, p->rotate_y, p->scale};
  lt__pose_turn turn = lt__pose_turn_of(&pose);
  size_t first = r->scene->count;
  for (size_t t = 0; t < mesh->count; t++) {
    float v[3][3];
    for (int k = 0; k < 3; k++) lt__pose_apply(&pose, turn, mesh->tris + 9 * t + 3 * k, v[k]);
    lt_status status = lt__scene_add_tri(r->scene, v[0], v[1], v[2]);
    if (status) return status;
  }
  r->scene->skipped += mesh->skipped;

  /* A moving instance keeps its mesh's shape and poses; its triangles must all be kept, for
   * the numbering to hold in every frame. */
  const float *burst = lt_scene_is_animated(mesh) ? mesh->motion->movers[0].burst : NULL;
  if (p->keys || burst) {
    if (r->scene->count - first != mesh->count) {
      char key[KEY_SIZE];
      snprintf(key, sizeof key, "instances[%d]", index);
      return lt__fail(LT_ERROR_PARSE, "%s:%d: %s: a moving instance places triangles beyond float range", r->path,
                      line_of(r, key), key);
    }
    lt_status status = lt__motion_add(r->scene, first, mesh->count, mesh->tris, burst, p->keys ? p->keys : &pose,
                                      p->keys ? p->key_count : 1);
    if (status) return status;
  }

  /* Each new triangle gets the instance's material. */
  if (r->scene->count > r->tri_capacity) {
    size_t capacity = r->scene->capacity;
    int *m = realloc(r->desc->tri_material, capacity * sizeof *m);
    if (!m) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory for materials", r->path);
    r->desc->tri_material = m, r->tri_capacity = capacity;
  }
  for (size_t t = first; t < r->scene->count; t++) r->desc->tri_material[t] = p->material;
  return LT_OK;
}

/* Meshes, then instances (or every mesh once as it is); a generator's cameras come along when
 * it is placed as it is, so that its "outer" camera serves a file that names none. */
static lt_status read_geometry(reader *r, const cJSON *root) {
  lt_status status;
  const cJSON *meshes = array_of(r, root, "meshes", &status);
  if (status) return status;
  if (!meshes || cJSON_GetArraySize(meshes) == 0)
    return expected(r, "meshes", "an array of at least one mesh ({\"generator\": ...} or {\"file\": ...})", meshes);
  int n = cJSON_GetArraySize(meshes);
  lt_scene **loaded = calloc((size_t)n, sizeof *loaded);
  if (!loaded) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
  for (int i = 0; i < n && !status; i++) status = load_mesh(r, cJSON_GetArrayItem(meshes, i), i, &loaded[i]);

  const cJSON *instances = status ? NULL : array_of(r, root, "instances", &status);
  int count = instances ? cJSON_GetArraySize(instances) : n;
  for (int i = 0; i < count && !status; i++) {
    placement p = {i, 0, {0, 0, 0}, 0.0f, 1.0f, NULL, 0};
    if (instances) status = read_instance(r, cJSON_GetArrayItem(instances, i), i, n, &p);
    if (!status) status = place(r, loaded[p.mesh], &p, i);
    int still = is_identity(&p);
    free(p.keys), p.keys = NULL;
    if (!status && still && r->scene->camera_count == 0)
      for (int c = 0; c < loaded[p.mesh]->camera_count && !status; c++)
        status = lt__scene_add_camera(r->scene, loaded[p.mesh]->camera_names[c], loaded[p.mesh]->cameras[c]);
  }
  for (int i = 0; i < n; i++) lt_scene_destroy(loaded[i]);
  free(loaded);

  /* Moving instances take their pose at time 0. */
  if (!status) lt_scene_set_time(r->scene, 0.0);
  return status;
}

/* ---- Materials, lights, camera, image ---- */

static lt_status read_materials(reader *r, const cJSON *root) {
  static const char *const keys[] = {"diffuse", "mirror", "emission", NULL};
  static const float grey[3] = {0.8f, 0.8f, 0.8f}, black[3] = {0, 0, 0};
  lt_status status;
  const cJSON *list = array_of(r, root, "materials", &status);
  if (status) return status;
  size_t n = list && cJSON_GetArraySize(list) > 0 ? (size_t)cJSON_GetArraySize(list) : 1;
  r->desc->materials = calloc(n, sizeof *r->desc->materials);
  if (!r->desc->materials) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
  r->desc->material_count = n;
  r->desc->materials[0] = (lt_material){{0.8f, 0.8f, 0.8f}, 0.0f, {0, 0, 0}};
  for (int i = 0; list && i < cJSON_GetArraySize(list) && !status; i++) {
    const cJSON *item = cJSON_GetArrayItem(list, i);
    lt_material *m = &r->desc->materials[i];
    char where[KEY_SIZE];
    double mirror = 0.0;
    snprintf(where, sizeof where, "materials[%d]", i);
    status = element_object(r, item, where);
    if (!status) status = known_keys(r, item, where, keys);
    if (!status) status = vec3(r, item, where, "diffuse", 0.0, 1.0, grey, m->diffuse);
    if (!status) status = number(r, item, where, "mirror", 0.0, 1.0, 0.0, &mirror);
    if (!status) status = vec3(r, item, where, "emission", 0.0, 1e30, black, m->emission);
    m->mirror = (float)mirror;
  }
  return status;
}

static lt_status read_lights(reader *r, const cJSON *root) {
  static const char *const keys[] = {"point", "direction", "intensity", NULL};
  static const float one[3] = {1, 1, 1};
  lt_status status;
  const cJSON *list = array_of(r, root, "lights", &status);
  if (status || !list || cJSON_GetArraySize(list) == 0) return status;
  size_t n = (size_t)cJSON_GetArraySize(list);
  r->desc->lights = calloc(n, sizeof *r->desc->lights);
  if (!r->desc->lights) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", r->path);
  r->desc->light_count = n;
  for (size_t i = 0; i < n && !status; i++) {
    const cJSON *item = cJSON_GetArrayItem(list, (int)i);
    lt_light *l = &r->desc->lights[i];
    char where[KEY_SIZE];
    snprintf(where, sizeof where, "lights[%zu]", i);
    status = element_object(r, item, where);
    if (!status) status = known_keys(r, item, where, keys);
    if (status) break;
    int point = cJSON_HasObjectItem(item, "point"), direction = cJSON_HasObjectItem(item, "direction");
    if (point == direction) return expected(r, where, "an object with either \"point\" or \"direction\"", item);
    l->kind = point ? LT_LIGHT_POINT : LT_LIGHT_DIRECTIONAL;
    status = vec3(r, item, where, point ? "point" : "direction", -INFINITY, INFINITY, NULL, l->vector);
    if (!status) status = vec3(r, item, where, "intensity", 0.0, 1e30, one, l->intensity);
    if (!status && direction && l->vector[0] == 0 && l->vector[1] == 0 && l->vector[2] == 0) {
      char key[KEY_SIZE];
      join(key, where, "direction");
      status = expected(r, key, "a direction that is not zero", cJSON_GetObjectItemCaseSensitive(item, "direction"));
    }
  }
  return status;
}

static lt_status read_camera(reader *r, const cJSON *root) {
  static const char *const keys[] = {"eye", "look", "up", "fov", NULL};
  static const float up[3] = {0, 1, 0};
  const cJSON *cam = cJSON_GetObjectItemCaseSensitive(root, "camera");
  if (!cam) return LT_OK;
  lt_camera c;
  double fov;
  lt_status status = element_object(r, cam, "camera");
  if (!status) status = known_keys(r, cam, "camera", keys);
  if (!status) status = vec3(r, cam, "camera", "eye", -INFINITY, INFINITY, NULL, c.eye);
  if (!status) status = vec3(r, cam, "camera", "look", -INFINITY, INFINITY, NULL, c.look);
  if (!status) status = vec3(r, cam, "camera", "up", -INFINITY, INFINITY, up, c.up);
  if (!status) status = number(r, cam, "camera", "fov", 1.0, 179.0, 60.0, &fov);
  if (status) return status;
  if (c.eye[0] == c.look[0] && c.eye[1] == c.look[1] && c.eye[2] == c.look[2])
    return expected(r, "camera.look", "a point other than camera.eye", cJSON_GetObjectItemCaseSensitive(cam, "look"));

  /* An up vector that is zero or along the view direction leaves no image plane: every ray
   * would be NaN and the image blank. The angle between them must be clear of 0 and 180. */
  double d[3] = {c.look[0] - c.eye[0], c.look[1] - c.eye[1], c.look[2] - c.eye[2]};
  double x[3] = {d[1] * c.up[2] - d[2] * c.up[1], d[2] * c.up[0] - d[0] * c.up[2], d[0] * c.up[1] - d[1] * c.up[0]};
  double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2], uu = c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2];
  double xx = x[0] * x[0] + x[1] * x[1] + x[2] * x[2];
  if (!(xx > 1e-6 * dd * uu))
    return expected(r, "camera.up", "a direction that is not zero and not along the view (camera.look - camera.eye)",
                    cJSON_GetObjectItemCaseSensitive(cam, "up"));
  c.fov_deg = (float)fov;

  /* The file's camera comes first, ahead of any a generator brought along. */
  r->scene->camera_count = 0, r->scene->active_camera = -1;
  return lt__scene_add_camera(r->scene, "camera", c);
}

static lt_status read_image(reader *r, const cJSON *root) {
  static const char *const keys[] = {"width", "height", "spp", NULL};
  const cJSON *img = cJSON_GetObjectItemCaseSensitive(root, "image");
  if (!img) return LT_OK;
  lt_status status = element_object(r, img, "image");
  if (!status) status = known_keys(r, img, "image", keys);
  if (!status) status = integer(r, img, "image", "width", 1, 16384, 0, &r->desc->width);
  if (!status) status = integer(r, img, "image", "height", 1, 16384, 0, &r->desc->height);
  if (!status) status = integer(r, img, "image", "spp", 1, 65536, 0, &r->desc->spp);
  return status;
}

/* ---- Effects ---- */

/* An effect given as false (off), true (on with its defaults) or an object of parameters. */
static lt_status effect(const reader *r, const cJSON *effects, const char *name, const char *const *keys,
                        const cJSON **params, int *on) {
  char key[KEY_SIZE];
  const cJSON *v = cJSON_GetObjectItemCaseSensitive(effects, name);
  join(key, "effects", name);
  *params = NULL, *on = 0;
  if (!v || cJSON_IsFalse(v)) return LT_OK;
  *on = 1;
  if (cJSON_IsTrue(v)) return LT_OK;
  if (!cJSON_IsObject(v) || !keys) return expected(r, key, keys ? "true, false or an object" : "true or false", v);
  *params = v;
  return known_keys(r, v, key, keys);
}

static lt_status read_effects(reader *r, const cJSON *root) {
  static const char *const keys[] = {"primary", "shadows", "ao", "diffuse", "mirror", "collision", NULL};
  static const char *const ao_keys[] = {"samples", "distance", NULL}, *const diffuse_keys[] = {"samples", "bounces", NULL};
  static const char *const mirror_keys[] = {"depth", NULL}, *const collision_keys[] = {"agents", "rays", "frames", NULL};
  lt_effects *e = &r->desc->effects;
  const cJSON *fx = cJSON_GetObjectItemCaseSensitive(root, "effects"), *p;
  if (!fx) return LT_OK;
  lt_status status = element_object(r, fx, "effects");
  if (!status) status = known_keys(r, fx, "effects", keys);
  if (status) return status;
  const cJSON *primary = cJSON_GetObjectItemCaseSensitive(fx, "primary");
  if (primary && !cJSON_IsBool(primary)) return expected(r, "effects.primary", "true or false", primary);
  e->primary = !primary || cJSON_IsTrue(primary);

  int on;
  double distance;
  if ((status = effect(r, fx, "shadows", NULL, &p, &e->shadows))) return status;
  if ((status = effect(r, fx, "ao", ao_keys, &p, &on))) return status;
  if (on && (status = integer(r, p, "effects.ao", "samples", 1, 4096, 8, &e->ao_samples))) return status;
  if (on && (status = number(r, p, "effects.ao", "distance", 1e-30, 1e30, 1.0, &distance))) return status;
  if (on) e->ao_distance = (float)distance;
  if ((status = effect(r, fx, "diffuse", diffuse_keys, &p, &on))) return status;
  if (on && (status = integer(r, p, "effects.diffuse", "samples", 1, 4096, 4, &e->diffuse_samples))) return status;
  if (on && (status = integer(r, p, "effects.diffuse", "bounces", 1, 64, 1, &e->diffuse_bounces))) return status;
  if ((status = effect(r, fx, "mirror", mirror_keys, &p, &on))) return status;
  if (on && (status = integer(r, p, "effects.mirror", "depth", 1, 64, 2, &e->mirror_depth))) return status;
  if ((status = effect(r, fx, "collision", collision_keys, &p, &on))) return status;
  if (on && (status = integer(r, p, "effects.collision", "agents", 1, 1 << 20, 100, &e->collision_agents))) return status;
  if (on && (status = integer(r, p, "effects.collision", "rays", 1, 1 << 16, 8, &e->collision_rays))) return status;
  if (on && (status = integer(r, p, "effects.collision", "frames", 1, 1 << 16, 20, &e->collision_frames))) return status;

  /* Shading effects start from the camera's hits. */
  if (!e->primary && (e->shadows || e->ao_samples || e->diffuse_samples || e->mirror_depth)) {
    const char *name = e->shadows ? "shadows" : e->ao_samples ? "ao" : e->diffuse_samples ? "diffuse" : "mirror";
    char key[KEY_SIZE];
    join(key, "effects", name);
    return lt__fail(LT_ERROR_PARSE, "%s:%d: %s: expected effects.primary to be on (it starts from the primary hits)",
                    r->path, line_of(r, key), key);
  }
  return LT_OK;
}

/* ---- The file ---- */

/* The file's text, NUL-terminated. */
static lt_status read_text(const char *path, char **out) {
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  size_t size = 0, capacity = 4096;
  char *text = malloc(capacity);
  for (size_t got = 1; text && got > 0 && size <= FILE_MAX;) {
    if (size + 1 == capacity) {
      char *grown = realloc(text, 2 * capacity);
      if (!grown) free(text);
      text = grown, capacity *= 2;
      if (!text) break;
    }
    got = fread(text + size, 1, capacity - 1 - size, f);
    size += got;
  }
  int failed = ferror(f);
  fclose(f);
  if (!text) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the file", path);
  if (failed || size > FILE_MAX) {
    free(text);
    return lt__fail(LT_ERROR_IO, "%s: %s", path, failed ? "read failed" : "larger than a scene file can be");
  }
  text[size] = '\0';
  *out = text;
  return LT_OK;
}

/* A JSON syntax error, named by line and column. */
static lt_status syntax_error(const char *path, const char *text, const char *at) {
  int line = 1, column = 1;
  for (const char *c = text; at && c < at && *c; c++) {
    if (*c == '\n') line++, column = 1;
    else column++;
  }
  char near[24] = "";
  if (at) snprintf(near, sizeof near, "%.20s", at);
  for (char *c = near; *c; c++)
    if (*c == '\n' || *c == '\r' || *c == '\t') *c = ' ';
  return lt__fail(LT_ERROR_PARSE, "%s:%d:%d: malformed JSON near '%s'", path, line, column, near);
}

lt_status lt__load_scene_file(const char *path, lt_scene *scene) {
  static const char *const keys[] = {"meshes", "instances", "materials", "lights", "camera", "image", "effects",
                                     "background", NULL};
  static const float sky[3] = {0.75f, 0.85f, 1.0f};
  char *text = NULL;
  lt_status status = read_text(path, &text);
  if (status) return status;
  const char *end = NULL;
  cJSON *root = cJSON_ParseWithOpts(text, &end, 1);
  if (!root) {
    status = syntax_error(path, text, cJSON_GetErrorPtr());
    free(text);
    return status;
  }

  reader r = {path, text, "", scene, calloc(1, sizeof(lt__scene_desc)), 0};
  const char *slash = strrchr(path, '/');
  if (slash) snprintf(r.dir, sizeof r.dir, "%.*s/", (int)(slash - path), path);
  if (!r.desc) status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  if (!status) lt__scene_desc_defaults(r.desc);
  if (!status && !cJSON_IsObject(root)) status = expected(&r, "the top level", "an object", root);
  if (!status) status = known_keys(&r, root, "", keys);

  /* Materials before instances, which refer to them; the camera after the geometry, which
   * may bring a generator's cameras that a named camera replaces. */
  if (!status) status = read_materials(&r, root);
  if (!status) status = read_geometry(&r, root);
  if (!status) status = read_lights(&r, root);
  if (!status) status = read_camera(&r, root);
  if (!status) status = read_image(&r, root);
  if (!status) status = read_effects(&r, root);
  if (!status) status = vec3(&r, root, "", "background", 0.0, 1e30, sky, r.desc->background);
  cJSON_Delete(root);
  free(text);
  if (status) {
    lt__scene_desc_free(r.desc);
    return status;
  }
  scene->desc = r.desc;
  return LT_OK;
}
