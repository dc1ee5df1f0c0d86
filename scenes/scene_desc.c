/* Scene descriptions: the materials, lights, image and effects a scene file gives, and the
 * default description of generators and mesh files (one grey diffuse material, no lights,
 * primary rays only), so that every scene can be rendered the same way. */
#include <stdlib.h>
#include <string.h>

#include "scenes/scene_internal.h"

static const lt_material default_material = {{0.8f, 0.8f, 0.8f}, 0.0f, {0.0f, 0.0f, 0.0f}};

void lt__scene_desc_free(lt__scene_desc *desc) {
  if (!desc) return;
  free(desc->materials);
  free(desc->tri_material);
  free(desc->lights);
  free(desc);
}

/* The default description, as a constant so that concurrent readers need no lock. The
 * background is a pale blue sky: the light that ambient-occlusion and diffuse rays find when
 * they escape. */
static const lt__scene_desc fallback = {
    .background = {0.75f, 0.85f, 1.0f},
    .effects = {.primary = 1, .ao_distance = 1.0f, .diffuse_bounces = 1, .collision_rays = 8, .collision_frames = 20},
};
static const lt__scene_desc *desc_of(const lt_scene *scene) { return scene->desc ? scene->desc : &fallback; }

void lt__scene_desc_defaults(lt__scene_desc *desc) { *desc = fallback; }

size_t lt_scene_material_count(const lt_scene *scene) {
  return scene->desc && scene->desc->material_count ? scene->desc->material_count : 1;
}

const lt_material *lt_scene_materials(const lt_scene *scene) {
  return scene->desc && scene->desc->material_count ? scene->desc->materials : &default_material;
}

int lt_scene_triangle_material(const lt_scene *scene, size_t tri) {
  return scene->desc && scene->desc->tri_material && tri < scene->count ? scene->desc->tri_material[tri] : 0;
}

size_t lt_scene_light_count(const lt_scene *scene) { return desc_of(scene)->light_count; }
const lt_light *lt_scene_lights(const lt_scene *scene) { return desc_of(scene)->lights; }
lt_effects lt_scene_effects(const lt_scene *scene) { return desc_of(scene)->effects; }

void lt_scene_image(const lt_scene *scene, int *width, int *height, int *spp) {
  const lt__scene_desc *d = desc_of(scene);
  if (width) *width = d->width;
  if (height) *height = d->height;
  if (spp) *spp = d->spp;
}

void lt_scene_background(const lt_scene *scene, float rgb[3]) { memcpy(rgb, desc_of(scene)->background, 3 * sizeof *rgb); }
