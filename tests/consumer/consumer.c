/* A program that uses lazytrace the way a user does: through the installed header and library
 * only. It traces camera rays through every structure and build mode the library lists, on the
 * native backend, and checks each hit against the brute-force reference (same triangle, same
 * distance, bit for bit). Exit status 0 when everything agrees.
 *   consumer [SCENE]    (default sphere:2) */
#include <lazytrace.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIDE 24

static int fail(const char *what, lt_status status) {
  fprintf(stderr, "consumer: %s: %s (%s)\n", what, lt_status_str(status), lt_last_error());
  return 1;
}

/* Traces the rays through one structure and counts the hits that differ from the reference. */
static int check_variant(lt_context *ctx, const lt_scene *scene, lt_structure_config config, const lt_ray *rays,
                         size_t n, const lt_hit *expected, lt_hit *hits) {
  lt_structure *structure;
  lt_status status = lt_structure_create(ctx, scene, &config, NULL, &structure);
  if (status) return fail("creating a structure", status);
  status = lt_structure_trace(structure, rays, n, LT_QUERY_CLOSEST, hits, NULL);
  lt_structure_destroy(structure);
  if (status) return fail("tracing", status);
  int wrong = 0;
  for (size_t i = 0; i < n; i++)
    wrong += hits[i].prim != expected[i].prim || memcmp(&hits[i].t, &expected[i].t, sizeof(float)) != 0;
  printf("%-7s %-11s %zu rays, %d differ from brute force\n", lt_structure_kind_name(config.kind),
         lt_build_mode_name(config.build), n, wrong);
  return wrong != 0;
}

int main(int argc, char **argv) {
  const char *spec = argc > 1 ? argv[1] : "sphere:2";
  printf("lazytrace %s (header %d.%d.%d)\n", lt_version(), LT_VERSION_MAJOR, LT_VERSION_MINOR, LT_VERSION_PATCH);
  if (strcmp(lt_version(), "") == 0) return 1;

  lt_context *ctx;
  lt_context_config context_config = {.device = LT_DEVICE_NATIVE, .quiet = 1};
  lt_status status = lt_context_create(&context_config, &ctx);
  if (status) return fail("creating a context", status);
  lt_scene *scene;
  if ((status = lt_scene_load(spec, &scene))) return lt_context_destroy(ctx), fail(spec, status);

  /* Camera rays and the brute-force answers to compare with. */
  size_t n = SIDE * SIDE;
  lt_ray *rays = malloc(n * sizeof *rays);
  lt_hit *expected = malloc(n * sizeof *expected), *hits = malloc(n * sizeof *hits);
  int bad = !rays || !expected || !hits;
  lt_camera camera = lt_scene_camera(scene);
  if (!bad) lt_camera_primary_rays(&camera, SIDE, SIDE, rays);
  if (!bad && (status = lt_reference_trace(scene, rays, n, LT_QUERY_CLOSEST, expected)))
    bad = fail("reference", status);

  /* Every structure and build mode the library implements. */
  lt_structure_kind kinds[64];
  lt_build_mode modes[64];
  size_t variants = lt_structure_variants(kinds, modes, 64);
  for (size_t v = 0; v < variants && !bad; v++) {
    lt_structure_config config = lt_structure_config_default(kinds[v]);
    config.build = modes[v];
    bad |= check_variant(ctx, scene, config, rays, n, expected, hits);
  }

  free(rays), free(expected), free(hits);
  lt_scene_destroy(scene);
  lt_context_destroy(ctx);
  puts(bad ? "consumer: FAILED" : "consumer: all hits agree");
  return bad;
}
