#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass, first dispatch: places every instance triangle in voxel space (once: voxelize.comp's many
// invocations per triangle read it), and the most chunks any triangle's voxel range needs becomes voxelize.comp's
// indirect dispatch along y and z (y at most maxChunkGroups, z as many layers of y as the rest needs), so the
// host never scans the triangles.
#include "voxelize_instances.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = kVoxelizeBindingDispatch) buffer Dispatch { uint groups[3]; };
layout(std430, binding = kVoxelizeBindingPlaced) writeonly buffer Placed { vec4 placed[]; };

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
    placeInstanceTriangle(g, t0, t1, t2);
    placed[3u * g] = vec4(t0, 0.0);
    placed[3u * g + 1u] = vec4(t1, 0.0);
    placed[3u * g + 2u] = vec4(t2, 0.0);
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
