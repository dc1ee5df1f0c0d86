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
  if (dst && src && dst != src) *dst = *src;
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

  /* Top-level numbers first, then the pool's counters as one nested object. */
  for (int i = 0; i < LT_STAT_COUNT; i++) {
    if (strncmp(key_names[i], "pool.", 5) == 0) continue;
    fprintf(out, ",\n  \"%s\": ", key_names[i]);
    write_number(out, stats->value[i], strstr(key_names[i], "_ms") != NULL);
  }
  fputs(",\n  \"pool\": {", out);
  const char *sep = "";
  for (int i = 0; i < LT_STAT_COUNT; i++) {
    if (strncmp(key_names[i], "pool.", 5) != 0) continue;
    fprintf(out, "%s\"%s\": ", sep, key_names[i] + 5);
    write_number(out, stats->value[i], 0);
    sep = ", ";
  }
  fputs("}\n}\n", out);
  return ferror(out) ? lt__fail(LT_ERROR_IO, "writing statistics failed") : LT_OK;
}

double lt_now_ms(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}
