// Shared by C++ and GLSL: the flattened BVH layout the GPU traverses (bottom level per mesh in object
// space, top level over instances in world space) and the query records of bvh_query.comp. Here rather than
// beside GpuSceneBvh (sdf/scenebvh) because the flattening (bvh/Bvh.h) writes it.
#ifndef RTSDF_BVH_GPUBVHLAYOUT_H
#define RTSDF_BVH_GPUBVHLAYOUT_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// Bindings of the scene BVH in every shader that includes bvh_bindings.glsl (GpuSceneBvh::bind fills them).
const uint kBvhBindingBlasNodes = 0u;   // bottom-level nodes of every mesh
const uint kBvhBindingCorners = 1u;     // triangle corners in leaf order, object space
const uint kBvhBindingTriangleIds = 2u; // leaf order -> the mesh's triangle index
const uint kBvhBindingTlasNodes = 3u;   // top-level nodes over the instances
const uint kBvhBindingTlasSlots = 4u;   // top-level leaf order -> instance
const uint kBvhBindingInstances = 5u;   // BvhInstance per instance
const uint kBvhBindingCount = 6u;

/// Bindings of bvh_query.comp after the BVH's.
const uint kBvhQueryBindingQueries = kBvhBindingCount + 0u;
const uint kBvhQueryBindingHits = kBvhBindingCount + 1u;
const uint kBvhQueryBindingCount = kBvhBindingCount + 2u;

/// A BVH node, 32 bytes. Inner node (count == 0): children at 'first' and 'first + 1'. Leaf: 'count'
/// primitives from 'first' (triangles for a bottom level, instance slots for the top level).
struct BvhNode {
  vec4 lo; // xyz: box min, w: uintBitsToFloat(first)
  vec4 hi; // xyz: box max, w: uintBitsToFloat(count)
};

/// One placed mesh: its transforms (rows of 3x4 matrices) and the root of its bottom-level BVH.
struct BvhInstance {
  vec4 worldToObject[3];
  vec4 objectToWorld[3];
  uint blasRoot;     // node index in the bottom-level node array
  uint mirrored;     // 1 when the transform flips orientation (front and back faces swap)
  uint instanceId;   // index in the scene's instance list
  float minScale;    // lower bound of the transform's smallest singular value (culls closest-point queries)
};

/// bvh_query.comp: a ray (or, for closest-point queries, a point in origin.xyz and a radius in origin.w).
struct BvhQuery {
  vec4 origin;    // xyz origin, w: tmin (rays) or max distance (points)
  vec4 direction; // xyz direction (not necessarily unit; t is in its units), w: tmax
};

/// bvh_query.comp's answer: nearest hit (rays) or closest point (points).
struct BvhHit {
  vec4 point;     // xyz: hit or closest point (world), w: t (rays) or distance (points); negative: none
  uint instance;  // index in the scene's instance list
  uint triangle;  // index in the mesh's (validated) triangle list
  uint frontFace; // rays: 1 when the ray hit the outside (front) of the triangle
  uint leaf;      // leaf-order triangle index (its corners are corners[3 leaf .. 3 leaf + 2], object space)
};

/// The distance from @a p to the box [@a lo, @a hi] (0 inside): BVH culling and the refinement's moved boxes.
RTSDF_FN float boxDistance(vec3 p, vec3 lo, vec3 hi) { return length(max(max(lo - p, p - hi), vec3(0.0))); }

RTSDF_SHARED_END

#endif
