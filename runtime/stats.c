/* Statistics: named counters and times, written as the contract's JSON object. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "runtime/error.h"
#include "runtime/stats_internal.h"

static const char *const key_names[LT_STAT_COUNT] = {
#define LT_STAT_NAME(id, key) key,
    LT_STAT_LIST(LT_STAT_NAME)
#undef LT_STAT_NAME
};

lt_status lt_stats_create(lt_stats **out) {
  if (!out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_stats_create: NULL argument");
  *out = malloc(sizeof **out);
  if (!*out) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "out of memory for statistics");
  lt_stats_reset(*out);
  return LT_OK;
}

void lt_stats_destroy(lt_stats *stats) { free(stats); }

void lt_stats_reset(lt_stats *stats) {
  memset(stats, 0, sizeof *stats);
  for (int i = 0; i < LT_STAT_COUNT; i++) stats->value[i] = -1.0;
}

void lt_stats_copy(lt_stats *dst, const lt_stats *src) {
  if (!dst || !src || dst == src) return;

  /* The frames belong to the animation dst sums up, not to the frame copied into it. */
  int frame_count = dst->frame_count;
  long frames_more = dst->frames_more;
  lt__frame_record frames[LT_STATS_MAX_FRAMES];
  memcpy(frames, dst->frames, (size_t)frame_count * sizeof *frames);
  *dst = *src;
  dst->frame_count = frame_count, dst->frames_more = frames_more;
  memcpy(dst->frames, frames, (size_t)frame_count * sizeof *frames);
}

static int key_index(const char *key) {
  for (int i = 0; i < LT_STAT_COUNT; i++)
    if (strcmp(key_names[i], key) == 0) return i;
  return -1;
}

double lt_stats_get(const lt_stats *stats, const char *key) {
  int i = stats && key ? key_index(key) : -1;
  return i < 0 ? -1.0 : stats->value[i];
}

const char *lt_stats_key(size_t i) { return i < LT_STAT_COUNT ? key_names[i] : NULL; }

const char *lt_stats_text(const lt_stats *stats, const char *key) {
  if (!stats || !key) return NULL;
  if (strcmp(key, "structure") == 0) return stats->structure;
  if (strcmp(key, "build") == 0) return stats->build;
  if (strcmp(key, "device") == 0) return stats->device;
  if (strcmp(key, "intersect") == 0) return stats->intersect;
  return NULL;
}

lt_status lt_stats_set(lt_stats *stats, const char *key, double value) {
  int i = stats && key ? key_index(key) : -1;
  if (i < 0) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "no statistic named '%s'", key ? key : "(null)");
  stats->value[i] = value;
  return LT_OK;
}

void lt__stats_add(lt_stats *stats, lt_stat_id id, double value) {
  if (!stats) return;
  stats->value[id] = (stats->value[id] < 0 ? 0 : stats->value[id]) + value;
}

void lt__stats_put(lt_stats *stats, lt_stat_id id, double value) {
  if (stats) stats->value[id] = value;
}

void lt__stats_text(lt_stats *stats, const char *key, const char *text) {
  if (!stats) return;
  char *slot = strcmp(key, "structure") == 0 ? stats->structure
               : strcmp(key, "build") == 0   ? stats->build
               : strcmp(key, "intersect") == 0 ? stats->intersect
                                              : stats->device;
  size_t size = slot == stats->device ? sizeof stats->device
                : slot == stats->intersect ? sizeof stats->intersect
                                           : sizeof stats->structure;
  snprintf(slot, size, "%s", text);
}

/* Writes a JSON string with the characters JSON requires escaped. */
static void write_string(FILE *out, const char *s) {
  fputc('"', out);
  for (; *s; s++) {
    if (*s == '"' || *s == '\\') fprintf(out, "\\%c", *s);
    else if ((unsigned char)*s < 0x20) fprintf(out, "\\u%04x", *s);
    else fputc(*s, out);
  }
  fputc('"', out);
}

static void write_number(FILE *out, double v, int is_time) {
  if (v < 0 || !isfinite(v)) fputs("null", out);
  else if (is_time) fprintf(out, "%.3f", v);
  else if (v == floor(v)) fprintf(out, "%.0f", v);
  else fprintf(out, "%.6g", v);
}

/* `, "name": value` inside a record. */
static void write_field(FILE *out, const char *name, double v, int is_time) {
  fprintf(out, ", \"%s\": ", name);
  write_number(out, v, is_time);
}

void lt__stats_batch(lt_stats *stats, const char *effect, double rays, double ms, double nodes_built) {
  if (!stats) return;
  if (stats->batch_count == LT_STATS_MAX_BATCHES) {
    stats->batches_more++;
    return;
  }
  lt__batch_record *b = &stats->batches[stats->batch_count++];
  snprintf(b->effect, sizeof b->effect, "%s", effect);
  b->rays = rays, b->ms = ms, b->nodes_built = nodes_built;
}

