/* lazytrace's own Wavefront OBJ reader. It exists so that triangle numbering follows the
 * contract (faces in file order, each polygon fanned as (v0, vi, vi+1)) and so that every error
 * names the file and line. Only vertex positions and faces matter; everything else is skipped. */
#include "scene_internal.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"

/* Tokens quoted in error messages are cut to this many characters. */
#define QUOTE_MAX 40

typedef struct obj_reader {
  const char *path;
  size_t line;           /* 1-based number of the line being parsed */
  float *verts;          /* 3 floats per vertex, in file order */
  size_t vert_count;     /* vertices read so far */
  size_t vert_capacity;  /* vertices the verts buffer holds */
  lt_scene *scene;
} obj_reader;

/* '\n' and '\r' count as blanks so that LF and CRLF line endings both end the last token. */
static int is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

static int is_token_end(char c) { return c == '\0' || is_blank(c); }

static char *skip_blanks(char *s) {
  while (is_blank(*s)) s++;
  return s;
}

static size_t token_length(const char *s) {
  size_t n = 0;
  while (!is_token_end(s[n])) n++;
  return n;
}

static int token_is(const char *token, size_t len, const char *word) {
  return strlen(word) == len && memcmp(token, word, len) == 0;
}

static int quote_length(size_t len) { return len > QUOTE_MAX ? QUOTE_MAX : (int)len; }

static lt_status push_vertex(obj_reader *r, const float p[3]) {
  if (r->vert_count == r->vert_capacity) {
    size_t capacity = r->vert_capacity ? 2 * r->vert_capacity : 4096;
    float *verts = realloc(r->verts, capacity * 3 * sizeof *verts);
    if (!verts)
      return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s:%zu: out of memory growing the vertex list to %zu vertices",
                      r->path, r->line, capacity);
    r->verts = verts;
    r->vert_capacity = capacity;
  }
  memcpy(r->verts + 3 * r->vert_count++, p, 3 * sizeof *p);
  return LT_OK;
}

/* Parses one number that must fill the whole token; nan and inf are accepted here because the
 * scene drops and counts triangles that use them. */
static int parse_number(const char *token, float *out) {
  char *end;
  *out = strtof(token, &end);
  return end != token && is_token_end(*end);
}

/* "v x y z [w]". A fourth number is the rational-curve weight, which polygons ignore; some
 * exporters append r g b vertex colours instead, so any further numbers are accepted too. */
static lt_status parse_vertex(obj_reader *r, char *s) {
  float p[3];
  int count = 0;
  for (s = skip_blanks(s); *s; s = skip_blanks(s + token_length(s))) {
    float value;
    if (!parse_number(s, &value)) {
      size_t len = token_length(s);
      return lt__fail(LT_ERROR_PARSE, "%s:%zu: vertex coordinate '%.*s' is not a number", r->path, r->line,
                      quote_length(len), s);
    }
    if (count < 3) p[count] = value;
    count++;
  }
  if (count < 3) return lt__fail(LT_ERROR_PARSE, "%s:%zu: vertex needs 3 coordinates", r->path, r->line);
  return push_vertex(r, p);
}

/* Reads one optional signed integer part of a face vertex; returns the position after it, or
 * NULL if the part is neither empty nor an integer. An index too large for a long comes back
 * as LONG_MAX or LONG_MIN, which no vertex count reaches, so it fails the range check. */
static const char *parse_integer(const char *s, long *out, int *present) {
  /* strtol would skip blanks and read the next token's digits, so an empty part stops here. */
  if (*s == '/' || is_token_end(*s)) {
    *present = 0;
    return s;
  }
  char *end;
  *out = strtol(s, &end, 10);
  *present = end != s;
  return *present ? end : NULL;
}

/* Checks the shape of one face vertex: i, i/j, i//k or i/j/k (the texture and normal indices
 * are not used, but must be integers when present). Returns 1 and the position index if so. */
