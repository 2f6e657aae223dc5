/* rayaccel's C API: scenes from the caller's arrays, structures built by spec string, closest-hit and any-hit queries
 * (one ray, batches, packets), for C and for bindings (Rust, Julia, C#, Go, Fortran, Python ctypes). Plain C99/C11:
 * opaque handles, fixed-size records, status codes plus a per-thread error message; no C++ exception crosses it. */
#ifndef RAYACCEL_RAYACCEL_C_H
#define RAYACCEL_RAYACCEL_C_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What every call returns; the message of a failure is rayaccel_last_error(). */
typedef enum rayaccel_status {
  RAYACCEL_OK = 0,
  RAYACCEL_INVALID_ARGUMENT = 1, /* a null pointer, a bad count, an index out of range, an unknown spec or option */
  RAYACCEL_INVALID_OPERATION = 2, /* e.g. adding a mesh to a scene a structure was already built over */
  RAYACCEL_OUT_OF_MEMORY = 3,
  RAYACCEL_INTERNAL_ERROR = 4 /* anything else; the message says what */
} rayaccel_status;

/* The id of no primitive and no geometry: a miss's prim_id and geom_id. */
#define RAYACCEL_INVALID_ID 0xFFFFFFFFu

/* A ray, the 32-byte record of a .rays file: a hit counts when t_min < t <= t_max; the direction need not be unit
 * length (t is in units of its length). A ray with a NaN or infinite component, a zero direction or t_max < t_min
 * hits nothing. */
typedef struct rayaccel_ray {
  float org_x, org_y, org_z, t_min;
  float dir_x, dir_y, dir_z, t_max;
} rayaccel_ray;

/* A closest hit: t, and (u, v) with hit point (1-u-v)*v0 + u*v1 + v*v2, as in Embree. prim_id is the triangle's index
 * within its mesh and geom_id the mesh's id (the order rayaccel_scene_add_mesh was called); a miss has t = +inf,
 * prim_id = geom_id = RAYACCEL_INVALID_ID and u = v = 0. */
typedef struct rayaccel_hit {
  float t;
  uint32_t prim_id;
  float u, v;
  uint32_t geom_id;
} rayaccel_hit;

typedef struct rayaccel_scene rayaccel_scene; /* meshes; immutable once a structure is built over it */
typedef struct rayaccel_accel rayaccel_accel; /* a built structure; keeps its scene alive */

/* The message of the last failed call on this thread ("" when the last call succeeded); valid until the next call. */
const char* rayaccel_last_error(void);
/* The library's version, e.g. "0.1.0". */
const char* rayaccel_version(void);

rayaccel_status rayaccel_scene_new(rayaccel_scene** out);
/* Drops the caller's reference (structures built over the scene keep it alive); null is ignored. */
void rayaccel_scene_release(rayaccel_scene* scene);
/* Copies a triangle mesh into the scene: `vertices` holds 3 floats (x, y, z) per vertex, `indices` 3 vertex indices
 * per triangle (into this mesh's own vertices). Its id (0, 1, ... in call order) goes to *geom_id when not null.
 * Fails (RAYACCEL_INVALID_OPERATION) once a structure was built over the scene. */
rayaccel_status rayaccel_scene_add_mesh(rayaccel_scene* scene, const float* vertices, size_t vertex_count,
                                        const uint32_t* indices, size_t triangle_count, uint32_t* geom_id);
rayaccel_status rayaccel_scene_geometry_count(const rayaccel_scene* scene, uint32_t* count);
/* Triangles of all meshes. */
rayaccel_status rayaccel_scene_primitive_count(const rayaccel_scene* scene, uint32_t* count);

/* Builds the structure `spec` names ("bvh_wide", "kdtree:builder=sah,leaf_size=4"; `rayaccel list --names` prints
 * them all) over the scene. */
rayaccel_status rayaccel_accel_new(rayaccel_scene* scene, const char* spec, rayaccel_accel** out);
void rayaccel_accel_release(rayaccel_accel* accel);

