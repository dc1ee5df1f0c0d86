/* Each triangle's bounding box and the scene's, computed once on the host by as many threads
 * as the native backend has, for the builders that read boxes instead of vertices. */
#ifndef LT_TRIANGLE_BOXES_H
#define LT_TRIANGLE_BOXES_H

#include "device/box.h"
#include "lazytrace.h"

/* Writes 8 floats per triangle to `boxes` (lo xyz 0, hi xyz 0) and the scene's bounds. */
lt_status lt__triangle_boxes(const lt_scene *scene, float *boxes, lt_box *bounds);

#endif
