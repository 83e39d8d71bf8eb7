#version 450
#extension GL_GOOGLE_include_directive : require
// Batch BVH queries: nearest ray hits (mode 0) or closest points (mode 1). Used by tests to prove the GPU
// traversal against Embree and the exact reference; the refinement passes share bvh_traverse.glsl.
#include "bvh/GpuBvhLayout.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { uint count; uint mode; uint pad0, pad1; } params;
#include "bvh_bindings.glsl"
layout(std430, binding = kBvhQueryBindingQueries) readonly buffer Queries { BvhQuery queries[]; };
layout(std430, binding = kBvhQueryBindingHits) writeonly buffer Hits { BvhHit hits[]; };

#include "bvh_traverse.glsl"

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= params.count) return;
  BvhQuery q = queries[i];
  BvhHit h;
  if (params.mode == 0u) traceNearest(q.origin.xyz, q.direction.xyz, q.origin.w, q.direction.w, h);
  else closestPoint(q.origin.xyz, q.origin.w, h);
  hits[i] = h;
}
