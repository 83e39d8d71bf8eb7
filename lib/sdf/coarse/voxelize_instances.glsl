// The triangles of every instance as voxelize_chunks.comp places them: mesh-space corners moved by their
// instance's transform on the GPU, then into voxel space. Invocation x takes one triangle of all instances.
#include "sdf/coarse/CoarseParams.h"

layout(push_constant) uniform Push { VoxelizeParams params; };
layout(std430, binding = kVoxelizeBindingCorners) readonly buffer Corners { vec4 corners[]; }; // 3 per triangle
layout(std430, binding = kVoxelizeBindingInstances) readonly buffer Instances { VoxelizeInstance instances[]; };

// The voxel-space corners of triangle g (< params.triangleCount) of all instances together: its instance is the
// last whose firstInstanceTriangle <= g (a binary search: instances are few, their triangles many).
void placeInstanceTriangle(uint g, out vec3 t0, out vec3 t1, out vec3 t2) {
  uint lo = 0u, hi = params.instanceCount - 1u;
  while (lo < hi) {
    uint mid = (lo + hi + 1u) / 2u;
    if (instances[mid].firstInstanceTriangle <= g) lo = mid; else hi = mid - 1u;
  }
  VoxelizeInstance inst = instances[lo];
  uint tri = inst.firstTriangle + (g - inst.firstInstanceTriangle);
  vec4 r0 = inst.objectToFrame[0], r1 = inst.objectToFrame[1], r2 = inst.objectToFrame[2];
  t0 = toVoxelSpace(transformToFrame(r0, r1, r2, corners[3u * tri].xyz), params.originInvH);
  t1 = toVoxelSpace(transformToFrame(r0, r1, r2, corners[3u * tri + 1u].xyz), params.originInvH);
  t2 = toVoxelSpace(transformToFrame(r0, r1, r2, corners[3u * tri + 2u].xyz), params.originInvH);
}
