/* lazytrace's own PLY reader: ascii 1.0, binary_little_endian 1.0 and binary_big_endian 1.0.
 * It reads x, y, z of the vertex element and the vertex_indices (or vertex_index) list of each
 * face element; every other property and element is read past. Triangle numbering follows the
 * contract: faces in file order, each polygon fanned as (v0, vi, vi+1), as for OBJ.
 *
 * The whole file is read into memory once and parsed from there. Every count the header
 * declares is checked against the bytes after it before anything is allocated for it, each
 * value read moves forward through the buffer or fails, and errors name the file with the line
 * (header and ascii bodies) or the element, item and byte offset (binary bodies). Items count
 * from 0, as PLY's vertex indices do. */
#include <errno.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "runtime/error.h"
#include "scene_internal.h"

/* Tokens quoted in error messages are cut to this many characters. */
#define QUOTE_MAX 40
/* Fixed tables keep the header free of allocation. A 3D Gaussian splat vertex, among the widest
 * in use, has 62 properties. */
#define MAX_ELEMENTS   32
#define MAX_PROPERTIES 256
#define MAX_WORDS      6

enum { FORMAT_NONE, FORMAT_ASCII, FORMAT_LITTLE, FORMAT_BIG };
enum { ROLE_OTHER, ROLE_X, ROLE_Y, ROLE_Z, ROLE_INDICES };

/* The scalar types under both their names: bytes in binary, integer or not, signed or not. */
static const struct ply_type {
  const char *name, *alias;
  unsigned char size, is_int, is_signed;
} types[] = {{"char", "int8", 1, 1, 1},     {"uchar", "uint8", 1, 1, 0},   {"short", "int16", 2, 1, 1},
             {"ushort", "uint16", 2, 1, 0}, {"int", "int32", 4, 1, 1},     {"uint", "uint32", 4, 1, 0},
             {"float", "float32", 4, 0, 1}, {"double", "float64", 8, 0, 1}};

/* A word of the file, with its length as quoted in messages (at most QUOTE_MAX). */
typedef struct word {
  const char *s;
  size_t len;
  int n;
} word;

typedef struct ply_property {
  word name;      /* points into the file's buffer */
  int type;       /* index into types: a scalar's type or a list's item type */
  int count_type; /* a list's count type, or -1 for a scalar */
  int role;
} ply_property;

typedef struct ply_element {
  word name;
  size_t count, line;               /* items declared; the header line that declares them */
  int first, property_count, roles; /* properties[first..]; roles: bit per ROLE_ found */
} ply_element;

typedef struct ply_reader {
  const char *path;
  char *data;          /* the whole file, with a '\0' after it */
  const char *p, *end; /* what is left to read */
  size_t line;         /* 1-based line of p (header and ascii bodies) */
  int format;
  ply_element elements[MAX_ELEMENTS];
  ply_property properties[MAX_PROPERTIES];
  int element_count, property_count, vertex_element; /* vertex_element: -1 until declared */
  const ply_element *element;                        /* in the body: the element, item and value being read */
  size_t item;
  const char *value_at;
  float *verts;      /* 3 floats per vertex */
  size_t vert_count; /* vertices read, once the whole vertex element is */
  lt_scene *scene;
} ply_reader;

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }

static int is(word w, const char *text) { return strlen(text) == w.len && memcmp(w.s, text, w.len) == 0; }

static word make_word(const char *s, size_t len) { return (word){s, len, len > QUOTE_MAX ? QUOTE_MAX : (int)len}; }

/* Splits [s, end) into blank-separated words; returns how many, MAX_WORDS + 1 for more. */
static int split_words(const char *s, const char *end, word out[MAX_WORDS]) {
  int n = 0;
  while (s < end) {
    if (is_blank(*s)) {
      s++;
      continue;
    }
    const char *start = s;
    while (s < end && !is_blank(*s)) s++;
    if (n == MAX_WORDS) return MAX_WORDS + 1;
    out[n++] = make_word(start, (size_t)(s - start));
  }
  return n;
}

