/* The host registry of structures (see registry.h): the table made from LT_STRUCTURE_LIST, the
 * names planned for later, and the public functions that read the table. */
#include "runtime/registry.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "runtime/error.h"

static const lt__structure_class *const classes[LT_STRUCTURE_COUNT] = {
#define LT__STRUCTURE_ENTRY(kind, entry) [kind] = &lt__structure_##entry,
    LT_STRUCTURE_LIST(LT__STRUCTURE_ENTRY)
#undef LT__STRUCTURE_ENTRY
};

/* Names a user may give that later issues implement, separated by commas (none at present);
 * each is refused with a clear message. */
static const char planned[] = "";

static const char *const build_names[] = {"default", "full", "requested", "speculative"};

const lt__structure_class *lt__structure_class_of(lt_structure_kind kind) {
  return (unsigned)kind < LT_STRUCTURE_COUNT ? classes[kind] : NULL;
}

const char *lt_structure_planned(void) { return planned; }

/* Whether `name` is one of the comma-separated names of `list`. */
static int listed(const char *list, const char *name) {
  size_t n = strlen(name);
  for (const char *p = list; *p;) {
    const char *end = strchr(p, ',');
    size_t len = end ? (size_t)(end - p) : strlen(p);
    if (len == n && strncmp(p, name, n) == 0) return 1;
    if (!end) break;
    for (p = end + 1; *p == ' ';) p++;
  }
  return 0;
}

/* The implemented names, separated by commas, for messages. */
static const char *known_names(void) {
  static char names[256];
  names[0] = '\0';
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++) {
    if (k) strncat(names, ", ", sizeof names - strlen(names) - 1);
    strncat(names, classes[k]->name, sizeof names - strlen(names) - 1);
  }
  return names;
}

lt_status lt_structure_kind_parse(const char *name, lt_structure_kind *out) {
  if (!name || !out) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_kind_parse: NULL argument");
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++)
    if (strcmp(name, classes[k]->name) == 0) return *out = (lt_structure_kind)k, LT_OK;
  if (listed(planned, name))
    return lt__fail(LT_ERROR_UNSUPPORTED, "--structure %s is not implemented yet (available: %s)", name, known_names());
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown structure '%s' (known: %s%s%s)", name, known_names(),
                  planned[0] ? "; planned: " : "", planned);
}

const char *lt_structure_kind_name(lt_structure_kind kind) {
  const lt__structure_class *c = lt__structure_class_of(kind);
  return c ? c->name : "unknown";
}

const char *lt_structure_summary(lt_structure_kind kind) {
  const lt__structure_class *c = lt__structure_class_of(kind);
  return c ? c->summary : "";
}

/* The name of choice `value` (1-based) in a "a|b|c" list. */
static void choice_name(const char *names, int value, char *out, size_t size) {
  const char *at = names;
  for (int i = 1; i < value && at; i++) {
    at = strchr(at, '|');
    if (at) at++;
  }
  size_t len = at ? strcspn(at, "|") : 0;
  snprintf(out, size, "%.*s", (int)len, at ? at : "");
}

/* The 1-based index of `value` in a "a|b|c" list, or 0. */
static int choice_index(const char *names, const char *value) {
  size_t len = strlen(value);
  int i = 1;
  for (const char *at = names; at; i++) {
    size_t n = strcspn(at, "|");
    if (n == len && strncmp(at, value, len) == 0) return i;
    at = strchr(at, '|');
    if (at) at++;
  }
  return 0;
}

const char *lt_structure_parameters(lt_structure_kind kind) {
  static char text[LT_STRUCTURE_COUNT][2048];
  const lt__structure_class *c = lt__structure_class_of(kind);
  if (!c) return "";
  char *out = text[kind];
  size_t used = 0;
  out[0] = '\0';
  for (const lt__param *p = c->params; p && p->option; p++) {
    const char *field = (const char *)&c->defaults + p->offset;
    double value = p->is_float ? (double)*(const float *)field : (double)*(const int *)field;
    int n;
    if (p->names) {
      char name[64];
      choice_name(p->names, (int)value, name, sizeof name);
      n = snprintf(out + used, sizeof text[0] - used, "%s%s %s: %s (default %s)", used ? "\n" : "", p->option,
                   p->names, p->help, name);
    } else {
      n = snprintf(out + used, sizeof text[0] - used, "%s%s %s: %s (default %g)", used ? "\n" : "", p->option,
                   p->is_float ? "X" : "N", p->help, value);
    }
    if (n < 0 || (size_t)n >= sizeof text[0] - used) break;
    used += (size_t)n;
  }
  return out;
}

lt_status lt_structure_option(lt_structure_config *config, const char *option, const char *value) {
  if (!config || !option || !value) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "lt_structure_option: NULL argument");
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++)
    for (const lt__param *p = classes[k]->params; p && p->option; p++) {
      if (strcmp(option, p->option) != 0) continue;
      if (p->names) {
        int index = choice_index(p->names, value);
        if (!index) return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s '%s': expected %s", option, value, p->names);
        *(int *)((char *)config + p->offset) = index;
        return LT_OK;
      }
      char *end;
      errno = 0;
      double v = strtod(value, &end);
      int whole = v == (double)(long long)v;
      if (errno || end == value || *end || !(v >= p->min && v <= p->max) || (!p->is_float && !whole))
        return lt__fail(LT_ERROR_INVALID_ARGUMENT, "%s '%s': expected %s from %g to %g", option, value,
                        p->is_float ? "a number" : "a whole number", p->min, p->max);
      char *field = (char *)config + p->offset;
      if (p->is_float) *(float *)field = (float)v;
      else *(int *)field = (int)v;
      return LT_OK;
    }
  return lt__fail(LT_ERROR_UNSUPPORTED, "no structure takes %s", option);
}

unsigned lt_structure_modes(lt_structure_kind kind) {
  const lt__structure_class *c = lt__structure_class_of(kind);
  return c ? c->modes : 0;
}

size_t lt_structure_variants(lt_structure_kind *kinds, lt_build_mode *modes, size_t max) {
  size_t n = 0;
  for (int k = 0; k < LT_STRUCTURE_COUNT; k++)
    for (int m = LT_BUILD_FULL; m <= LT_BUILD_SPECULATIVE; m++)
      if (classes[k]->modes & (1u << m)) {
        if (n < max && kinds) kinds[n] = (lt_structure_kind)k;
        if (n < max && modes) modes[n] = (lt_build_mode)m;
        n++;
      }
  return n;
}

lt_structure_config lt_structure_config_default(lt_structure_kind kind) {
  const lt__structure_class *c = lt__structure_class_of(kind);
  lt_structure_config none;
  memset(&none, 0, sizeof none);
  return c ? c->defaults : none;
}

const char *lt_build_mode_name(lt_build_mode mode) {
  return (unsigned)mode <= LT_BUILD_SPECULATIVE ? build_names[mode] : "unknown";
}

lt_status lt_build_mode_parse(const char *name, lt_build_mode *out) {
  for (int i = LT_BUILD_FULL; i <= LT_BUILD_SPECULATIVE; i++)
    if (strcmp(name, build_names[i]) == 0) return *out = (lt_build_mode)i, LT_OK;
  return lt__fail(LT_ERROR_INVALID_ARGUMENT, "unknown build mode '%s' (known: full, requested, speculative)", name);
}