static int split_face_vertex(const char *token, long *index) {
  int present;
  const char *s = parse_integer(token, index, &present);
  if (!s || !present) return 0;
  for (int part = 0; part < 2 && *s == '/'; part++) {
    long ignored;
    s = parse_integer(s + 1, &ignored, &present);
    if (!s) return 0;
  }
  return is_token_end(*s);
}

/* Turns one face vertex token into a 0-based position index, resolving negative (relative)
 * indices against the vertices read so far. */
static lt_status resolve_face_vertex(obj_reader *r, const char *token, size_t *out) {
  long index;
  size_t len = token_length(token);
  if (!split_face_vertex(token, &index))
    return lt__fail(LT_ERROR_PARSE, "%s:%zu: face vertex '%.*s' is not an index", r->path, r->line,
                    quote_length(len), token);
  if (index == 0)
    return lt__fail(LT_ERROR_PARSE, "%s:%zu: face index 0 is invalid (OBJ indices start at 1)", r->path, r->line);

  /* Index -1 is the vertex read last; positive indices count from 1. */
  size_t n = r->vert_count;
  int in_range = index > 0 ? (unsigned long)index <= n : (unsigned long)-(index + 1) < n;
  if (!in_range)
    return lt__fail(LT_ERROR_PARSE, "%s:%zu: face index %ld out of range (%zu vertices so far)", r->path, r->line,
                    index, n);
  *out = index > 0 ? (size_t)index - 1 : n - (size_t)(-(index + 1)) - 1;
  return LT_OK;
}

/* "f v1 v2 v3 ...": the polygon is fanned as (v0, vi, vi+1) while it is read, so faces of any
 * size need no buffer. */
static lt_status parse_face(obj_reader *r, char *s) {
  size_t count = 0, first = 0, prev = 0;
  for (s = skip_blanks(s); *s; s = skip_blanks(s + token_length(s))) {
    size_t index = 0;
    lt_status status = resolve_face_vertex(r, s, &index);
    if (status) return status;
    if (count == 0) first = index;
    if (count >= 2) {
      status = lt__scene_add_tri(r->scene, r->verts + 3 * first, r->verts + 3 * prev, r->verts + 3 * index);
      if (status) return status;
    }
    prev = index;
    count++;
  }
  if (count < 3) return lt__fail(LT_ERROR_PARSE, "%s:%zu: face with fewer than 3 vertices", r->path, r->line);
  return LT_OK;
}

static lt_status parse_line(obj_reader *r, char *line) {
  /* A '#' starts a comment wherever it stands; some exporters put them after the data. */
  char *hash = strchr(line, '#');
  if (hash) *hash = '\0';

  /* Only positions and faces carry triangles. Normals, texture coordinates, groups, smoothing,
   * materials, lines, points and the free-form statements are skipped. */
  char *keyword = skip_blanks(line);
  size_t len = token_length(keyword);
  if (token_is(keyword, len, "v")) return parse_vertex(r, keyword + len);
  if (token_is(keyword, len, "f")) return parse_face(r, keyword + len);
  return LT_OK;
}

static lt_status read_lines(obj_reader *r, FILE *f) {
  char *line = NULL;
  size_t size = 0;
  lt_status status = LT_OK;

  /* getline reuses one buffer and grows it for long lines, so no line is ever truncated. */
  for (;;) {
    errno = 0;
    ssize_t n = getline(&line, &size, f);
    if (n < 0) break;
    r->line++;
    status = parse_line(r, line);
    if (status) break;
  }
  if (!status && ferror(f))
    status = lt__fail(LT_ERROR_IO, "%s:%zu: read failed: %s", r->path, r->line + 1, strerror(errno));
  else if (!status && errno == ENOMEM)
    status = lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s:%zu: out of memory reading a line", r->path, r->line + 1);
  free(line);
  return status;
}

lt_status lt__load_obj(const char *path, lt_scene *scene) {
  if (!path || !scene) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__load_obj: NULL argument");
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));

  obj_reader reader = {.path = path, .scene = scene};
  lt_status status = read_lines(&reader, f);
  fclose(f);
  free(reader.verts);
  return status;
}
