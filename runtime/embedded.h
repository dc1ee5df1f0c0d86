/* Kernel sources embedded at build time (cmake/embed_sources.cmake). */
#ifndef LT_EMBEDDED_H
#define LT_EMBEDDED_H

typedef struct lt__embedded_file {
  const char *path;     /* relative to the source root, e.g. "traversal/bvh_traverse.h" */
  const char *contents; /* NUL-terminated text */
} lt__embedded_file;

/* Terminated by an entry whose path is NULL. */
extern const lt__embedded_file lt__embedded_files[];

#endif
