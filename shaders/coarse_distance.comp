#version 450
#extension GL_GOOGLE_include_directive : require
// The coarse SDF from the nearest seeds: c = |p - seed| * h - beta (the paper's thin negative shells).
#include "gpu/shared/CoarseSdf.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { CoarseDistanceParams params; };
layout(std430, binding = 0) readonly buffer Nearest { uint nearest[]; };
layout(std430, binding = 1) writeonly buffer Distance { float distance[]; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  ivec3 dims = params.dims.xyz;
  if (i >= uint(dims.x * dims.y * dims.z)) return;
  uint s = nearest[i];
  if (s == kNoSeed) { distance[i] = params.emptyDistance; return; }
  ivec3 p = ivec3(int(i) % dims.x, (int(i) / dims.x) % dims.y, int(i) / (dims.x * dims.y));
  distance[i] = sqrt(float(distance2(p, unpackSeed(s)))) * params.voxelSize - params.beta;
}
