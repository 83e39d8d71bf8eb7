#version 450
#extension GL_GOOGLE_include_directive : require
// The coarse SDF from the nearest seeds: c = |p - seed| * h - beta (the paper's thin negative shells).
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { CoarseDistanceParams params; };
layout(std430, binding = kCoarseDistanceBindingNearest) readonly buffer Nearest { uint nearest[]; };
layout(std430, binding = kCoarseDistanceBindingDistance) writeonly buffer Distance { float distance[]; };

void main() {
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = params.dims.xyz;
  if (any(greaterThanEqual(p, dims))) return;
  int i = (p.z * dims.y + p.y) * dims.x + p.x;
  uint s = nearest[i];
  distance[i] = s == kNoSeed ? params.emptyDistance
                             : sqrt(float(distance2(p, unpackSeed(s)))) * params.voxelSize - params.beta;
}
