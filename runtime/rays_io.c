/* The ray and hit files of the contract: little-endian records of 32 and 16 bytes; and whole
 * output files for the command line. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>

#include "runtime/error.h"
#include "runtime/output_file.h"

_Static_assert(sizeof(lt_ray) == 32, "a ray record is 32 bytes");
_Static_assert(sizeof(lt_hit) == 16, "a hit record is 16 bytes");

/* Reads a whole file of fixed-size records; a partial record is a parse error. */
static lt_status read_records(const char *path, size_t record, void **out, size_t *count) {
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  if (fseek(f, 0, SEEK_END) != 0) {
    fclose(f);
    return lt__fail(LT_ERROR_IO, "%s: cannot seek: %s", path, strerror(errno));
  }
  long size = ftell(f);
  rewind(f);
  if (size < 0 || (size_t)size % record != 0) {
    fclose(f);
    return lt__fail(LT_ERROR_PARSE, "%s: %ld bytes is not a whole number of %zu-byte records (truncated?)", path,
                    size, record);
  }
  void *data = malloc(size ? (size_t)size : 1);
  if (!data) {
    fclose(f);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %ld bytes", path, size);
  }
  size_t got = fread(data, 1, (size_t)size, f);
  fclose(f);
  if (got != (size_t)size) {
    free(data);
    return lt__fail(LT_ERROR_IO, "%s: short read (%zu of %ld bytes)", path, got, size);
  }
  *out = data;
  *count = (size_t)size / record;
  return LT_OK;
}

/* Written whole or not at all (runtime/output_file.h). */
static lt_status write_records(const char *path, const void *data, size_t record, size_t count) {
  lt__output out;
  lt_status status = lt__output_open(&out, path);
  if (status) return status;
  if (count && fwrite(data, record, count, out.file) != count) {
    int err = errno;
    lt__output_abort(&out);
    return lt__fail(LT_ERROR_IO, "%s: could not write: %s (the file is left as it was)", path, strerror(err));
  }
  return lt__output_commit(&out);
}

lt_status lt_file_write(const char *path, const void *data, size_t bytes) {
  if (!path || (bytes && !data)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_file_write: NULL argument");
  return write_records(path, data, 1, bytes);
}

int lt_files_same(const char *a, const char *b) {
  struct stat sa, sb;
  if (!a || !b || stat(a, &sa) != 0 || stat(b, &sb) != 0) return 0;
  return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

lt_status lt_rays_read(const char *path, lt_ray **rays, size_t *count) {
  if (!path || !rays || !count) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_rays_read: NULL argument");
  return read_records(path, sizeof(lt_ray), (void **)rays, count);
}

lt_status lt_rays_read_part(const char *path, size_t part, size_t parts, lt_ray **rays, size_t *count, size_t *first,
                            size_t *total) {
  if (!path || !rays || !count || !first || !total || parts < 1 || part >= parts)
    return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_rays_read_part: NULL argument or part %zu of %zu", part, parts);
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat st = {0};
  if (fstat(fileno(f), &st) != 0 || st.st_size < 0 || (size_t)st.st_size % sizeof(lt_ray) != 0) {
    long size = (long)st.st_size;
    fclose(f);
    return lt__fail(LT_ERROR_PARSE, "%s: %ld bytes is not a whole number of %zu-byte records (truncated?)", path, size,
                    sizeof(lt_ray));
  }

  /* floor(n * part / parts), written so that n * part cannot overflow. */
  size_t n = (size_t)st.st_size / sizeof(lt_ray), q = n / parts, rem = n % parts;
  size_t lo = q * part + rem * part / parts, hi = q * (part + 1) + rem * (part + 1) / parts;
  lt_ray *data = malloc(hi > lo ? (hi - lo) * sizeof *data : 1);
  if (!data) {
    fclose(f);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu rays", path, hi - lo);
  }
  size_t got = 0;
  if (hi > lo && fseeko(f, (off_t)(lo * sizeof *data), SEEK_SET) == 0) got = fread(data, sizeof *data, hi - lo, f);
  fclose(f);
  if (got != hi - lo) {
    free(data);
    return lt__fail(LT_ERROR_IO, "%s: short read (%zu of %zu rays from ray %zu)", path, got, hi - lo, lo);
  }
  *rays = data, *count = hi - lo, *first = lo, *total = n;
  return LT_OK;
}

lt_status lt_rays_write(const char *path, const lt_ray *rays, size_t count) {
  if (!path || (count && !rays)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_rays_write: NULL argument");
  return write_records(path, rays, sizeof(lt_ray), count);
}

lt_status lt_hits_read(const char *path, lt_hit **hits, size_t *count) {
  if (!path || !hits || !count) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_hits_read: NULL argument");
  return read_records(path, sizeof(lt_hit), (void **)hits, count);
}

lt_status lt_hits_write(const char *path, const lt_hit *hits, size_t count) {
  if (!path || (count && !hits)) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_hits_write: NULL argument");
  return write_records(path, hits, sizeof(lt_hit), count);
}
