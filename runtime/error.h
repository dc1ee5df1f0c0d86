/* The thread's last error message, set where an lt_status error is first returned. */
#ifndef LT_ERROR_H
#define LT_ERROR_H

#include "lazytrace.h"

/* Formats the message for lt_last_error() and returns status, so that a failing path reads
 * `return lt__fail(LT_ERROR_PARSE, "%s:%d: expected a vertex index", path, line);`. */
lt_status lt__fail(lt_status status, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void lt__clear_error(void);

#endif
