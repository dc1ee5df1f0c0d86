/* Kernel source assembly: the embedded files with their quoted includes expanded, each file
 * once, as Cycles did, because OpenCL drivers cache binaries without looking at includes. A
 * body instantiated by include (a file named *_body.h, with no include guard) is expanded at
 * every include, as the preprocessor would. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/context_internal.h"
#include "runtime/embedded.h"

typedef struct text {
  char *data;
  size_t len, cap;
} text;

static int append(text *t, const char *s, size_t n) {
  if (t->len + n + 1 > t->cap) {
    size_t cap = (t->len + n + 1) * 2;
    char *data = realloc(t->data, cap);
    if (!data) return -1;
    t->data = data, t->cap = cap;
  }
  memcpy(t->data + t->len, s, n);
  t->len += n;
  t->data[t->len] = '\0';
  return 0;
}

static int find_file(const char *path) {
  for (int i = 0; lt__embedded_files[i].path; i++)
    if (strcmp(lt__embedded_files[i].path, path) == 0) return i;
  return -1;
}

static int is_body(const char *path) {
  size_t n = strlen(path);
  return n >= 7 && strcmp(path + n - 7, "_body.h") == 0;
}

/* Appends file `index`, replacing each `#include "x"` line by x's text the first time (every
 * time for a body). */
static int expand(text *t, int index, unsigned char *seen) {
  if (seen[index] && !is_body(lt__embedded_files[index].path)) return 0;
  seen[index] = 1;
  const char *s = lt__embedded_files[index].contents;
  while (*s) {
    const char *end = strchr(s, '\n');
    size_t n = end ? (size_t)(end - s + 1) : strlen(s);
    const char *q = s;
    while (*q == ' ' || *q == '\t') q++;
    if (strncmp(q, "#include \"", 10) == 0) {
      char name[256];
      const char *close = strchr(q + 10, '"');
      size_t len = close ? (size_t)(close - q - 10) : 0;
      if (!close || len >= sizeof name) return -1;
      memcpy(name, q + 10, len);
      name[len] = '\0';
      int inc = find_file(name);
      if (inc < 0 || expand(t, inc, seen) != 0) return -1;
    } else if (append(t, s, n) != 0) {
      return -1;
    }
    s += n;
  }
  return 0;
}

char *lt__kernel_source(const char *path, uint64_t *hash) {
  int count = 0;
  while (lt__embedded_files[count].path) count++;
  unsigned char *seen = calloc(count ? count : 1, 1);
  text t = {0};
  int index = find_file(path);
  if (!seen || index < 0 || expand(&t, index, seen) != 0) {
    free(seen);
    free(t.data);
    return NULL;
  }
  free(seen);

  /* FNV-1a over the expanded text. */
  uint64_t h = 1469598103934665603ull;
  for (size_t i = 0; i < t.len; i++) h = (h ^ (unsigned char)t.data[i]) * 1099511628211ull;
  if (hash) *hash = h;
  return t.data;
}
