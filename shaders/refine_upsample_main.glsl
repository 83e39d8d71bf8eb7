// UpsamplePass's body (the includer defines RTSDF_UPSAMPLE_RUN): the first half of a refinement frame, every
// fine voxel gets the coarse SDF c_t trilinearly upsampled (the value outside the ray mask; the refinement then
// overwrites the masked voxels). One invocation per run of RTSDF_UPSAMPLE_RUN fine voxels along z (neighbouring
// invocations: neighbouring x, so a group's writes are contiguous): the run keeps the 2 x 2 x 2 coarse values
// of its cell and loads only the new z plane of 4 when it crosses into the next coarse cell.
// Weights and the order of the lerps are upsampleCoarse()'s (sdf/RefineReference.cpp).
#include "gpu/shared/Refine.h"

layout(local_size_x = RTSDF_UPSAMPLE_GROUP_X, local_size_y = RTSDF_UPSAMPLE_GROUP_Y, local_size_z = 1) in;
layout(push_constant) uniform Push { RefineParams params; };
layout(std430, binding = kUpsampleBindingCoarse) readonly buffer Coarse { float coarse[]; };
layout(std430, binding = kUpsampleBindingFine) writeonly buffer Fine { float fine[]; };

// The four coarse values of plane z at the cell's x and y corners: (x0 y0, x1 y0, x0 y1, x1 y1).
vec4 coarsePlane(ivec2 x01, ivec2 y01, int z) {
  ivec3 d = params.coarseDims.xyz;
  int r0 = (z * d.y + y01.x) * d.x, r1 = (z * d.y + y01.y) * d.x;
  return vec4(coarse[r0 + x01.x], coarse[r0 + x01.y], coarse[r1 + x01.x], coarse[r1 + x01.y]);
}

void main() {
  ivec3 fd = params.fineDims.xyz;
  ivec3 cd = params.coarseDims.xyz;
  int x = int(gl_GlobalInvocationID.x), y = int(gl_GlobalInvocationID.y);
  int zBegin = int(gl_GlobalInvocationID.z) * RTSDF_UPSAMPLE_RUN;
  if (x >= fd.x || y >= fd.y || zBegin >= fd.z) return;
  int zEnd = min(zBegin + RTSDF_UPSAMPLE_RUN, fd.z);
  int plane0 = -1, plane1 = -1;
  vec4 c0 = vec4(0.0), c1 = vec4(0.0); // planes i0.z and i1.z
  for (int z = zBegin; z < zEnd; ++z) {
    ivec3 v = ivec3(x, y, z);
    vec3 p = params.fineOriginH.xyz + (vec3(v) + 0.5) * params.fineOriginH.w;
    vec3 g = (p - params.coarseOriginInvH.xyz) * params.coarseOriginInvH.w - 0.5;
    ivec3 i0 = clamp(ivec3(floor(g)), ivec3(0), cd - 1);
    ivec3 i1 = min(i0 + 1, cd - 1);
    vec3 t = clamp(g - vec3(i0), 0.0, 1.0);
    ivec2 x01 = ivec2(i0.x, i1.x), y01 = ivec2(i0.y, i1.y);
    if (i0.z != plane0) {
      c0 = i0.z == plane1 ? c1 : coarsePlane(x01, y01, i0.z);
      plane0 = i0.z;
    }
    if (i1.z != plane1) {
      c1 = i1.z == plane0 ? c0 : coarsePlane(x01, y01, i1.z);
      plane1 = i1.z;
    }
    float c00 = mix(c0.x, c0.y, t.x);
    float c10 = mix(c0.z, c0.w, t.x);
    float c01 = mix(c1.x, c1.y, t.x);
    float c11 = mix(c1.z, c1.w, t.x);
    fine[(v.z * fd.y + v.y) * fd.x + v.x] = mix(mix(c00, c10, t.y), mix(c01, c11, t.y), t.z);
  }
}
