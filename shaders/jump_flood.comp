#version 450
#extension GL_GOOGLE_include_directive : require
// JumpFloodPass, one step: each voxel keeps the nearest of the seeds held by itself and its 26 neighbours
// at distance 'step' (ties go to the smaller packed seed, so the result does not depend on order).
#include "gpu/shared/CoarseSdf.h"

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
layout(push_constant) uniform Push { JumpFloodParams params; };
layout(std430, binding = 0) readonly buffer Src { uint src[]; };
layout(std430, binding = 1) writeonly buffer Dst { uint dst[]; };

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = params.dims.xyz;
  if (any(greaterThanEqual(p, dims))) return;
  uint best = src[(p.z * dims.y + p.y) * dims.x + p.x];
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        ivec3 q = p + params.step * ivec3(dx, dy, dz);
        if (any(lessThan(q, ivec3(0))) || any(greaterThanEqual(q, dims))) continue;
        best = nearerSeed(p, best, src[(q.z * dims.y + q.y) * dims.x + q.x]);
      }
  dst[(p.z * dims.y + p.y) * dims.x + p.x] = best;
}
