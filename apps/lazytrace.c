/* lazytrace: the command-line tool. Dispatches to the subcommands in apps/cmd_*.c. */
#include <stdio.h>
#include <string.h>

#include "apps/cli.h"

static const char usage[] =
    "lazytrace: ray queries against triangle scenes, with acceleration structures built on demand\n"
    "\n"
    "usage:\n"
    "  lazytrace render  SCENE [OPTIONS] [--size WxH] [--spp N] [--seed S] [--frames N] [-o IMAGE.png]\n"
    "  lazytrace trace   SCENE --rays RAYS --hits HITS [--any] [OPTIONS]\n"
    "  lazytrace collide SCENE [--agents 100] [--rays-per-agent 8] [--frames 20] [--seed S] [OPTIONS]\n"
    "  lazytrace scene   SCENE -o FILE.obj\n"
    "  lazytrace devices\n"
    "  lazytrace help [COMMAND]\n"
    "\n"
    "SCENE    a generator (house, house-row:N, house-grid:RxC, hairball:N, teapot-stadium,\n"
    "         sphere:LEVEL, cornell; add @outer or @close to pick the camera; explode:BASE is\n"
    "         BASE's triangles flying apart over an animation) or a mesh file\n"
    "         (.obj and .ply read by lazytrace in file order; .gltf, .glb, ... through assimp)\n"
    "         or a scene file (.json: meshes, instances, materials, lights, camera, image,\n"
    "         effects; see 'lazytrace help render')\n"
    "\n"
    "OPTIONS  --structure NAME              acceleration structure (default bvh; the list below)\n"
    "         --build full|requested|speculative\n"
    "                                        build mode (default: speculative where the structure\n"
    "                                        builds on demand, else full): requested builds only\n"
    "                                        the nodes rays reach\n"
    "         --device auto|opencl[:N]|native\n"
    "                                        auto: OpenCL if a device exists, else native\n"
    "         --work-groups N  --local-size N  launch shape (default: what runs concurrently)\n"

    "         --intersect watertight|fast    ray-triangle test (default watertight: no ray\n"
    "                                        slips through a shared edge or vertex; fast:\n"
    "                                        Moller-Trumbore, fewer operations, may leak)\n"
    "         --stats FILE|-                 statistics as one JSON object\n"
    "         --split tiles|interleaved|queue  under mpirun (MPI build): each rank takes a\n"
    "                                        contiguous share of the rays, pixels or agents\n"
    "                                        (default), or every ranks-th one; queue (render\n"
    "                                        only; trace and collide take contiguous shares):\n"
    "                                        bands of rows handed out one at a time to the\n"
    "                                        rank that asks first\n"
    "         and each structure's own options, listed with it below\n"
    "\n"
    "Ray file: 32-byte little-endian records: float ox oy oz tmin dx dy dz tmax.\n"
    "Hit file: 16-byte records: float t u v, int32 prim (-1 on a miss);\n"
    "          hit point = (1-u-v)*v0 + u*v1 + v*v2.\n";

static const char *const command_help[][2] = {
    {"render", "lazytrace render SCENE [OPTIONS] [--size WxH] [--spp N] [--seed S] [--frames N] [-o IMAGE.png]\n"
               "  Traces the ray batches the scene's effects call for, all through one structure, and\n"
               "  writes a gamma-corrected PNG (default render.png). A scene file's \"effects\" choose\n"
               "  among primary (camera rays), shadows (any-hit rays to each light), ao {samples,\n"
               "  distance}, diffuse {samples, bounces}, mirror {depth} and collision {agents, rays,\n"
               "  frames}; generators and mesh files render primary rays, lit from the eye.\n"
               "  --size and --spp override the file's image (default 1024x1024, 1 sample per pixel);\n"
               "  --seed fixes every random number. The statistics add rays_by_effect, ms_by_effect\n"
               "  and one record per batch.\n"
               "  --frames N renders an animation: frame f (0 to N-1) at time f/(N-1) from 0 to 1, the\n"
               "  structure rebuilt from scratch every frame, written to IMAGE_0000.png, IMAGE_0001.png,\n"
               "  ...; a line per frame on stderr; the statistics add \"frames\" (rays, build_ms,\n"
               "  trace_ms, total_ms, nodes_built per frame) and give totals over the frames.\n"
               "  Scenes move by instance \"keyframes\" (poses at times from 0 to 1, interpolated\n"
               "  linearly; a key's translate, rotate_y, scale default to the instance's) or by the\n"
               "  generator explode:BASE (every triangle flies off, falls and spins; the same in\n"
               "  every run).\n"
               "  Scene file: {\"meshes\": [{\"generator\": \"house\"}, {\"file\": \"chair.obj\"}],\n"
               "    \"instances\": [{\"mesh\": 0, \"translate\": [0,0,0], \"rotate_y\": 0, \"scale\": 1, \"material\": 0},\n"
               "      {\"mesh\": 1, \"keyframes\": [{\"time\": 0, \"translate\": [0,0,0]}, {\"time\": 1, \"rotate_y\": 90}]}],\n"
               "    \"materials\": [{\"diffuse\": [0.8,0.8,0.8], \"mirror\": 0, \"emission\": [0,0,0]}],\n"
               "    \"lights\": [{\"point\": [0,5,0], \"intensity\": [10,10,10]}, {\"direction\": [1,-1,0]}],\n"
               "    \"camera\": {\"eye\": [0,2,-10], \"look\": [0,1,0], \"up\": [0,1,0], \"fov\": 60},\n"
               "    \"image\": {\"width\": 512, \"height\": 512, \"spp\": 1}, \"background\": [0.75,0.85,1],\n"
               "    \"effects\": {\"primary\": true, \"shadows\": true, \"ao\": {\"samples\": 8, \"distance\": 2}}}\n"},
    {"trace", "lazytrace trace SCENE --rays RAYS --hits HITS [--any] [OPTIONS]\n"
              "  Answers every ray of RAYS (closest hit, or any hit with --any) and writes HITS,\n"
              "  one record per ray in the same order.\n"},
    {"collide", "lazytrace collide SCENE [--agents 100] [--rays-per-agent 8] [--frames 20] [--seed S] [--hits HITS]\n"
                "  The on-demand paper's collision test: agents move along random paths; each frame\n"
                "  rebuilds the structure and every agent shoots rays around it. --hits writes every\n"
                "  frame's hits, frame after frame, agent after agent. An animated scene (keyframes,\n"
                "  explode:BASE) moves to each frame's time; the statistics add \"frames\".\n"},
    {"scene", "lazytrace scene SCENE -o FILE.obj\n"
              "  Writes the scene's triangles as OBJ, in the order trace numbers them.\n"},
    {"devices", "lazytrace devices\n  Lists the OpenCL devices found and the native backend.\n"},
};

