/* The host side of a kernel's argument list (device/kernel_args.h): from the same X-macro
 * list, a struct of the launch's buffers and values, the clSetKernelArg calls in the list's
 * order, and the native backend's view with the buffers' host pointers.
 *
 *   LT__KERNEL_ARGS(name, LIST, view_type)
 *
 * defines `name` (the struct: an lt__buffer * per BUF entry, the value per VAL entry),
 * `name##_set(kernel, args, &next)` (returns a cl_int; next gets the index after the list, for
 * an entry point's own last parameters; `name##_set_any` takes the args as a void pointer, for
 * generic launchers) and `name##_view(args, view)` (and `name##_view_any`). */
#ifndef LT_KERNEL_ARGS_HOST_H
#define LT_KERNEL_ARGS_HOST_H

#include "runtime/buffer.h"

#define LT__ARG_FIELD(kind, type, field, name) LT__ARG_FIELD_##kind(type, name)
#define LT__ARG_FIELD_BUF(type, name) lt__buffer *name;
#define LT__ARG_FIELD_VAL(type, name) type name;

#define LT__ARG_SET(kind, type, field, name) LT__ARG_SET_##kind(type, name)
#define LT__ARG_SET_BUF(type, name) err |= clSetKernelArg(kernel, index++, sizeof(cl_mem), &args->name->mem);
#define LT__ARG_SET_VAL(type, name) err |= clSetKernelArg(kernel, index++, sizeof(type), &args->name);

#define LT__ARG_VIEW(kind, type, field, name) LT__ARG_VIEW_##kind(type, field, name)
#define LT__ARG_VIEW_BUF(type, field, name) view->field = (type *)args->name->host;
#define LT__ARG_VIEW_VAL(type, field, name) view->field = args->name;

#define LT__KERNEL_ARGS(name, LIST, view_type)                                                 \
  typedef struct name {                                                                        \
    LIST(LT__ARG_FIELD)                                                                        \
  } name;                                                                                      \
  static inline cl_int name##_set(cl_kernel kernel, const name *args, cl_uint *next) {         \
    cl_uint index = 0;                                                                         \
    cl_int err = CL_SUCCESS;                                                                   \
    LIST(LT__ARG_SET)                                                                          \
    *next = index;                                                                             \
    return err;                                                                                \
  }                                                                                            \
  static inline void name##_view(const name *args, view_type *view) {                          \
    memset(view, 0, sizeof *view);                                                             \
    LIST(LT__ARG_VIEW)                                                                         \
  }                                                                                            \
  static inline cl_int name##_set_any(cl_kernel kernel, const void *args, cl_uint *next) {     \
    return name##_set(kernel, (const name *)args, next);                                       \
  }                                                                                            \
  static inline void name##_view_any(const void *args, void *view) {                           \
    name##_view((const name *)args, (view_type *)view);                                        \
  }

#endif
