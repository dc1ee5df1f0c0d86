/* A temporary directory for a test group's files (temp_files.h). */
#define _POSIX_C_SOURCE 200809L
#include "tests/temp_files.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "lazytrace.h"

#define MAX_TEMP_FILES 64
#define TEMP_PATH_SIZE 512

static char temp_dir[64];
static char temp_files[MAX_TEMP_FILES][TEMP_PATH_SIZE];
static int temp_file_count;

int lt_test_temp_dir_create(void **state) {
  (void)state;
  snprintf(temp_dir, sizeof temp_dir, "/tmp/lt_test_XXXXXX");
  return mkdtemp(temp_dir) ? 0 : -1;
}

int lt_test_temp_dir_remove(void **state) {
  (void)state;
  for (int i = 0; i < temp_file_count; i++) unlink(temp_files[i]);
  temp_file_count = 0;
  return rmdir(temp_dir);
}

const char *lt_test_temp_path(const char *name) {
  assert_true(temp_file_count < MAX_TEMP_FILES);
  char *path = temp_files[temp_file_count++];
  snprintf(path, TEMP_PATH_SIZE, "%s/%s", temp_dir, name);
  return path;
}

const char *lt_test_write_file(const char *name, const char *text) {
  const char *path = lt_test_temp_path(name);
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(text, 1, strlen(text), f), strlen(text));
  assert_int_equal(fclose(f), 0);
  return path;
}

lt_status lt_test_load_bad(size_t case_number, const char *text, const char **message, lt_scene **scene) {
  char name[32];
  snprintf(name, sizeof name, "bad%zu.json", case_number);
  const char *path = lt_test_write_file(name, text);
  *scene = NULL;
  lt_status status = lt_scene_load(path, scene);
  *message = lt_last_error();
  if (strncmp(*message, path, strlen(path)) != 0) *message = NULL;
  return status;
}

lt_scene *lt_test_load_ok(const char *path) {
  lt_scene *scene = NULL;
  lt_status status = lt_scene_load(path, &scene);
  if (status) fail_msg("loading %s: %s: %s", path, lt_status_name(status), lt_last_error());
  return scene;
}
