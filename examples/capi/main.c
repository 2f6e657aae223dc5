/* The README's C example: two meshes in one scene, a bvh_wide over them, one ray; each hit names its mesh. Built and
 * run by CTest (capi.example); exits 1 with the library's message on any failure. */
#include <stdio.h>

#include "rayaccel/rayaccel_c.h"

int main(void) {
  const float floor_vertices[] = {-4, -4, 0, 4, -4, 0, 4, 4, 0, -4, 4, 0}; /* x y z per vertex */
  const uint32_t floor_indices[] = {0, 1, 2, 0, 2, 3};                      /* three per triangle */
  const float lamp_vertices[] = {-1, -1, 3, 1, -1, 3, 0, 1, 3};
  const uint32_t lamp_indices[] = {0, 1, 2};
  rayaccel_scene* scene = NULL;
  rayaccel_accel* accel = NULL;
  uint32_t floor_id, lamp_id;
  if (rayaccel_scene_new(&scene) != RAYACCEL_OK ||
      rayaccel_scene_add_mesh(scene, floor_vertices, 4, floor_indices, 2, &floor_id) != RAYACCEL_OK ||
      rayaccel_scene_add_mesh(scene, lamp_vertices, 3, lamp_indices, 1, &lamp_id) != RAYACCEL_OK ||
      rayaccel_accel_new(scene, "bvh_wide", &accel) != RAYACCEL_OK) {
    fprintf(stderr, "rayaccel: %s\n", rayaccel_last_error());
    return 1;
  }
  rayaccel_scene_release(scene); /* the structure keeps it alive */
  const rayaccel_ray ray = {0, 0, 5, 0, 0, 0, -1, 100}; /* origin, t_min, direction, t_max */
  rayaccel_hit hit;
  if (rayaccel_intersect1(accel, &ray, &hit) != RAYACCEL_OK) return 1;
  printf("t = %g on triangle %u of mesh %u\n", hit.t, hit.prim_id, hit.geom_id); /* t = 2 on triangle 0 of mesh 1 */
  rayaccel_accel_release(accel);
  return hit.geom_id == lamp_id && hit.t == 2.0f ? 0 : 1;
}