static int find_type(word w) {
  for (int t = 0; t < (int)(sizeof types / sizeof types[0]); t++)
    if (is(w, types[t].name) || is(w, types[t].alias)) return t;
  return -1;
}

/* A whole number of digits only, no sign, that fits a size_t. */
static int parse_count(word w, size_t *out) {
  size_t n = 0;
  for (size_t i = 0; i < w.len; i++) {
    if (w.s[i] < '0' || w.s[i] > '9' || n > (SIZE_MAX - (size_t)(w.s[i] - '0')) / 10) return 0;
    n = 10 * n + (size_t)(w.s[i] - '0');
  }
  *out = n;
  return w.len > 0;
}

/* Fails with the place being read: the line in the header and in ascii bodies, the element, item
 * and byte offset in binary bodies. */
__attribute__((format(printf, 2, 3))) static lt_status parse_fail(const ply_reader *r, const char *fmt, ...) {
  char message[256];
  va_list args;
  va_start(args, fmt);
  vsnprintf(message, sizeof message, fmt, args);
  va_end(args);
  if (!r->element) return lt__fail(LT_ERROR_PARSE, "%s:%zu: %s", r->path, r->line, message);
  word e = r->element->name;
  if (r->format == FORMAT_ASCII)
    return lt__fail(LT_ERROR_PARSE, "%s:%zu: %.*s %zu: %s", r->path, r->line, e.n, e.s, r->item, message);
  return lt__fail(LT_ERROR_PARSE, "%s: %.*s %zu at byte %zu: %s", r->path, e.n, e.s, r->item,
                  (size_t)(r->value_at - r->data), message);
}

static lt_status add_element(ply_reader *r, const word *w, int n) {
  if (n != 3) return parse_fail(r, "expected 'element NAME COUNT'");
  if (r->element_count == MAX_ELEMENTS) return parse_fail(r, "more than %d elements", MAX_ELEMENTS);
  ply_element *e = &r->elements[r->element_count];
  *e = (ply_element){.name = w[1], .line = r->line, .first = r->property_count};
  if (!parse_count(w[2], &e->count))
    return parse_fail(r, "element count '%.*s' is not a whole number from 0", w[2].n, w[2].s);
  if (is(w[1], "vertex")) {
    if (r->vertex_element >= 0) return parse_fail(r, "a second vertex element");
    r->vertex_element = r->element_count;
  }
  /* Faces are fanned while they are read, so the vertices must be known by then. */
  if (is(w[1], "face") && r->vertex_element < 0)
    return parse_fail(r, "the face element comes before the vertex element");
  r->element_count++;
  return LT_OK;
}

/* "property TYPE NAME" or "property list COUNT_TYPE ITEM_TYPE NAME". */
static lt_status add_property(ply_reader *r, const word *w, int n) {
  if (r->element_count == 0) return parse_fail(r, "a property before any element");
  if (r->property_count == MAX_PROPERTIES) return parse_fail(r, "more than %d properties", MAX_PROPERTIES);
  int list = n == 5 && is(w[1], "list");
  if (n != 3 && !list)
    return parse_fail(r, "expected 'property TYPE NAME' or 'property list COUNT_TYPE ITEM_TYPE NAME'");
  ply_property *p = &r->properties[r->property_count];
  *p = (ply_property){.name = w[n - 1], .type = find_type(w[n - 2]), .count_type = list ? find_type(w[2]) : -1};
  for (int i = list ? 2 : 1; i < n - 1; i++)
    if (find_type(w[i]) < 0) return parse_fail(r, "unknown type '%.*s'", w[i].n, w[i].s);
  if (list && !types[p->count_type].is_int)
    return parse_fail(r, "a list count of type '%.*s' (an integer type is needed)", w[2].n, w[2].s);

  /* Only the properties that carry triangles get a role; the rest are read past. */
  ply_element *e = &r->elements[r->element_count - 1];
  if (!list && r->element_count - 1 == r->vertex_element)
    p->role = is(p->name, "x") ? ROLE_X : is(p->name, "y") ? ROLE_Y : is(p->name, "z") ? ROLE_Z : ROLE_OTHER;
  if (list && is(e->name, "face") && !(e->roles & 1 << ROLE_INDICES) &&
      (is(p->name, "vertex_indices") || is(p->name, "vertex_index"))) {
    if (!types[p->type].is_int)
      return parse_fail(r, "vertex indices of type '%.*s' (an integer type is needed)", w[3].n, w[3].s);
    p->role = ROLE_INDICES;
  }
  e->roles |= 1 << p->role;
  e->property_count++;
  r->property_count++;
  return LT_OK;
}

