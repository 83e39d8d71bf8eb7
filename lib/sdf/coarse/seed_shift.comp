#version 450
#extension GL_GOOGLE_include_directive : require
// SeedShiftPass: the seeds or nearest seeds of a grid that scrolled by whole voxels, moved so that a build after the
// scroll voxelizes only the voxels that entered and transforms only what they and the seeds that left reach
// (CoarseSdfBuilder::recordScroll). A packed seed is a voxel's coordinate, so a moved one is packed again from the
// grid's new corner: voxel v takes what v + shift held, seed u becoming u - shift, none where v entered or the seed
// left the grid (a seed buffer's own seeds never leave: u = v + shift). One invocation per voxel; the source is a
// copy of the buffer before the scroll.
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
  ivec3 u = unpackSeed(seed) - params.shift.xyz;
  bool inGrid = all(greaterThanEqual(u, ivec3(0))) && all(lessThan(u, dims));
  seeds[(v.z * dims.y + v.y) * dims.x + v.x] = seed != kNoSeed && inGrid ? packSeed(u) : kNoSeed;
}
