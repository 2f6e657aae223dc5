/* The C API from plain C11 (CTest capi.c11): two meshes, several structures, one ray, batches and packets agreeing bit
 * for bit, geometry ids, skip / masks / filters through a query context, and every error path returning a code and a
 * message instead of crashing. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "rayaccel/rayaccel_c.h"

static int failures = 0;
#define CHECK(cond)                                                   \
  do {                                                                \
    if (!(cond)) {                                                    \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                     \
    }                                                                 \
  } while (0)

/* Mesh 0: the square [0, 4]^2 at z = 0 (two triangles). Mesh 1: one triangle at z = 1 over [0, 2]^2's lower half. */
static const float floor_vertices[] = {0, 0, 0, 4, 0, 0, 4, 4, 0, 0, 4, 0};
static const uint32_t floor_indices[] = {0, 1, 2, 0, 2, 3};
static const float roof_vertices[] = {0, 0, 1, 2, 0, 1, 0, 2, 1};
static const uint32_t roof_indices[] = {0, 1, 2};

enum { kRays = 64 };

static rayaccel_ray down_ray(float x, float y) {
  rayaccel_ray r = {x, y, 2.0f, 0.0f, 0.0f, 0.0f, -1.0f, INFINITY};
  return r;
}

static void check_structure(rayaccel_scene* scene, const char* spec) {
  rayaccel_accel* accel = NULL;
  if (rayaccel_accel_new(scene, spec, &accel) != RAYACCEL_OK) {
    fprintf(stderr, "%s: %s\n", spec, rayaccel_last_error());
    ++failures;
    return;
  }
  CHECK(accel != NULL && strcmp(rayaccel_last_error(), "") == 0);

  rayaccel_hit hit;
  rayaccel_ray ray = down_ray(0.5f, 0.5f); /* under the roof: geometry 1 at t = 1 */
  CHECK(rayaccel_intersect1(accel, &ray, &hit) == RAYACCEL_OK);
  CHECK(hit.t == 1.0f && hit.geom_id == 1 && hit.prim_id == 0);
  ray = down_ray(3.0f, 1.0f); /* beside it: the floor's first triangle at t = 2 */
  CHECK(rayaccel_intersect1(accel, &ray, &hit) == RAYACCEL_OK);
  CHECK(hit.t == 2.0f && hit.geom_id == 0 && hit.prim_id == 0);
  ray = down_ray(1.0f, 3.0f); /* the floor's second triangle */
  CHECK(rayaccel_intersect1(accel, &ray, &hit) == RAYACCEL_OK);
  CHECK(hit.t == 2.0f && hit.geom_id == 0 && hit.prim_id == 1);
  ray = down_ray(5.0f, 5.0f); /* a miss */
  CHECK(rayaccel_intersect1(accel, &ray, &hit) == RAYACCEL_OK);
  CHECK(isinf(hit.t) && hit.prim_id == RAYACCEL_INVALID_ID && hit.geom_id == RAYACCEL_INVALID_ID);
  ray = down_ray(0.5f, 0.5f);
  ray.t_max = 0.5f; /* stops short of the roof */
  int occluded = -1;
  CHECK(rayaccel_occluded1(accel, &ray, &occluded) == RAYACCEL_OK && occluded == 0);
  ray.t_max = 1.0f; /* t_max is inclusive */
  CHECK(rayaccel_occluded1(accel, &ray, &occluded) == RAYACCEL_OK && occluded == 1);

  /* A grid of rays, some off the floor: batches and packets answer as one ray at a time, bit for bit. */
  rayaccel_ray rays[kRays];
  rayaccel_hit one[kRays], batch[kRays], packets[kRays];
  uint8_t occ_batch[kRays], occ_packets[kRays];
  for (int i = 0; i < kRays; ++i) {
    rays[i] = down_ray(0.3f + 0.61f * (float)(i % 8), 0.2f + 0.59f * (float)(i / 8));
    CHECK(rayaccel_intersect1(accel, &rays[i], &one[i]) == RAYACCEL_OK);
  }
  CHECK(rayaccel_intersect(accel, rays, kRays, batch) == RAYACCEL_OK);
  CHECK(rayaccel_intersect_packets(accel, rays, kRays, packets) == RAYACCEL_OK);
  CHECK(memcmp(one, batch, sizeof(one)) == 0);
  CHECK(memcmp(one, packets, sizeof(one)) == 0);
  CHECK(rayaccel_occluded(accel, rays, kRays, occ_batch) == RAYACCEL_OK);
  CHECK(rayaccel_occluded_packets(accel, rays, kRays, occ_packets) == RAYACCEL_OK);
  int hits = 0;
  for (int i = 0; i < kRays; ++i) {
    CHECK(occ_batch[i] == (one[i].prim_id != RAYACCEL_INVALID_ID));
    CHECK(occ_packets[i] == occ_batch[i]);
    hits += one[i].prim_id != RAYACCEL_INVALID_ID;
  }
  CHECK(hits > 0 && hits < kRays); /* the grid has both hits and misses */
  CHECK(rayaccel_intersect(accel, rays, 0, NULL) == RAYACCEL_OK); /* an empty batch */
  rayaccel_accel_release(accel);
}

