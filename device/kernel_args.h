/* Kernel arguments from one description. A workload lists its arguments once, as an X-macro
 * of entries X(KIND, TYPE, FIELD, NAME): KIND is BUF (a global array; FIELD is a pointer in
 * the workload's view struct) or VAL (a scalar); FIELD is the member's path in the view
 * ("build.nodes"); NAME is the kernel parameter. The same list makes the OpenCL entry's
 * parameters and their copy into the view (below), and on the host the clSetKernelArg calls
 * and the native backend's view (runtime/kernel_args_host.h), so the two backends cannot
 * disagree on an argument's position or type. */
#ifndef LT_DEVICE_KERNEL_ARGS_H
#define LT_DEVICE_KERNEL_ARGS_H

/* One kernel parameter per entry, each followed by a comma: an entry point lists the
 * workload's arguments and then one last parameter of its own. */
#define LT_ARG_PARAM(kind, type, field, name) LT_ARG_PARAM_##kind(type, name)
#define LT_ARG_PARAM_BUF(type, name) LT_GLOBAL type *name,
#define LT_ARG_PARAM_VAL(type, name) type name,

/* Copies each parameter into a view struct named `view`. */
#define LT_ARG_FILL(kind, type, field, name) view.field = name;

#endif
