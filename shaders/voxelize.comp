#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass: every voxel whose box a triangle touches becomes a seed (its own packed coordinate).
// One invocation per (triangle, z-slab of its voxel range); empty voxels keep kNoSeed.
#include "gpu/shared/CoarseSdf.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { VoxelizeParams params; };
layout(std430, binding = 0) readonly buffer Triangles { vec4 corners[]; }; // 3 per triangle, world space
layout(std430, binding = 1) buffer Seeds { uint seeds[]; };

void main() {
  uint tri = gl_GlobalInvocationID.x;
  if (tri >= params.triangleCount) return;
  vec3 t0 = toVoxelSpace(corners[3 * tri + 0].xyz, params.originInvH);
  vec3 t1 = toVoxelSpace(corners[3 * tri + 1].xyz, params.originInvH);
  vec3 t2 = toVoxelSpace(corners[3 * tri + 2].xyz, params.originInvH);
  ivec3 lo = voxelRangeLo(t0, t1, t2);
  ivec3 hi = voxelRangeHi(t0, t1, t2, params.dims.xyz);
  int z0 = lo.z + int(gl_GlobalInvocationID.y * params.slabSize);
  int z1 = min(hi.z, z0 + int(params.slabSize) - 1);
  for (int z = z0; z <= z1; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        ivec3 v = ivec3(x, y, z);
        if (voxelOverlaps(v, t0, t1, t2))
          seeds[(z * params.dims.y + y) * params.dims.x + x] = packSeed(v);
      }
}
