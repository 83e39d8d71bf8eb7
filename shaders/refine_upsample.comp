#version 450
#extension GL_GOOGLE_include_directive : require
// The first half of a refinement frame: every fine voxel gets the coarse SDF c_t, trilinearly upsampled
// (the value outside the ray mask; RayRefinePass then overwrites the masked voxels).
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_UPSAMPLE_GROUP_X, local_size_y = RTSDF_UPSAMPLE_GROUP_Y, local_size_z = RTSDF_UPSAMPLE_GROUP_Z) in;
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kUpsampleBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kUpsampleBindingFine) writeonly buffer Fine { float fine[]; };

float coarseAt(ivec3 c) {
  ivec3 d = params.coarseDims.xyz;
  return coarse[(c.z * d.y + c.y) * d.x + c.x];
}

void main() {
  ivec3 v = ivec3(gl_GlobalInvocationID);
  ivec3 fd = params.fineDims.xyz;
  if (any(greaterThanEqual(v, fd))) return;
  vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;
  vec3 g = (p - params.coarseOriginInvH.xyz) * params.coarseOriginInvH.w - 0.5;
  ivec3 cd = params.coarseDims.xyz;
  ivec3 i0 = clamp(ivec3(floor(g)), ivec3(0), cd - 1);
  ivec3 i1 = min(i0 + 1, cd - 1);
  vec3 t = clamp(g - vec3(i0), 0.0, 1.0);
  float c00 = mix(coarseAt(ivec3(i0.x, i0.y, i0.z)), coarseAt(ivec3(i1.x, i0.y, i0.z)), t.x);
  float c10 = mix(coarseAt(ivec3(i0.x, i1.y, i0.z)), coarseAt(ivec3(i1.x, i1.y, i0.z)), t.x);
  float c01 = mix(coarseAt(ivec3(i0.x, i0.y, i1.z)), coarseAt(ivec3(i1.x, i0.y, i1.z)), t.x);
  float c11 = mix(coarseAt(ivec3(i0.x, i1.y, i1.z)), coarseAt(ivec3(i1.x, i1.y, i1.z)), t.x);
  fine[(v.z * fd.y + v.y) * fd.x + v.x] = mix(mix(c00, c10, t.y), mix(c01, c11, t.y), t.z);
}
