/* Option parsing shared by the subcommands, and the steps every tracing command starts with. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "apps/cli.h"

static int bad(const char *option, const char *value, const char *expected) {
  fprintf(stderr, "lazytrace: %s '%s': expected %s\n", option, value ? value : "", expected);
  return 1;
}

/* A whole positive int, or -1. */
static long parse_positive(const char *s, long max) {
  char *end;
  errno = 0;
  long v = strtol(s, &end, 10);
  return (errno || end == s || *end || v <= 0 || v > max) ? -1 : v;
}

static int parse_device(const char *value, lt_context_config *ctx) {
  if (strcmp(value, "auto") == 0) ctx->device = LT_DEVICE_AUTO;
  else if (strcmp(value, "native") == 0) ctx->device = LT_DEVICE_NATIVE;
  else if (strcmp(value, "opencl") == 0) ctx->device = LT_DEVICE_OPENCL, ctx->opencl_index = 0;
  else if (strncmp(value, "opencl:", 7) == 0) {
    long index = strcmp(value + 7, "0") == 0 ? 0 : parse_positive(value + 7, 1 << 16);
    if (index < 0) return bad("--device", value, "auto, native, opencl or opencl:N");
    ctx->device = LT_DEVICE_OPENCL, ctx->opencl_index = (int)index;
  } else {
    return bad("--device", value, "auto, native, opencl or opencl:N");
  }
  return 0;
}

/* Options that take a value; each returns nonzero on a bad value. */
static int apply(lt_cli *cli, const char *option, const char *value) {
  long n;
  if (strcmp(option, "-o") == 0 || strcmp(option, "--output") == 0) cli->output = value;
  else if (strcmp(option, "--rays") == 0) cli->rays = value;
  else if (strcmp(option, "--hits") == 0) cli->hits = value;
  else if (strcmp(option, "--stats") == 0) cli->stats = value;
  else if (strcmp(option, "--device") == 0) return parse_device(value, &cli->context);
  else if (strcmp(option, "--split") == 0) {
    if (strcmp(value, "tiles") != 0 && strcmp(value, "interleaved") != 0 && strcmp(value, "queue") != 0)
      return bad(option, value, "tiles, interleaved or queue");
    cli->interleaved = strcmp(value, "interleaved") == 0;
    cli->queue = strcmp(value, "queue") == 0;
  }
  else if (strcmp(option, "--structure") == 0) {
    lt_status status = lt_structure_kind_parse(value, &cli->structure.kind);
    if (status) return fprintf(stderr, "lazytrace: %s\n", lt_last_error()), 1;
  } else if (strcmp(option, "--build") == 0) {
    lt_status status = lt_build_mode_parse(value, &cli->structure.build);
    if (status) return fprintf(stderr, "lazytrace: %s\n", lt_last_error()), 1;
    cli->build_given = 1;
  } else if (strcmp(option, "--intersect") == 0) {
    lt_status status = lt_intersect_kind_parse(value, &cli->structure.intersect);
    if (status) return fprintf(stderr, "lazytrace: %s\n", lt_last_error()), 1;
  } else if (strcmp(option, "--size") == 0) {
    int w = 0, h = 0, used = 0;
    if (sscanf(value, "%dx%d%n", &w, &h, &used) != 2 || value[used] || w <= 0 || h <= 0 || w > 16384 || h > 16384)
      return bad(option, value, "WIDTHxHEIGHT, each 1 to 16384");
    cli->width = w, cli->height = h, cli->size_given = 1;
  } else if (strcmp(option, "--seed") == 0) {
    char *end;
    errno = 0;
    cli->seed = strtoull(value, &end, 10);
    if (errno || end == value || *end) return bad(option, value, "a non-negative integer");
  } else {
    /* The remaining options are positive integers. */
    int *slot = strcmp(option, "--agents") == 0           ? &cli->agents
                : strcmp(option, "--rays-per-agent") == 0 ? &cli->rays_per_agent
                : strcmp(option, "--frames") == 0         ? &cli->frames
                : strcmp(option, "--spp") == 0            ? &cli->spp
                : strcmp(option, "--work-groups") == 0    ? &cli->context.work_groups
                : strcmp(option, "--local-size") == 0     ? &cli->context.local_size
                                                          : NULL;
    if (!slot) {
      /* The structures' own options, as the registry lists them. */
      lt_status status = lt_structure_option(&cli->structure, option, value);
      if (status == LT_ERROR_UNSUPPORTED)
        return fprintf(stderr, "lazytrace: unknown option '%s' (run 'lazytrace --help')\n", option), 1;
      if (status) return fprintf(stderr, "lazytrace: %s\n", lt_last_error()), 1;
      return 0;
    }
    if ((n = parse_positive(value, 1 << 24)) < 0) return bad(option, value, "a positive integer");
    *slot = (int)n;
    cli->frames_given |= slot == &cli->frames;
  }
  return 0;
}