/* The usage, then the structures as the library's registry describes them. */
static void print_usage(FILE *out) {
  fputs(usage, out);
  fputs("\nStructures (--structure NAME):\n", out);
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) {
    lt_structure_kind kind = (lt_structure_kind)k;
    unsigned modes = lt_structure_modes(kind);
    fprintf(out, "  %-6s %s\n         builds: %s%s%s (default %s)\n", lt_structure_kind_name(kind), lt_structure_summary(kind),
            modes & (1u << LT_BUILD_FULL) ? "full" : "", modes & (1u << LT_BUILD_REQUESTED) ? ", requested" : "",
            modes & (1u << LT_BUILD_SPECULATIVE) ? ", speculative" : "",
            lt_build_mode_name(lt_structure_config_default(kind).build));
    for (const char *p = lt_structure_parameters(kind); *p;) {
      const char *end = strchr(p, '\n');
      int len = end ? (int)(end - p) : (int)strlen(p);
      fprintf(out, "         %.*s\n", len, p);
      p += len + (end != NULL);
    }
  }
  if (*lt_structure_planned()) fprintf(out, "  planned, refused for now: %s\n", lt_structure_planned());
}

int main(int argc, char **argv) {
  if (argc < 2 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "--help") == 0) {
    print_usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? 2 : 0;
  }
  int n_help = (int)(sizeof command_help / sizeof command_help[0]);
  if (strcmp(argv[1], "help") == 0) {
    for (int i = 0; argc > 2 && i < n_help; i++)
      if (strcmp(argv[2], command_help[i][0]) == 0) return fputs(command_help[i][1], stdout), 0;
    print_usage(stdout);
    return 0;
  }

  /* "lazytrace COMMAND --help" prints that command's help. */
  for (int i = 2; i < argc; i++)
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0)
      for (int c = 0; c < n_help; c++)
        if (strcmp(argv[1], command_help[c][0]) == 0) return fputs(command_help[c][1], stdout), 0;

  lt_cli cli;
  if (lt_cli_parse(&cli, argc, argv) != 0) return 2;
#ifdef LT_WITH_MPI
  /* Started by mpirun: the tracing commands are split between the ranks. */
  if (lt_mpi_launched() && strcmp(cli.command, "render") == 0 && cli.frames_given) {
    fprintf(stderr, "lazytrace: render --frames is not split between MPI ranks; run it without mpirun\n");
    return 2;
  }
  if (lt_mpi_launched() && (strcmp(cli.command, "render") == 0 || strcmp(cli.command, "trace") == 0 ||
                            strcmp(cli.command, "collide") == 0))
    return lt_mpi_run(&cli);
#endif
  if (strcmp(cli.command, "render") == 0) return lt_cmd_render(&cli);
  if (strcmp(cli.command, "trace") == 0) return lt_cmd_trace(&cli);
  if (strcmp(cli.command, "collide") == 0) return lt_cmd_collide(&cli);
  if (strcmp(cli.command, "scene") == 0) return lt_cmd_scene(&cli);
  if (strcmp(cli.command, "devices") == 0) return lt_cmd_devices(&cli);
  fprintf(stderr, "lazytrace: unknown command '%s' (run 'lazytrace --help')\n", cli.command);
  return 2;
}