/* One ray: the closest hit, or whether anything is hit (*occluded = 1 or 0). */
rayaccel_status rayaccel_intersect1(const rayaccel_accel* accel, const rayaccel_ray* ray, rayaccel_hit* hit);
rayaccel_status rayaccel_occluded1(const rayaccel_accel* accel, const rayaccel_ray* ray, int* occluded);
/* Batches of `count` rays, traced in parallel; occluded[i] is 1 or 0. */
rayaccel_status rayaccel_intersect(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                   rayaccel_hit* hits);
rayaccel_status rayaccel_occluded(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                  uint8_t* occluded);
/* Batches of coherent rays: each run of 8 consecutive rays is traced as one packet where the structure has a packet
 * traversal (bvh_wide), one by one elsewhere; the answers are those of the batch calls (a tie in t may name
 * another triangle). */
rayaccel_status rayaccel_intersect_packets(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                           rayaccel_hit* hits);
rayaccel_status rayaccel_occluded_packets(const rayaccel_accel* accel, const rayaccel_ray* rays, size_t count,
                                          uint8_t* occluded);

/* Skip, masks and filters (Embree's ray mask, geometry mask and intersection filter). A hit a leaf finds, offered to
 * a filter before it is kept: the triangle (prim_id within geometry geom_id), t, u, v, and the ray's index in the
 * call's array. */
typedef struct rayaccel_candidate {
  uint32_t geom_id, prim_id;
  float t, u, v;
  size_t ray_index;
} rayaccel_candidate;
/* Returns nonzero to accept the candidate, 0 to reject it (traversal goes on as if the triangle were not there for
 * this ray). Called only for candidates closer than the closest accepted so far, in any order, possibly on several
 * threads at once; it must not call back into rayaccel. */
typedef int (*rayaccel_filter)(void* user_data, const rayaccel_candidate* candidate);
/* The optional controls of a batch: every pointer may be null (that control off); the per-ray arrays hold one entry
 * per ray of the call. A triangle of geometry g is a candidate of ray i only when it is not (skip_geom_id[i],
 * skip_prim_id[i]), g != skip_geometry[i] and (ray_mask[i] & the geometry's mask) != 0 (rayaccel_scene_set_mask),
 * all tested before the exact triangle test; then filter must accept it. RAYACCEL_INVALID_ID skips nothing. */
typedef struct rayaccel_query_context {
  const uint32_t* skip_geom_id; /* per ray, with skip_prim_id: the triangle the ray leaves (its own surface) */
  const uint32_t* skip_prim_id; /* per ray */
  const uint32_t* skip_geometry; /* per ray: a whole geometry the ray ignores */
  const uint32_t* ray_mask; /* per ray; null: all ones */
  rayaccel_filter filter; /* null: every candidate is accepted */
  void* filter_data;
} rayaccel_query_context;
/* Sets geometry geom_id's mask (all ones until set; 0 disables the geometry), read by the calls below; no rebuild is
 * needed. Not while queries over the scene run. */
rayaccel_status rayaccel_scene_set_mask(rayaccel_scene* scene, uint32_t geom_id, uint32_t mask);
/* The batch calls under a context (null: no per-ray controls; the geometry masks still apply to an all-ones ray
 * mask). A single ray is a batch of one. */
rayaccel_status rayaccel_intersect_context(const rayaccel_accel* accel, const rayaccel_query_context* context,
                                           const rayaccel_ray* rays, size_t count, rayaccel_hit* hits);
rayaccel_status rayaccel_occluded_context(const rayaccel_accel* accel, const rayaccel_query_context* context,
                                          const rayaccel_ray* rays, size_t count, uint8_t* occluded);
/* The packet calls under a context: the answers of the two calls above, each run of 8 consecutive rays traced as one
 * packet where the structure has a packet traversal (bvh_wide). */
rayaccel_status rayaccel_intersect_packets_context(const rayaccel_accel* accel, const rayaccel_query_context* context,
                                                   const rayaccel_ray* rays, size_t count, rayaccel_hit* hits);
rayaccel_status rayaccel_occluded_packets_context(const rayaccel_accel* accel, const rayaccel_query_context* context,
                                                  const rayaccel_ray* rays, size_t count, uint8_t* occluded);

#ifdef __cplusplus
}
#endif

#endif /* RAYACCEL_RAYACCEL_C_H */