/* The element's smallest size in the body: 1 byte per byte of each scalar and list count in
 * binary; in ascii a digit and a separator per value. */
static size_t min_item_bytes(const ply_reader *r, const ply_element *e) {
  size_t bytes = 0;
  for (int i = 0; i < e->property_count; i++) {
    const ply_property *p = &r->properties[e->first + i];
    bytes += r->format == FORMAT_ASCII ? 2 : types[p->count_type >= 0 ? p->count_type : p->type].size;
  }
  return bytes;
}

/* After end_header: what the body needs is there, and the declared counts fit in it. */
static lt_status check_header(ply_reader *r) {
  if (r->format == FORMAT_NONE) return parse_fail(r, "the header has no format line");
  /* The last ascii value may end the file without a separator. */
  size_t ascii = r->format == FORMAT_ASCII, left = (size_t)(r->end - r->p) + ascii;
  for (int i = 0; i < r->element_count; i++) {
    const ply_element *e = &r->elements[i];
    r->line = e->line;
    if (i == r->vertex_element)
      for (int role = ROLE_X; role <= ROLE_Z; role++)
        if (!(e->roles & 1 << role))
          return parse_fail(r, "the vertex element has no property %c", "xyz"[role - ROLE_X]);
    if (is(e->name, "face") && !(e->roles & 1 << ROLE_INDICES))
      return parse_fail(r, "the face element has no vertex_indices list");
    size_t bytes = min_item_bytes(r, e);
    if (bytes && e->count > left / bytes)
      return lt__fail(LT_ERROR_PARSE,
                      "%s: the header declares %zu %.*s elements (line %zu) of at least %zu bytes "
                      "each, more than the %zu bytes left for them can hold",
                      r->path, e->count, e->name.n, e->name.s, e->line, bytes, left > ascii ? left - ascii : 0);
    left -= bytes * e->count;
  }
  return LT_OK;
}