void lt_stats_add_frame(lt_stats *stats, const lt_stats *frame) {
  if (!stats || !frame) return;
  if (stats->frame_count == LT_STATS_MAX_FRAMES) {
    stats->frames_more++;
    return;
  }
  lt__frame_record *f = &stats->frames[stats->frame_count++];
  f->rays = frame->value[LT_STAT_RAYS];
  f->build_ms = frame->value[LT_STAT_BUILD_MS];
  f->trace_ms = frame->value[LT_STAT_TRACE_MS];
  f->total_ms = frame->value[LT_STAT_TOTAL_MS];
  f->nodes_built = frame->value[LT_STAT_NODES_BUILT];
}

/* An animation's frames, one record each; null when nothing was animated. */
static void write_frames(const lt_stats *stats, FILE *out) {
  fputs(",\n  \"frames\": ", out);
  if (stats->frame_count == 0) fputs("null", out);
  for (int i = 0; i < stats->frame_count; i++) {
    const lt__frame_record *f = &stats->frames[i];
    fprintf(out, "%s\n    {\"frame\": %d", i ? "," : "[", i);
    write_field(out, "rays", f->rays, 0);
    write_field(out, "build_ms", f->build_ms, 1);
    write_field(out, "trace_ms", f->trace_ms, 1);
    write_field(out, "total_ms", f->total_ms, 1);
    write_field(out, "nodes_built", f->nodes_built, 0);
    fputs("}", out);
  }
  if (stats->frame_count) fputs("\n  ]", out);
  fputs(",\n  \"frames_not_recorded\": ", out);
  write_number(out, stats->frame_count ? (double)stats->frames_more : -1.0, 0);
}

/* The length of a nested key's prefix ("pool" of "pool.tasks"), or 0 for a top-level key. */
static size_t prefix_length(const char *key) {
  const char *dot = strchr(key, '.');
  return dot ? (size_t)(dot - key) : 0;
}

/* The nested object whose keys start with the prefix of key i; a group whose values all do not
 * apply is null, except the pool's, which has always been written as an object. */
static void write_group(const lt_stats *stats, FILE *out, int first) {
  size_t n = prefix_length(key_names[first]);
  int any = strncmp(key_names[first], "pool.", 5) == 0;
  for (int i = first; i < LT_STAT_COUNT; i++)
    if (prefix_length(key_names[i]) == n && strncmp(key_names[i], key_names[first], n) == 0) any |= stats->value[i] >= 0;
  fprintf(out, ",\n  \"%.*s\": ", (int)n, key_names[first]);
  if (!any) {
    fputs("null", out);
    return;
  }
  const char *sep = "{";
  for (int i = first; i < LT_STAT_COUNT; i++) {
    if (prefix_length(key_names[i]) != n || strncmp(key_names[i], key_names[first], n) != 0) continue;
    fprintf(out, "%s\"%s\": ", sep, key_names[i] + n + 1);
    write_number(out, stats->value[i], strstr(key_names[i], "_ms") != NULL || strncmp(key_names[i], "ms_", 3) == 0);
    sep = ", ";
  }
  fputs("}", out);
}

lt_status lt_stats_write_json(const lt_stats *stats, FILE *out) {
  if (!stats || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_stats_write_json: NULL argument");
  fputs("{\n  \"structure\": ", out);
  write_string(out, stats->structure);
  fputs(",\n  \"build\": ", out);
  write_string(out, stats->build);
  fputs(",\n  \"device\": ", out);
  write_string(out, stats->device);
  fputs(",\n  \"intersect\": ", out);
  if (stats->intersect[0]) write_string(out, stats->intersect);
  else fputs("null", out);

  /* Top-level numbers first, then each group of dotted keys as one nested object, in the
   * order the list gives them. */
  for (int i = 0; i < LT_STAT_COUNT; i++) {
    if (prefix_length(key_names[i])) continue;
    fprintf(out, ",\n  \"%s\": ", key_names[i]);
    write_number(out, stats->value[i], strstr(key_names[i], "_ms") != NULL);
  }
  for (int i = 0; i < LT_STAT_COUNT; i++) {
    size_t n = prefix_length(key_names[i]);
    if (n && (i == 0 || prefix_length(key_names[i - 1]) != n || strncmp(key_names[i - 1], key_names[i], n) != 0))
      write_group(stats, out, i);
  }

  /* A render's batches, one record each. */
  fputs(",\n  \"batches\": ", out);
  if (stats->batch_count == 0) fputs("null", out);
  for (int b = 0; b < stats->batch_count; b++) {
    const lt__batch_record *r = &stats->batches[b];
    fprintf(out, "%s\n    {\"effect\": ", b ? "," : "[");
    write_string(out, r->effect);
    write_field(out, "rays", r->rays, 0);
    write_field(out, "ms", r->ms, 1);
    write_field(out, "nodes_built", r->nodes_built, 0);
    fputs("}", out);
  }
  if (stats->batch_count) fputs("\n  ]", out);
  fputs(",\n  \"batches_not_recorded\": ", out);
  write_number(out, stats->batch_count ? (double)stats->batches_more : -1.0, 0);
  write_frames(stats, out);
  fputs("\n}\n", out);
  return ferror(out) ? lt__fail(LT_ERROR_IO, "writing statistics failed") : LT_OK;
}

double lt_now_ms(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
