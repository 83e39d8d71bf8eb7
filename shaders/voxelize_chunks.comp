#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass, first dispatch: the most chunks any triangle's voxel range needs becomes voxelize.comp's
// indirect dispatch along y and z (y at most maxChunkGroups, z as many layers of y as the rest needs), so the
// host never scans the triangles.
#include "voxelize_instances.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = kVoxelizeBindingDispatch) buffer Dispatch { uint groups[3]; };

shared uint groupMost, groupLayers;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    groupMost = 0u;
    groupLayers = 0u;
  }
  barrier();
  uint g = gl_GlobalInvocationID.x;
  if (g < params.triangleCount) {
    vec3 t0, t1, t2;
    instanceTriangle(g, t0, t1, t2);
    uint chunks = voxelRangeChunks(t0, t1, t2, params.dims.xyz, params.chunkSize);
    if (chunks > 0u) {
      atomicMax(groupMost, min(chunks, params.maxChunkGroups));
      atomicMax(groupLayers, (chunks + params.maxChunkGroups - 1u) / params.maxChunkGroups);
    }
  }
  barrier();
  // One global atomic per count and work group.
  if (gl_LocalInvocationIndex == 0u && groupMost > 0u) {
    atomicMax(groups[1], groupMost);
    atomicMax(groups[2], groupLayers);
  }
}