/* A filter that rejects geometry 1 (the roof) and counts the candidates it saw with a bad ray index. */
static int reject_roof(void* data, const rayaccel_candidate* c) {
  if (c->ray_index >= 2) ++*(int*)data;
  return c->geom_id != 1;
}

/* The packet calls under `context` answer as the batch calls do (hits[] and occluded[] from those). */
static void check_packets_agree(const rayaccel_accel* accel, const rayaccel_query_context* context,
                                const rayaccel_ray* rays, const rayaccel_hit* hits, const uint8_t* occluded) {
  rayaccel_hit packet_hits[2];
  uint8_t packet_occluded[2];
  CHECK(rayaccel_intersect_packets_context(accel, context, rays, 2, packet_hits) == RAYACCEL_OK);
  CHECK(memcmp(packet_hits, hits, sizeof(packet_hits)) == 0);
  CHECK(rayaccel_occluded_packets_context(accel, context, rays, 2, packet_occluded) == RAYACCEL_OK);
  CHECK(memcmp(packet_occluded, occluded, sizeof(packet_occluded)) == 0);
}

/* Skip, masks and a filter: each hides the roof from the ray under it, which then hits the floor at t = 2. */
static void check_context(rayaccel_scene* scene, const char* spec) {
  rayaccel_accel* accel = NULL;
  CHECK(rayaccel_accel_new(scene, spec, &accel) == RAYACCEL_OK);
  const rayaccel_ray rays[2] = {down_ray(0.5f, 0.3f), down_ray(0.3f, 0.6f)}; /* both under the roof, off the diagonal */
  rayaccel_hit hits[2];
  uint8_t occluded[2];
  rayaccel_query_context none = {NULL, NULL, NULL, NULL, NULL, NULL};
  CHECK(rayaccel_intersect_context(accel, &none, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 1 && hits[0].t == 1.0f);
  const uint32_t skip_geom[2] = {1, RAYACCEL_INVALID_ID}, skip_prim[2] = {0, RAYACCEL_INVALID_ID};
  rayaccel_query_context skip = {skip_geom, skip_prim, NULL, NULL, NULL, NULL};
  CHECK(rayaccel_intersect_context(accel, &skip, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 0 && hits[0].prim_id == 0 && hits[0].t == 2.0f); /* ray 0 skips the roof */
  CHECK(hits[1].geom_id == 1 && hits[1].t == 1.0f);                         /* ray 1 skips nothing */
  rayaccel_query_context whole = {NULL, NULL, skip_geom, NULL, NULL, NULL};
  CHECK(rayaccel_intersect_context(accel, &whole, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 0 && hits[1].geom_id == 1);
  int bad = 0;
  rayaccel_query_context filtered = {NULL, NULL, NULL, NULL, reject_roof, &bad};
  CHECK(rayaccel_intersect_context(accel, &filtered, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 0 && hits[1].geom_id == 0 && hits[1].t == 2.0f && bad == 0);
  /* Masks: the roof gets mask 2; rays with mask 1 no longer see it, rays with mask 3 do. Mask 0 turns it off. */
  const uint32_t ray_mask[2] = {1, 3};
  rayaccel_query_context masked = {NULL, NULL, NULL, ray_mask, NULL, NULL};
  CHECK(rayaccel_scene_set_mask(scene, 1, 2) == RAYACCEL_OK);
  CHECK(rayaccel_intersect_context(accel, &masked, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 0 && hits[1].geom_id == 1);
  /* The packet calls under each context so far: a skipped triangle, a geometry, a filter, masks. */
  const rayaccel_query_context* contexts[4] = {&skip, &whole, &filtered, &masked};
  for (int k = 0; k < 4; ++k) {
    CHECK(rayaccel_intersect_context(accel, contexts[k], rays, 2, hits) == RAYACCEL_OK);
    CHECK(rayaccel_occluded_context(accel, contexts[k], rays, 2, occluded) == RAYACCEL_OK);
    check_packets_agree(accel, contexts[k], rays, hits, occluded);
  }
  CHECK(rayaccel_scene_set_mask(scene, 1, 0) == RAYACCEL_OK);
  CHECK(rayaccel_occluded_context(accel, NULL, rays, 2, occluded) == RAYACCEL_OK && occluded[0] == 1);
  CHECK(rayaccel_intersect_context(accel, NULL, rays, 2, hits) == RAYACCEL_OK);
  CHECK(hits[0].geom_id == 0 && hits[1].geom_id == 0);
  CHECK(rayaccel_scene_set_mask(scene, 1, 0xFFFFFFFFu) == RAYACCEL_OK);
  CHECK(rayaccel_scene_set_mask(scene, 7, 1) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(strstr(rayaccel_last_error(), "geometry 7") != NULL);
  rayaccel_query_context half = {skip_geom, NULL, NULL, NULL, NULL, NULL};
  CHECK(rayaccel_intersect_context(accel, &half, rays, 2, hits) == RAYACCEL_INVALID_ARGUMENT);
  rayaccel_accel_release(accel);
}

static void check_errors(rayaccel_scene* scene) {
  rayaccel_accel* accel = NULL;
  CHECK(rayaccel_accel_new(scene, "no_such_structure", &accel) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(accel == NULL && strstr(rayaccel_last_error(), "no_such_structure") != NULL);
  CHECK(rayaccel_accel_new(scene, "bvh:no_such_key=1", &accel) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(strstr(rayaccel_last_error(), "no_such_key") != NULL);
  CHECK(rayaccel_accel_new(scene, NULL, &accel) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(strstr(rayaccel_last_error(), "spec is null") != NULL);
  uint32_t count = 0;
  CHECK(rayaccel_scene_geometry_count(NULL, &count) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(rayaccel_intersect1(NULL, NULL, NULL) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(rayaccel_intersect(NULL, NULL, 4, NULL) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(rayaccel_scene_geometry_count(scene, &count) == RAYACCEL_OK && count == 2);
  CHECK(strcmp(rayaccel_last_error(), "") == 0); /* a success clears the message */
}

int main(void) {
  CHECK(strlen(rayaccel_version()) > 0);
  rayaccel_scene* scene = NULL;
  CHECK(rayaccel_scene_new(&scene) == RAYACCEL_OK && scene != NULL);
  uint32_t geom = 99;
  CHECK(rayaccel_scene_add_mesh(scene, floor_vertices, 4, floor_indices, 2, &geom) == RAYACCEL_OK && geom == 0);
  CHECK(rayaccel_scene_add_mesh(scene, roof_vertices, 3, roof_indices, 1, &geom) == RAYACCEL_OK && geom == 1);
  const uint32_t bad_indices[] = {0, 1, 3};
  CHECK(rayaccel_scene_add_mesh(scene, roof_vertices, 3, bad_indices, 1, &geom) == RAYACCEL_INVALID_ARGUMENT);
  CHECK(strstr(rayaccel_last_error(), "vertex index 3") != NULL);
  CHECK(rayaccel_scene_add_mesh(scene, NULL, 3, roof_indices, 1, NULL) == RAYACCEL_INVALID_ARGUMENT);
  uint32_t count = 0;
  CHECK(rayaccel_scene_primitive_count(scene, &count) == RAYACCEL_OK && count == 3); /* the failed meshes left no trace */

  check_errors(scene);
  const char* specs[] = {"brute_force", "bvh", "bvh_wide", "kdtree", "grid", "octree", "bsp"};
  for (size_t i = 0; i < sizeof(specs) / sizeof(specs[0]); ++i) check_structure(scene, specs[i]);
  for (size_t i = 0; i < sizeof(specs) / sizeof(specs[0]); ++i) check_context(scene, specs[i]);

  /* Built over, the scene is immutable; a structure keeps it alive after the caller lets it go. */
  rayaccel_accel* accel = NULL;
  CHECK(rayaccel_accel_new(scene, "bvh_wide", &accel) == RAYACCEL_OK);
  CHECK(rayaccel_scene_add_mesh(scene, roof_vertices, 3, roof_indices, 1, NULL) == RAYACCEL_INVALID_OPERATION);
  CHECK(strstr(rayaccel_last_error(), "immutable") != NULL);
  rayaccel_scene_release(scene);
  rayaccel_hit hit;
  rayaccel_ray ray = down_ray(0.5f, 0.5f);
  CHECK(rayaccel_intersect1(accel, &ray, &hit) == RAYACCEL_OK && hit.geom_id == 1);
  rayaccel_accel_release(accel);

  if (failures) fprintf(stderr, "%d checks failed\n", failures);
  else printf("C API: all checks passed\n");
  return failures ? 1 : 0;
}
