#version 450
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// WindingExactPass: the sign of the fine voxels the refinement listed because their walked winding number lay within
// kWindingExactBand of 1/2, where the dipoles' error may put it on either side. One work group per listed voxel sums
// the solid angles of every triangle of the instance's mesh (each invocation every RTSDF_WINDING_EXACT_GROUP-th, in
// object space), adds the partial sums in shared memory, and stores the voxel's distance with the side w >= 1/2 of
// that sum: the exact field's rule (WindingNumberTree::inside sums every triangle there too). The refinement has
// already asked the union of closed pieces: a listed voxel no other piece holds.
#include "bvh/GpuBvhLayout.h"
#include "sdf/refine/RefineParams.h"

layout(local_size_x = RTSDF_WINDING_EXACT_GROUP) in;
layout(push_constant) uniform Push { RefineParams params; };
#include "sdf/scenebvh/bvh_bindings.glsl"
layout(std430, binding = kWindingExactBindingDoubts) readonly buffer WindingDoubts { uvec4 doubtHeader; uvec4 doubts[]; };
layout(std430, binding = kWindingExactBindingDense) buffer Dense { float dense[]; };
layout(std430, binding = kWindingExactBindingTriangles) readonly buffer InstanceTriangles { uvec2 instanceTriangles[]; };
layout(std430, binding = kWindingExactBindingStats) buffer Stats { uint refineStats[]; };
#define RTSDF_VALUE_PAGES kWindingExactBindingValuePages
#include "sdf/mask/brick_pool.glsl"
#include "sdf/scenebvh/OpenPieceParams.h"

shared float partial[RTSDF_WINDING_EXACT_GROUP];

vec3 xformPoint(vec4 m[3], vec3 p) {
  return vec3(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w);
}

void main() {
  // The whole group leaves or stays together (a barrier follows).
  if (gl_WorkGroupID.x >= doubtHeader.x) return;
  uvec4 e = doubts[gl_WorkGroupID.x];
  uvec2 range = instanceTriangles[e.w];
  if (range.y > kWindingExactMaxTriangles) {
    if (gl_LocalInvocationIndex == 0u) atomicAdd(refineStats[kRefineStatNearHalfKept], 1u);
    return;
  }
  uvec3 fd = uvec3(params.fineDims.xyz);
  uvec3 v = uvec3(e.x % fd.x, e.x / fd.x % fd.y, e.x / (fd.x * fd.y));
  vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;
  vec3 po = xformPoint(instances[e.w].worldToObject, p);
  float sum = 0.0;
  for (uint t = range.x + gl_LocalInvocationIndex; t < range.x + range.y; t += RTSDF_WINDING_EXACT_GROUP)
    sum += triangleSolidAngle(po, corners[3u * t].xyz, corners[3u * t + 1u].xyz, corners[3u * t + 2u].xyz);
  partial[gl_LocalInvocationIndex] = sum;
  barrier();
  [[unroll]] for (uint stride = RTSDF_WINDING_EXACT_GROUP / 2; stride > 0u; stride /= 2u) {
    if (gl_LocalInvocationIndex < stride) partial[gl_LocalInvocationIndex] += partial[gl_LocalInvocationIndex + stride];
    barrier();
  }
  if (gl_LocalInvocationIndex != 0u) return;
  bool inside = partial[0] * 0.07957747155 >= 0.5; // 1 / 4 pi
  float f = abs(loadValue(e.y, e.z));
  storeValue(e.y, e.z, inside ? -f : f);
  if ((params.coarseDims.w & kRefineWriteDense) != 0) dense[e.x] = inside ? -f : f;
}
