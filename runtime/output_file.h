/* Output files written whole or not at all: the data goes to a temporary file beside the
 * target, which is renamed over the target only once every write, the flush and the close
 * have succeeded. A failure leaves the target as it was (an existing file is not destroyed)
 * and removes the temporary file. A target that exists and is not a regular file (a device
 * such as /dev/stdout or /dev/full, a pipe) is written in place, with every error checked. */
#ifndef LT_OUTPUT_FILE_H
#define LT_OUTPUT_FILE_H

#include <stdio.h>

#include "lazytrace.h"

typedef struct lt__output {
  FILE *file;   /* where to write */
  char *path;   /* the target */
  char *temp;   /* the temporary file, or NULL when writing in place */
} lt__output;

lt_status lt__output_open(lt__output *out, const char *path);
/* Flushes, closes and renames; the error names the path and the reason. */
lt_status lt__output_commit(lt__output *out);
/* Gives up: closes and removes the temporary file. */
void lt__output_abort(lt__output *out);

/* Tests set it to make the next commit fail as a full disk would, before the rename. */
extern int lt__output_fail_next_commit;

#endif
