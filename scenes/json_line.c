/* The line of a JSON value named by a key path ("instances[2].keyframes[1].time"), for error
 * messages: cJSON keeps no positions, so the text is walked again along the path. The text has
 * already parsed, so this reader can trust its syntax. */
#include <stdlib.h>
#include <string.h>

#include "scenes/scene_internal.h"

/* Whitespace as cJSON reads it: every control character and the space. */
static const char *skip_space(const char *c) {
  while (*c && (unsigned char)*c <= 32) c++;
  return c;
}

/* Past the string that starts at c (on its opening quote). */
static const char *skip_string(const char *c) {
  for (c++; *c && *c != '"'; c++)
    if (*c == '\\' && c[1]) c++;
  return *c ? c + 1 : c;
}

/* Past the value that starts at c. */
static const char *skip_value(const char *c) {
  if (*c == '"') return skip_string(c);
  if (*c != '{' && *c != '[') {
    while ((unsigned char)*c > 32 && *c != ',' && *c != '}' && *c != ']') c++;
    return c;
  }
  int depth = 0;
  for (; *c; c++) {
    if (*c == '"') c = skip_string(c) - 1;
    else if (*c == '{' || *c == '[') depth++;
    else if ((*c == '}' || *c == ']') && --depth == 0) return c + 1;
  }
  return c;
}

/* The value of member `name` (length n) of the object at c, or NULL. */
static const char *member(const char *c, const char *name, size_t n) {
  if (*c != '{') return NULL;
  for (c = skip_space(c + 1); *c == '"';) {
    const char *key = c + 1, *end = skip_string(c);
    int match = (size_t)(end - 1 - key) == n && strncmp(key, name, n) == 0;
    c = skip_space(end);
    if (*c != ':') return NULL;
    c = skip_space(c + 1);
    if (match) return c;
    c = skip_space(skip_value(c));
    if (*c == ',') c = skip_space(c + 1);
  }
  return NULL;
}

/* Element i of the array at c, or NULL. */
static const char *element(const char *c, long i) {
  if (*c != '[') return NULL;
  for (c = skip_space(c + 1); *c && *c != ']'; i--) {
    if (i == 0) return c;
    c = skip_space(skip_value(c));
    if (*c == ',') c = skip_space(c + 1);
  }
  return NULL;
}

int lt__json_line(const char *text, const char *path) {
  if (!text) return 0;
  const char *at = skip_space(text), *p = path ? path : "";

  /* Follow the path as far as the text has it: a missing key names its object's line. */
  while (*p) {
    const char *next;
    if (*p == '[') {
      char *end;
      next = element(at, strtol(p + 1, &end, 10));
      p = *end == ']' ? end + 1 : end;
    } else {
      size_t n = strcspn(p, ".[");
      next = member(at, p, n);
      p += n;
    }
    if (*p == '.') p++;
    if (!next) break;
    at = next;
  }
  int line = 1;
  for (const char *c = text; c < at; c++) line += *c == '\n';
  return line;
}
