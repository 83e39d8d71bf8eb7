#version 450
#extension GL_GOOGLE_include_directive : require
// SeedShiftPass: the seeds of a grid that scrolled by whole voxels, moved so that a build after the scroll voxelizes
// only the voxels that entered (CoarseSdfBuilder::recordScroll). A seed packs its own voxel's coordinate, so a moved
// seed is packed again at its new voxel: voxel v takes a seed where v + shift lay in the grid and held one. One
// invocation per voxel; the source is a copy of the seeds before the scroll.
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { SeedShiftParams params; };
layout(std430, binding = kSeedShiftBindingSource) readonly buffer Source { uint source[]; };
layout(std430, binding = kSeedShiftBindingSeeds) writeonly buffer Seeds { uint seeds[]; };

void main() {
  ivec3 dims = params.dims.xyz;
  ivec3 v = ivec3(gl_GlobalInvocationID);
  if (any(greaterThanEqual(v, dims))) return;
  ivec3 from = v + params.shift.xyz;
  bool kept = all(greaterThanEqual(from, ivec3(0))) && all(lessThan(from, dims));
  uint seed = kept ? source[(from.z * dims.y + from.y) * dims.x + from.x] : kNoSeed;
  seeds[(v.z * dims.y + v.y) * dims.x + v.x] = seed == kNoSeed ? kNoSeed : packSeed(v);
}
