/* The host registry of structures: one entry per structure (its name, parameters and their
 * defaults, help, build modes, and the functions that create, trace, report and release it),
 * one line per structure in LT_STRUCTURE_LIST (lazytrace.h). The library's generic code
 * (runtime/structure.c), the command line's names and help, and the variant lists of tests
 * and benchmarks all read it. docs/notes/structures.md says how to add an entry. */
#ifndef LT_REGISTRY_H
#define LT_REGISTRY_H

#include <stddef.h>

#include "runtime/structure_internal.h"

/* A parameter a structure reads: its command-line option, the lt_structure_config field it
 * sets, the accepted range, and a few words for help (the default is in the entry's defaults). */
typedef struct lt__param {
  const char *option; /* "--leaf-size" */
  size_t offset;      /* of an int or float field of lt_structure_config */
  int is_float;
  double min, max;
  const char *help;
  const char *names;  /* a choice: "stack|restart|backtrack", stored as 1 + the name's index (0:
                         the default); NULL for a number */
} lt__param;

#define LT__PARAM_INT(opt, field, lo, hi, text) {opt, offsetof(lt_structure_config, field), 0, lo, hi, text, NULL}
#define LT__PARAM_FLOAT(opt, field, lo, hi, text) {opt, offsetof(lt_structure_config, field), 1, lo, hi, text, NULL}
#define LT__PARAM_CHOICE(opt, field, choices, text) {opt, offsetof(lt_structure_config, field), 0, 0, 0, text, choices}

typedef struct lt__structure_class {
  const char *name;       /* what --structure takes */
  const char *summary;    /* one line for help */
  const lt__param *params; /* the options it reads, ended by an entry without an option */
  unsigned modes;         /* the build modes it can be built in: bits 1 << lt_build_mode */
  lt_structure_config defaults; /* every field filled in (kind and build included) */
  size_t state_size;      /* bytes of its own state, zeroed, at lt_structure.state */

  /* Builds (or prepares, on demand) the structure over s->scene with s->config, which holds no
   * zero defaults any more; adds build time and counters to stats (may be NULL). */
  lt_status (*create)(lt_structure *s, lt_stats *stats);
  /* Traces a batch with query flags (LT_QUERY_FLAG_*); adds build_ms, trace_ms, traversal
   * steps and intersections to stats (may be NULL). */
  lt_status (*trace)(lt_structure *s, const lt_ray *rays, int count, int flags, lt_hit *hits, lt_stats *stats);
  /* Puts the structure's own statistics (nodes, references, memory, depth, cost). */
  void (*put_stats)(lt_structure *s, lt_stats *stats);
  /* Frees what create made (also after a failed create). */
  void (*release)(lt_structure *s);
  /* The kernel entry points it launches, NULL-terminated (for docs and tests). */
  const char *const *kernels;
} lt__structure_class;

/* The entry of a kind, or NULL for a kind out of range. */
const lt__structure_class *lt__structure_class_of(lt_structure_kind kind);

/* Each entry is defined in its structure's own host file as lt__structure_<entry>. */
#define LT__STRUCTURE_DECLARE(kind, entry) extern const lt__structure_class lt__structure_##entry;
LT_STRUCTURE_LIST(LT__STRUCTURE_DECLARE)
#undef LT__STRUCTURE_DECLARE

#endif
