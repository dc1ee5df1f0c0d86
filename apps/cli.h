/* The lazytrace command-line tool: shared option parsing and the subcommands. */
#ifndef LT_CLI_H
#define LT_CLI_H

#include <stdint.h>

#include "lazytrace.h"

typedef struct lt_cli {
  const char *command;
  const char *scene;  /* the positional SCENE */
  const char *output; /* -o */
  const char *rays, *hits, *stats;
  int any;
  int width, height;
  int size_given; /* --size was given: it overrides a scene file's image size */
  int spp;        /* --spp, or 0: the scene's */
  int agents, rays_per_agent, frames;
  int frames_given; /* --frames was given: render draws an animation of that many frames */
  uint64_t seed;
  int build_given;
  int interleaved; /* --split interleaved: under mpirun, rank r takes items r, r + ranks, ... */
  int queue;       /* --split queue: under mpirun, render's ranks take bands of rows from a shared counter */
  lt_structure_config structure;
  lt_context_config context;
} lt_cli;

/* Parses argv[2..]; prints the problem and returns nonzero on a bad option or value. */
int lt_cli_parse(lt_cli *cli, int argc, char **argv);
/* Prints "lazytrace: <what>: <lt_last_error()>" and returns 1. */
int lt_cli_fail(const char *what, lt_status status);
/* The context, scene and structure every tracing command starts from; prints errors. */
int lt_cli_open(lt_cli *cli, lt_context **ctx, lt_scene **scene, lt_stats *stats);
/* Refuses an output path that names an input file or another output; prints why. */
int lt_cli_check_outputs(const lt_cli *cli);
/* Writes stats to cli->stats ("-" for stdout) if it was asked for, whole or not at all. */
int lt_cli_write_stats(const lt_cli *cli, const lt_stats *stats);

/* A collision run's statistics: the last frame's (names, nodes, memory) with the totals over
 * frames of build, trace and rays, all of them collision rays; load_ms is kept. */
void lt_cli_collide_totals(lt_stats *stats, const lt_stats *last_frame, double build_ms, double trace_ms, double rays);
int lt_cmd_render(lt_cli *cli);
int lt_cmd_trace(lt_cli *cli);
int lt_cmd_collide(lt_cli *cli);
int lt_cmd_scene(lt_cli *cli);
int lt_cmd_devices(lt_cli *cli);

/* The MPI build (LT_WITH_MPI): whether a launcher (mpirun) started this process, and trace,
 * render or collide split between the ranks (apps/mpi/mpi_run.c). */
int lt_mpi_launched(void);
int lt_mpi_run(lt_cli *cli);

/* Writes an 8-bit RGB image as PNG; returns 0 on success. */
int lt_write_png(const char *path, int width, int height, const unsigned char *rgb);

#endif
