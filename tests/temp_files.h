/* Files written by tests, in one temporary directory per test group, and scenes loaded from
 * them. */
#ifndef LT_TEST_TEMP_FILES_H
#define LT_TEST_TEMP_FILES_H

#include "lazytrace.h"

/* A temporary directory for a test group's files (cmocka group setup and teardown): the
 * teardown removes the files made through lt_test_temp_path and the directory. */
int lt_test_temp_dir_create(void **state);
int lt_test_temp_dir_remove(void **state);
/* A path of that name in the directory, remembered for removal. */
const char *lt_test_temp_path(const char *name);
/* Writes text to a file of that name in the directory; returns its path. */
const char *lt_test_write_file(const char *name, const char *text);

/* Loads a scene that must load; fails the test with the error otherwise. */
lt_scene *lt_test_load_ok(const char *path);

/* Writes text to bad<case>.json and loads it as a scene: returns the load's status, with its
 * error message in *message (NULL unless the message names the file, as every load error must)
 * and the scene, which a refused load leaves NULL, in *scene. */
lt_status lt_test_load_bad(size_t case_number, const char *text, const char **message, lt_scene **scene);

#endif
