#version 450
#extension GL_GOOGLE_include_directive : require
// The coarse SDF from the nearest seeds: c = |p - seed| * h - beta (the paper's thin negative shells). Each voxel whose
// value differs from the last build's (bit for bit) grows the changed box: per work group in shared memory, then one
// atomic per bound, so the passes after it can run over the region that changed (UpsamplePass).
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_JFA_GROUP_X, local_size_y = RTSDF_JFA_GROUP_Y, local_size_z = RTSDF_JFA_GROUP_Z) in;
layout(push_constant) uniform Push { CoarseDistanceParams params; };
layout(std430, binding = kCoarseDistanceBindingNearest) readonly buffer Nearest { uint nearest[]; };
layout(std430, binding = kCoarseDistanceBindingDistance) buffer Distance { float distance[]; };
layout(std430, binding = kCoarseDistanceBindingChanged) buffer Changed { ChangedBox changed; };

shared uint sLo[3], sHi[3];

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    for (int a = 0; a < 3; ++a) {
      sLo[a] = kChangedBoxEmptyLo;
      sHi[a] = 0u;
    }
  }
  barrier();
  ivec3 p = ivec3(gl_GlobalInvocationID);
  ivec3 dims = params.dims.xyz;
  if (all(lessThan(p, dims))) {
    int i = (p.z * dims.y + p.y) * dims.x + p.x;
    uint s = nearest[i];
    float c = s == kNoSeed ? params.emptyDistance
                           : sqrt(float(distance2(p, unpackSeed(s)))) * params.voxelSize - params.beta;
    if (floatBitsToUint(distance[i]) != floatBitsToUint(c)) {
      for (int a = 0; a < 3; ++a) {
        atomicMin(sLo[a], uint(p[a]));
        atomicMax(sHi[a], uint(p[a]));
      }
    }
    distance[i] = c;
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u && sLo[0] != kChangedBoxEmptyLo) {
    for (int a = 0; a < 3; ++a) {
      atomicMin(changed.lo[a], sLo[a]);
      atomicMax(changed.hi[a], sHi[a]);
    }
  }
}
