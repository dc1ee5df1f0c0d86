/* lazytrace scene and lazytrace devices: the two commands that trace nothing. */
#include "apps/cli.h"

int lt_cmd_scene(lt_cli *cli) {
  if (!cli->scene || !cli->output)
    return fprintf(stderr, "lazytrace scene: usage: lazytrace scene SCENE -o FILE.obj\n"), 2;
  lt_scene *scene;
  lt_status status = lt_scene_load(cli->scene, &scene);
  if (status) return lt_cli_fail("loading the scene", status);
  status = lt_scene_write_obj(scene, cli->output);
  if (!status)
    fprintf(stderr, "lazytrace: wrote %zu triangles to %s\n", lt_scene_triangle_count(scene), cli->output);
  lt_scene_destroy(scene);
  return status ? lt_cli_fail("writing the scene", status) : 0;
}

int lt_cmd_devices(lt_cli *cli) {
  (void)cli;
  return lt_devices_print(stdout) ? 1 : 0;
}
