#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass, first dispatch of a build over a change: the seeds of the clip box reset to kNoSeed (the triangles
// write theirs again), one invocation per voxel of the box; the seeds outside it stay the last build's. A full build
// fills the whole buffer instead (vkCmdFillBuffer).
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { VoxelizeParams params; };
layout(std430, binding = kVoxelizeBindingSeeds) writeonly buffer Seeds { uint seeds[]; };

void main() {
  ivec3 v = params.clipLo.xyz + ivec3(gl_GlobalInvocationID);
  if (any(greaterThan(v, params.clipHi.xyz))) return;
  seeds[(v.z * params.dims.y + v.y) * params.dims.x + v.x] = kNoSeed;
}
