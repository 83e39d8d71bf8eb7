#version 450
#extension GL_GOOGLE_include_directive : require
// JumpFloodPass, one step: each voxel keeps the nearest of the seeds held by itself and its 26 neighbours
// at distance 'step' (ties go to the smaller packed seed, so the result does not depend on order).
// Same candidates and the same rule as jumpFloodCpu() (sdf/coarse/CoarseCpu.cpp).
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { JumpFloodParams params; };
layout(std430, binding = kJumpFloodBindingSrc) readonly buffer Src { uint src[]; };
layout(std430, binding = kJumpFloodBindingDst) writeonly buffer Dst { uint dst[]; };

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = params.dims.xyz;
  if (any(greaterThanEqual(p, dims))) return;
  int k = params.step;
  uint best = src[(p.z * dims.y + p.y) * dims.x + p.x];
  int bestD = best == kNoSeed ? 0x7fffffff : distance2(p, unpackSeed(best));
  for (int dz = -1; dz <= 1; ++dz) {
    int qz = p.z + k * dz;
    if (qz < 0 || qz >= dims.z) continue;
    for (int dy = -1; dy <= 1; ++dy) {
      int qy = p.y + k * dy;
      if (qy < 0 || qy >= dims.y) continue;
      int row = (qz * dims.y + qy) * dims.x;
      for (int dx = -1; dx <= 1; ++dx) {
        int qx = p.x + k * dx;
        if (qx < 0 || qx >= dims.x || (dx == 0 && dy == 0 && dz == 0)) continue;
        uint s = src[row + qx];
        if (s == kNoSeed) continue;
        int d = distance2(p, unpackSeed(s));
        if (d < bestD || (d == bestD && s < best)) { best = s; bestD = d; }
      }
    }
  }
  dst[(p.z * dims.y + p.y) * dims.x + p.x] = best;
}
