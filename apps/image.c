/* PNG output through stb_image_write (Debian libstb). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_image_write.h>

#include "apps/cli.h"

/* The encoder's output, gathered in memory. */
typedef struct png_bytes {
  unsigned char *data;
  size_t size, cap;
  int failed;
} png_bytes;

static void gather(void *context, void *data, int size) {
  png_bytes *b = context;
  if (b->failed || size <= 0) return;
  if (b->size + (size_t)size > b->cap) {
    size_t cap = 2 * (b->size + (size_t)size);
    unsigned char *grown = realloc(b->data, cap);
    if (!grown) {
      b->failed = 1;
      return;
    }
    b->data = grown, b->cap = cap;
  }
  memcpy(b->data + b->size, data, (size_t)size);
  b->size += (size_t)size;
}

/* Encoded in memory, then written whole or not at all (lt_file_write): a full disk is an
 * error, never a truncated image. */
int lt_write_png(const char *path, int width, int height, const unsigned char *rgb) {
  png_bytes png = {NULL, 0, 0, 0};
  if (!stbi_write_png_to_func(gather, &png, width, height, 3, rgb, 3 * width) || png.failed) {
    free(png.data);
    return fprintf(stderr, "lazytrace: %s: could not encode the image\n", path), 1;
  }
  lt_status status = lt_file_write(path, png.data, png.size);
  free(png.data);
  return status ? fprintf(stderr, "lazytrace: %s\n", lt_last_error()), 1 : 0;
}