static lt_status read_header_line(ply_reader *r, const word *w, int n) {
  if (is(w[0], "element")) return add_element(r, w, n);
  if (is(w[0], "property")) return add_property(r, w, n);
  if (!is(w[0], "format"))
    return parse_fail(r, "not a PLY header line (format, comment, obj_info, element, property or end_header)");
  if (n != 3) return parse_fail(r, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
  r->format = is(w[1], "ascii")                  ? FORMAT_ASCII
              : is(w[1], "binary_little_endian") ? FORMAT_LITTLE
              : is(w[1], "binary_big_endian")    ? FORMAT_BIG
                                                 : FORMAT_NONE;
  if (!r->format) return parse_fail(r, "unknown format '%.*s'", w[1].n, w[1].s);
  if (!is(w[2], "1.0")) return parse_fail(r, "unknown PLY version '%.*s'", w[2].n, w[2].s);
  return LT_OK;
}

/* Reads the header line by line up to end_header and leaves p at the body's first byte. */
static lt_status read_header(ply_reader *r) {
  for (r->line = 1;; r->line++) {
    const char *eol = memchr(r->p, '\n', (size_t)(r->end - r->p)), *next = eol ? eol + 1 : r->end;
    if (!eol) eol = r->end;
    if (eol > r->p && eol[-1] == '\r') eol--;
    if (r->line == 1 && (eol - r->p != 3 || memcmp(r->p, "ply", 3) != 0))
      return lt__fail(LT_ERROR_PARSE, "%s:1: not a PLY file (the first line is not \"ply\")", r->path);
    if (r->p == r->end) return parse_fail(r, "the header ends without an end_header line");
    word w[MAX_WORDS];
    int n = split_words(r->p, eol, w);
    r->p = next;
    if (r->line == 1 || n == 0 || is(w[0], "comment") || is(w[0], "obj_info")) continue;
    if (n == 1 && is(w[0], "end_header")) {
      size_t end_line = r->line;
      lt_status status = check_header(r);
      r->line = end_line + 1;
      return status;
    }
    lt_status status = read_header_line(r, w, n);
    if (status) return status;
  }
}

/* Reads one value of the given type into a double, which holds every PLY integer exactly. */
static lt_status read_value(ply_reader *r, const ply_property *p, int type, double *out) {
  const struct ply_type *t = &types[type];
  if (r->format == FORMAT_ASCII) {
    for (; r->p < r->end && is_blank(*r->p); r->p++) r->line += *r->p == '\n';
    r->value_at = r->p;
    if (r->p == r->end) return parse_fail(r, "the file ends before property '%.*s'", p->name.n, p->name.s);
    /* strtof, not strtod then a cast, so that a float is rounded once; the '\0' after the
     * buffer stops both parsers. */
    char *end;
    *out = t->is_int ? (double)strtoll(r->p, &end, 10) : (double)strtof(r->p, &end);
    if (end == r->p || !(is_blank(*end) || end == r->end)) {
      size_t len = 0;
      while (r->p + len < r->end && !is_blank(r->p[len])) len++;
      word w = make_word(r->p, len);
      return parse_fail(r, "property '%.*s': '%.*s' is not %s", p->name.n, p->name.s, w.n, w.s,
                        t->is_int ? "an integer" : "a number");
    }
    r->p = end;
    return LT_OK;
  }

  /* Binary: assemble the bytes most significant first, which byte-swaps either order. */
  r->value_at = r->p;
  if ((size_t)(r->end - r->p) < t->size)
    return parse_fail(r, "the file ends before the %u bytes of property '%.*s'", t->size, p->name.n, p->name.s);
  uint64_t bits = 0;
  for (unsigned i = 0; i < t->size; i++)
    bits = bits << 8 | (unsigned char)r->p[r->format == FORMAT_BIG ? i : t->size - 1 - i];
  r->p += t->size;
  if (t->is_int) {
    double sign = t->is_signed && bits >> (8 * t->size - 1) ? (double)((uint64_t)1 << 8 * t->size) : 0.0;
    *out = (double)bits - sign;
  } else if (t->size == 4) {
    uint32_t u = (uint32_t)bits;
    float f;
    memcpy(&f, &u, sizeof f);
    *out = f;
  } else
    memcpy(out, &bits, sizeof *out);
  return LT_OK;
}

static lt_status read_list_count(ply_reader *r, const ply_property *p, size_t *count) {
  double value;
  lt_status status = read_value(r, p, p->count_type, &value);
  if (status) return status;
  /* As in check_header: 2 bytes an ascii value, the last of which may end the file. */
  size_t left = (size_t)(r->end - r->p);
  size_t most = r->format == FORMAT_ASCII ? (left + 1) / 2 : left / types[p->type].size;
  if (value < 0) return parse_fail(r, "list '%.*s' has a negative count %.0f", p->name.n, p->name.s, value);
  if (value > (double)most)
    return parse_fail(r, "list '%.*s' has a count %.0f, more than the %zu bytes left can hold", p->name.n, p->name.s,
                      value, left);
  *count = (size_t)value;
  return LT_OK;
}

/* A face is fanned as (v0, vi, vi+1) while it is read, so faces of any size need no buffer. */
static lt_status read_face(ply_reader *r, const ply_property *p, size_t count) {
  if (count < 3) return parse_fail(r, "face with fewer than 3 vertices (%zu)", count);
  size_t first = 0, prev = 0;
  for (size_t k = 0; k < count; k++) {
    double value;
    lt_status status = read_value(r, p, p->type, &value);
    if (status) return status;
    if (value < 0 || value >= (double)r->vert_count)
      return parse_fail(r, "vertex index %.0f out of range (%zu vertices)", value, r->vert_count);
    size_t index = (size_t)value;
    if (k == 0) first = index;
    if (k >= 2) status = lt__scene_add_tri(r->scene, r->verts + 3 * first, r->verts + 3 * prev, r->verts + 3 * index);
    if (status) return status;
    prev = index;
  }
  return LT_OK;
}

/* Doubles beyond float's range become infinities (and their triangles are skipped), where a
 * plain conversion would be undefined. */
static float to_float(double d) {
  if (d > FLT_MAX) return INFINITY;
  if (d < -FLT_MAX) return -INFINITY;
  return (float)d;
}

static lt_status read_item(ply_reader *r, const ply_element *e, float xyz[3]) {
  for (int i = 0; i < e->property_count; i++) {
    const ply_property *p = &r->properties[e->first + i];
    double value = 0.0;
    size_t count = 0;
    lt_status status = p->count_type < 0 ? read_value(r, p, p->type, &value) : read_list_count(r, p, &count);
    if (status) return status;
    if (p->role >= ROLE_X && p->role <= ROLE_Z) xyz[p->role - ROLE_X] = to_float(value);
    if (p->role == ROLE_INDICES)
      status = read_face(r, p, count);
    else if (p->count_type >= 0)
      for (size_t k = 0; k < count && !status; k++) status = read_value(r, p, p->type, &value);
    if (status) return status;
  }
  return LT_OK;
}

static lt_status read_body(ply_reader *r) {
  for (int i = 0; i < r->element_count; i++) {
    const ply_element *e = r->element = &r->elements[i];
    /* An element without properties takes no bytes, however many items it declares. */
    if (e->property_count == 0) continue;
    int vertices = i == r->vertex_element;
    if (vertices && e->count) {
      /* check_header bounded the count by the file's size; the size check is for 32-bit hosts. */
      r->verts = e->count <= SIZE_MAX / (3 * sizeof *r->verts) ? malloc(e->count * 3 * sizeof *r->verts) : NULL;
      if (!r->verts) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory for %zu vertices", r->path, e->count);
    }
    for (r->item = 0; r->item < e->count; r->item++) {
      float xyz[3] = {0};
      lt_status status = read_item(r, e, xyz);
      if (status) return status;
      if (vertices) memcpy(r->verts + 3 * r->item, xyz, sizeof xyz);
    }
    if (vertices) r->vert_count = e->count;
  }
  return LT_OK; /* whatever follows the last element is ignored */
}

/* The whole file, with a '\0' after it that stops strtof and strtoll at the end. */
static lt_status read_file(const char *path, char **data, size_t *size) {
  FILE *f = fopen(path, "rb");
  if (!f) return lt__fail(LT_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  const char *problem = NULL;
  if (fstat(fileno(f), &st) != 0)
    problem = strerror(errno);
  else if (!S_ISREG(st.st_mode))
    problem = "not a regular file";
  else if ((uintmax_t)st.st_size >= SIZE_MAX / 2)
    problem = "too large";
  else if (!(*data = malloc((size_t)st.st_size + 1))) {
    fclose(f);
    return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory reading %jd bytes", path, (intmax_t)st.st_size);
  } else {
    *size = fread(*data, 1, (size_t)st.st_size, f);
    if (*size != (size_t)st.st_size) problem = ferror(f) ? strerror(errno) : "the file got shorter while read";
    (*data)[*size] = '\0';
  }
  fclose(f);
  return problem ? lt__fail(LT_ERROR_IO, "%s: cannot read: %s", path, problem) : LT_OK;
}

lt_status lt__load_ply(const char *path, lt_scene *scene) {
  if (!path || !scene) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt__load_ply: NULL argument");
  /* The reader's tables take some 15 kB: on the heap, not the stack. */
  ply_reader *r = calloc(1, sizeof *r);
  if (!r) return lt__fail(LT_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
  r->path = path;
  r->vertex_element = -1;
  r->scene = scene;
  size_t size = 0;
  lt_status status = read_file(path, &r->data, &size);
  if (!status) {
    r->p = r->data;
    r->end = r->data + size;
    status = read_header(r);
  }
  if (!status) status = read_body(r);
  free(r->verts);
  free(r->data);
  free(r);
  return status;
}
