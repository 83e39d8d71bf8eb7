#version 450
#extension GL_GOOGLE_include_directive : require
// MaskCompactPass: the ray mask appended on the GPU. One invocation per coarse voxel: a voxel in the band
// (|c| <= d, the float comparison of the CPU mirror) appends itself to the coarse list and the fine voxels whose
// centres lie in it (the per-axis range tables, computed on the CPU as the mirror does) to the fine list. One
// atomic per band voxel reserves its whole run of fine slots; the refinement hashes by voxel, not by slot, so
// the lists' order does not matter.
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_MASK_GROUP, local_size_y = RTSDF_MASK_GROUP, local_size_z = RTSDF_MASK_GROUP) in;
layout(push_constant) uniform Push { MaskParams params; };
layout(std430, binding = kMaskBindingCounts) buffer Counts { uint counts[]; };
layout(std430, binding = kMaskBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kMaskBindingFineRanges) readonly buffer FineRanges { ivec2 fineRanges[]; };
layout(std430, binding = kMaskBindingFineList) writeonly buffer FineList { uint fineList[]; };
layout(std430, binding = kMaskBindingCoarseList) writeonly buffer CoarseList { uvec2 coarseList[]; };

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = params.coarseDims.xyz;
  if (any(greaterThanEqual(p, dims))) return;
  uint i = uint((p.z * dims.y + p.y) * dims.x + p.x);
  float c = coarse[i];
  if (!(abs(c) <= params.band)) return;
  uint slot = atomicAdd(counts[kMaskCountCoarse], 1u);
  if (slot < params.coarseCapacity) coarseList[slot] = uvec2(i, floatBitsToUint(c));
  ivec2 rx = fineRanges[p.x], ry = fineRanges[dims.x + p.y], rz = fineRanges[dims.x + dims.y + p.z];
  ivec3 n = max(ivec3(rx.y, ry.y, rz.y) - ivec3(rx.x, ry.x, rz.x) + 1, ivec3(0));
  uint count = uint(n.x * n.y * n.z);
  if (count == 0u) return;
  uint base = atomicAdd(counts[kMaskCountFine], count);
  for (int z = rz.x; z <= rz.y; ++z)
    for (int y = ry.x; y <= ry.y; ++y)
      for (int x = rx.x; x <= rx.y; ++x, ++base)
        if (base < params.fineCapacity) fineList[base] = uint(x) | (uint(y) << 10) | (uint(z) << 20);
}
