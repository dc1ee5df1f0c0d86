/* Output files written whole or not at all (see output_file.h). */
#include "runtime/output_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "runtime/error.h"

int lt__output_fail_next_commit;

lt_status lt__output_open(lt__output *out, const char *path) {
  memset(out, 0, sizeof *out);
  if (!path || !*path) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "no output path given");
  out->path = strdup(path);
  if (!out->path) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory");

  /* Devices and pipes are written in place: there is nothing to rename over them. */
  struct stat st;
  if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
    out->file = fopen(path, "wb");
    if (!out->file) {
      lt_status status = lt__fail(LT_ERROR_IO, "%s: cannot open for writing: %s", path, strerror(errno));
      lt__output_abort(out);
      return status;
    }
    return LT_OK;
  }

  /* A temporary file in the target's directory, so that the rename stays on one file system. */
  size_t n = strlen(path);
  out->temp = malloc(n + 16);
  if (!out->temp) {
    lt__output_abort(out);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory");
  }
  snprintf(out->temp, n + 16, "%s.tmp.XXXXXX", path);
  int fd = mkstemp(out->temp);
  if (fd < 0) {
    lt_status status = lt__fail(LT_ERROR_IO, "%s: cannot write there: %s", path, strerror(errno));
    free(out->temp), out->temp = NULL;
    lt__output_abort(out);
    return status;
  }
  fchmod(fd, 0644);
  out->file = fdopen(fd, "wb");
  if (!out->file) {
    close(fd);
    lt_status status = lt__fail(LT_ERROR_IO, "%s: cannot write there: %s", path, strerror(errno));
    lt__output_abort(out);
    return status;
  }
  return LT_OK;
}

lt_status lt__output_commit(lt__output *out) {
  int failed = ferror(out->file) || fflush(out->file) != 0;
  int err = errno;
  if (out->temp && !failed) failed = fsync(fileno(out->file)) != 0, err = errno;
  if (lt__output_fail_next_commit) failed = 1, err = ENOSPC, lt__output_fail_next_commit = 0;
  if (fclose(out->file) != 0 && !failed) failed = 1, err = errno;
  out->file = NULL;
  if (!failed && out->temp && rename(out->temp, out->path) != 0) failed = 1, err = errno;
  lt_status status = failed ? lt__fail(LT_ERROR_IO, "%s: could not write: %s%s", out->path, strerror(err),
                                       out->temp ? " (the file is left as it was)" : "")
                            : LT_OK;
  if (!failed && out->temp) free(out->temp), out->temp = NULL;
  lt__output_abort(out);
  return status;
}

void lt__output_abort(lt__output *out) {
  if (out->file) fclose(out->file);
  if (out->temp) unlink(out->temp);
  free(out->temp);
  free(out->path);
  memset(out, 0, sizeof *out);
}