int lt_cli_parse(lt_cli *cli, int argc, char **argv) {
  memset(cli, 0, sizeof *cli);
  cli->command = argv[1];
  cli->width = cli->height = 1024;
  cli->agents = 100, cli->rays_per_agent = 8, cli->frames = 20, cli->seed = 1;
  memset(&cli->structure, 0, sizeof cli->structure); /* every field: the structure's default */
  for (int i = 2; i < argc; i++) {
    const char *arg = argv[i];
    if (strcmp(arg, "--any") == 0) {
      cli->any = 1;
    } else if (arg[0] == '-' && arg[1] != '\0') {
      if (i + 1 >= argc) return fprintf(stderr, "lazytrace: option '%s' needs a value\n", arg), 1;
      if (apply(cli, arg, argv[++i])) return 1;
    } else if (!cli->scene) {
      cli->scene = arg;
    } else {
      return fprintf(stderr, "lazytrace: unexpected argument '%s' (one SCENE only)\n", arg), 1;
    }
  }
  if (lt_cli_check_outputs(cli)) return 1;
  /* Without --build, the structure's own default mode (speculative, or full where there is no
   * on-demand form), said by name in messages and statistics. */
  if (!cli->build_given) cli->structure.build = lt_structure_config_default(cli->structure.kind).build;
  return 0;
}

int lt_cli_fail(const char *what, lt_status status) {
  fprintf(stderr, "lazytrace: %s: %s\n", what, *lt_last_error() ? lt_last_error() : lt_status_str(status));
  return 1;
}

int lt_cli_open(lt_cli *cli, lt_context **ctx, lt_scene **scene, lt_stats *stats) {
  if (!cli->scene) return fprintf(stderr, "lazytrace %s: no SCENE given (run 'lazytrace help %s')\n", cli->command, cli->command), 1;
  double start = lt_now_ms();
  lt_status status = lt_scene_load(cli->scene, scene);
  if (status) return lt_cli_fail("loading the scene", status);
  double load_ms = lt_now_ms() - start;
  lt_stats_set(stats, "load_ms", load_ms);
  size_t skipped = lt_scene_skipped_triangles(*scene);
  fprintf(stderr, "lazytrace: %s: %zu triangles loaded in %.0f ms", cli->scene, lt_scene_triangle_count(*scene), load_ms);
  if (skipped) fprintf(stderr, " (%zu skipped: NaN or infinite coordinates)", skipped);
  fputc('\n', stderr);
  size_t unservable = lt_scene_unservable_triangles(*scene);
  if (unservable)
    fprintf(stderr,
            "lazytrace: warning: %zu triangles have coordinates beyond 1e12 or sizes below 1e-12, where float "
            "arithmetic cannot serve them (the intersection's products overflow or vanish): rays may miss them\n",
            unservable);

  status = lt_context_create(&cli->context, ctx);
  if (status) {
    lt_scene_destroy(*scene);
    return lt_cli_fail("opening the device", status);
  }
  return 0;
}

int lt_cli_write_stats(const lt_cli *cli, const lt_stats *stats) {
  if (!cli->stats) return 0;
  if (strcmp(cli->stats, "-") == 0) {
    lt_status status = lt_stats_write_json(stats, stdout);
    if (!status && fflush(stdout) != 0) status = LT_ERROR_IO;
    return status ? lt_cli_fail("writing statistics", status) : 0;
  }

  /* In memory first, then written whole or not at all. */
  char *text = NULL;
  size_t bytes = 0;
  FILE *f = open_memstream(&text, &bytes);
  if (!f) return lt_cli_fail("writing statistics", LT_ERROR_OUT_OF_MEMORY);
  lt_status status = lt_stats_write_json(stats, f);
  if (fclose(f) != 0 && !status) status = LT_ERROR_OUT_OF_MEMORY;
  if (!status) status = lt_file_write(cli->stats, text, bytes);
  free(text);
  return status ? lt_cli_fail("writing statistics", status) : 0;
}

int lt_cli_check_outputs(const lt_cli *cli) {
  const char *inputs[] = {cli->scene, cli->rays};
  const char *outputs[] = {cli->output, cli->hits, cli->stats};
  for (int o = 0; o < 3; o++) {
    if (!outputs[o] || strcmp(outputs[o], "-") == 0) continue;
    for (int i = 0; i < 2; i++)
      if (inputs[i] && lt_files_same(outputs[o], inputs[i]))
        return fprintf(stderr, "lazytrace: %s is also an input (%s); refusing to overwrite it\n", outputs[o], inputs[i]), 1;
    for (int p = 0; p < o; p++)
      if (outputs[p] && strcmp(outputs[p], outputs[o]) == 0)
        return fprintf(stderr, "lazytrace: %s is named for two outputs\n", outputs[o]), 1;
  }
  return 0;
}
