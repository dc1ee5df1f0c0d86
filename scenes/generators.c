/* Scene generators by name. This file reads the arguments after the ':' of a spec and checks
 * them before any generator runs, so that a bad spec fails with a message naming what was
 * expected; the shapes themselves are in gen_house.c and gen_shapes.c. */
#include <stdio.h>
#include <string.h>

#include "runtime/error.h"
#include "gen_geometry.h"

#define SPEC_SIZE 128
/* Digits beyond this are not read further: every limit is far below it. */
#define NUMBER_CAP 1000000000L

const char *lt_generator_names(void) {
  return "house, house-row:N, house-grid:RxC, hairball:N, teapot-stadium, sphere:LEVEL, cornell, explode:BASE";
}

/* The spec as the user wrote it, for messages. */
static const char *spec_of(const char *name, const char *args, char spec[SPEC_SIZE]) {
  snprintf(spec, SPEC_SIZE, "%s%s%s", name, args ? ":" : "", args ? args : "");
  return spec;
}

/* Reads decimal digits (no sign, no spaces), saturating at NUMBER_CAP; returns the character
 * after them, or NULL if there were none. */
static const char *read_number(const char *text, long *value) {
  if (*text < '0' || *text > '9') return NULL;
  *value = 0;
  for (; *text >= '0' && *text <= '9'; text++) {
    *value = 10 * *value + (*text - '0');
    if (*value > NUMBER_CAP) *value = NUMBER_CAP;
  }
  return text;
}

/* A spec of the form name:N with lo <= N <= hi; var is N's name in messages, what says what it
 * stands for. */
static lt_status one_number(const char *name, const char *args, long lo, long hi, const char *var, const char *what,
                            long *out) {
  char spec[SPEC_SIZE];
  const char *end = args ? read_number(args, out) : NULL;
  if (!end || *end != '\0')
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s: expected %s:%s with %s %s, a whole number from %ld to %ld",
                    spec_of(name, args, spec), name, var, var, what, lo, hi);
  if (*out < lo || *out > hi)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s: %s, %s, must be from %ld to %ld", spec_of(name, args, spec), var,
                    what, lo, hi);
  return LT_OK;
}

/* house-grid:RxC: R rows away from the camera by C columns, at most LT_HOUSES_MAX houses. */
static lt_status grid_numbers(const char *name, const char *args, long *rows, long *columns) {
  char spec[SPEC_SIZE];
  const char *x = args ? read_number(args, rows) : NULL;
  const char *end = x && (*x == 'x' || *x == 'X') ? read_number(x + 1, columns) : NULL;
  if (!end || *end != '\0')
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "%s: expected %s:RxC, R rows by C columns of houses as whole numbers (e.g. %s:3x3)",
                    spec_of(name, args, spec), name, name);
  if (*rows < 1 || *columns < 1 || *rows > LT_HOUSES_MAX || *columns > LT_HOUSES_MAX ||
      *rows * *columns > LT_HOUSES_MAX)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "%s: R and C must be at least 1 and R*C at most %d houses (about 100k triangles each)",
                    spec_of(name, args, spec), LT_HOUSES_MAX);
  return LT_OK;
}

static lt_status no_args(const char *name, const char *args) {
  char spec[SPEC_SIZE];
  if (!args) return LT_OK;
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s: the generator '%s' takes no arguments", spec_of(name, args, spec),
                  name);
}

/* explode:BASE: the scene of the generator spec BASE, whose triangles fly apart with time. */
static lt_status explode(const char *args, lt_scene *scene) {
  char base[SPEC_SIZE];
  if (!args || !*args)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT,
                    "explode: expected explode:BASE with BASE a generator spec (e.g. explode:sphere:4)");
  snprintf(base, sizeof base, "%s", args);
  char *colon = strchr(base, ':');
  if (colon) *colon = '\0';
  if (strcmp(base, "explode") == 0)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "explode:%s: the base of an explosion cannot explode itself", args);
  lt_status status = lt__generate(base, colon ? colon + 1 : NULL, scene);
  if (status) return status;

  /* The pieces fly up to about three times the scene's radius: its cameras step back three
   * times as far from what they look at, to keep the explosion in view. */
  for (int c = 0; c < scene->camera_count; c++)
    for (int k = 0; k < 3; k++) {
      lt_camera *cam = &scene->cameras[c];
      cam->eye[k] = cam->look[k] + 3.0f * (cam->eye[k] - cam->look[k]);
    }
  return lt__motion_explode(scene);
}

lt_status lt__generate(const char *name, const char *args, lt_scene *scene) {
  long a = 0, b = 0;
  lt_status status;
  if (!name || !scene) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__generate: NULL argument");

  /* Houses: one, a row one behind the other, or a grid. */
  if (strcmp(name, "house") == 0)
    return (status = no_args(name, args)) ? status : lt__gen_houses(scene, 1, 1, LT_HOUSES_ROW);
  if (strcmp(name, "house-row") == 0) {
    status = one_number(name, args, 1, LT_HOUSES_MAX, "N", "the number of houses", &a);
    return status ? status : lt__gen_houses(scene, (int)a, 1, LT_HOUSES_ROW);
  }
  if (strcmp(name, "house-grid") == 0) {
    status = grid_numbers(name, args, &a, &b);
    return status ? status : lt__gen_houses(scene, (int)a, (int)b, LT_HOUSES_GRID);
  }

  /* Single shapes and the classic test scenes. */
  if (strcmp(name, "sphere") == 0) {
    status = one_number(name, args, 0, 10, "LEVEL", "the subdivision level", &a);
    return status ? status : lt__gen_sphere(scene, (int)a);
  }
  if (strcmp(name, "hairball") == 0) {
    status = one_number(name, args, 1, 1000000, "N", "the number of strands", &a);
    return status ? status : lt__gen_hairball(scene, (int)a);
  }
  if (strcmp(name, "teapot-stadium") == 0)
    return (status = no_args(name, args)) ? status : lt__gen_teapot_stadium(scene);
  if (strcmp(name, "cornell") == 0) return (status = no_args(name, args)) ? status : lt__gen_cornell(scene);

  /* Animation: another generator's triangles flying apart over time. */
  if (strcmp(name, "explode") == 0) return explode(args, scene);
  return lt__fail(LT_ERROR_UNKNOWN_GENERATOR, "unknown generator '%s' (known: %s)", name, lt_generator_names());
}
