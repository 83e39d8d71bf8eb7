#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass: every voxel whose box a triangle touches becomes a seed (its own packed coordinate).
// One invocation per (triangle, chunk of chunkSize voxels of the triangle's voxel range); empty voxels keep
// kNoSeed. Loops stay short on purpose: lavapipe cut off a single loop of ~100k iterations (lost writes).
#include "gpu/shared/CoarseSdf.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { VoxelizeParams params; };
layout(std430, binding = kVoxelizeBindingCorners) readonly buffer Triangles { vec4 corners[]; }; // 3 per triangle, world space
layout(std430, binding = kVoxelizeBindingSeeds) buffer Seeds { uint seeds[]; };

void main() {
  uint tri = gl_GlobalInvocationID.x;
  if (tri >= params.triangleCount) return;
  vec3 t0 = toVoxelSpace(corners[3 * tri + 0].xyz, params.originInvH);
  vec3 t1 = toVoxelSpace(corners[3 * tri + 1].xyz, params.originInvH);
  vec3 t2 = toVoxelSpace(corners[3 * tri + 2].xyz, params.originInvH);
  ivec3 lo = voxelRangeLo(t0, t1, t2);
  ivec3 n = voxelRangeHi(t0, t1, t2, params.dims.xyz) - lo + ivec3(1);
  int total = (n.x > 0 && n.y > 0 && n.z > 0) ? n.x * n.y * n.z : 0;
  int first = int(gl_GlobalInvocationID.y * params.chunkSize);
  int last = min(total, first + int(params.chunkSize));
  for (int i = first; i < last; ++i) {
    ivec3 v = lo + ivec3(i % n.x, (i / n.x) % n.y, i / (n.x * n.y));
    if (voxelOverlaps(v, t0, t1, t2)) seeds[(v.z * params.dims.y + v.y) * params.dims.x + v.x] = packSeed(v);
  }
}
