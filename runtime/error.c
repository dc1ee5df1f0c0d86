/* Status names and messages from the one X-macro list, and the per-thread last error. */
#include "error.h"

#include <stdarg.h>
#include <stdio.h>

static _Thread_local char last_error[1024];

const char *lt_status_str(lt_status status) {
  switch (status) {
#define LT_STATUS_TEXT(name, text) \
  case name:                       \
    return text;
    LT_STATUS_LIST(LT_STATUS_TEXT)
#undef LT_STATUS_TEXT
  default:
    return "unknown status";
  }
}

const char *lt_status_name(lt_status status) {
  switch (status) {
#define LT_STATUS_NAME(name, text) \
  case name:                       \
    return #name;
    LT_STATUS_LIST(LT_STATUS_NAME)
#undef LT_STATUS_NAME
  default:
    return "LT_STATUS_UNKNOWN";
  }
}

#define LT_STRINGIFY(x) #x
#define LT_VERSION_TEXT(a, b, c) LT_STRINGIFY(a) "." LT_STRINGIFY(b) "." LT_STRINGIFY(c)

const char *lt_version(void) { return LT_VERSION_TEXT(LT_VERSION_MAJOR, LT_VERSION_MINOR, LT_VERSION_PATCH); }

const char *lt_last_error(void) { return last_error; }

void lt__clear_error(void) { last_error[0] = '\0'; }

lt_status lt__fail(lt_status status, const char *fmt, ...) {
  va_list args;
  va_start(args, fmt);
  vsnprintf(last_error, sizeof last_error, fmt, args);
  va_end(args);
  return status;
}
