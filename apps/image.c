/* PNG output through stb_image_write (Debian libstb). */
#include <stb_image_write.h>

#include "apps/cli.h"

int lt_write_png(const char *path, int width, int height, const unsigned char *rgb) {
  return stbi_write_png(path, width, height, 3, rgb, 3 * width) ? 0 : 1;
}
