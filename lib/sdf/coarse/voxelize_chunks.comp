#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass, the dispatch before voxelize.comp's: places every instance triangle in voxel space (once:
// voxelize.comp's many invocations per triangle read it), counts the chunks of its range inside the clip box, and
// fills voxelize.comp's two indirect dispatches (kVoxelizeDispatchWords), so the host never scans the triangles: a
// triangle of at most kVoxelizeFirstChunks chunks is the first's, which runs as many chunks of every triangle as the
// most of those needs; one with more is listed, and the second runs the listed triangles' chunks (along y at most
// maxChunkGroups, layers of them along z), as many as the most needs. A triangle whose range misses the box: none.
#include "voxelize_instances.glsl"

layout(local_size_x = 64) in;
layout(std430, binding = kVoxelizeBindingDispatch) buffer Dispatch { uint words[]; };
layout(std430, binding = kVoxelizeBindingPlaced) writeonly buffer Placed { vec4 placed[]; };
layout(std430, binding = kVoxelizeBindingLarge) writeonly buffer Large { uint large[]; };

shared uint groupFirst, groupMost, groupLayers;

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    groupFirst = 0u;
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
    ivec3 corner = params.cornerCell.xyz; // the clip box as lattice cells
    uint chunks =
        voxelRangeChunks(t0, t1, t2, params.clipLo.xyz + corner, params.clipHi.xyz + corner, params.chunkSize);
    if (chunks > kVoxelizeFirstChunks) {
      // Listed: a group of 64 more for the second dispatch with every 64th.
      uint n = atomicAdd(words[kVoxelizeLargeCount], 1u);
      large[n] = g;
      if (n % 64u == 0u) atomicAdd(words[kVoxelizeDispatchLarge], 1u);
      atomicMax(groupMost, min(chunks, params.maxChunkGroups));
      atomicMax(groupLayers, (chunks + params.maxChunkGroups - 1u) / params.maxChunkGroups);
    } else if (chunks > 0u) {
      atomicMax(groupFirst, chunks);
    }
  }
  barrier();
  // One global atomic per count and work group.
  if (gl_LocalInvocationIndex == 0u && groupFirst > 0u) {
    atomicMax(words[kVoxelizeDispatchFirst + 1u], groupFirst);
    atomicMax(words[kVoxelizeDispatchFirst + 2u], 1u);
  }
  if (gl_LocalInvocationIndex == 0u && groupMost > 0u) {
    atomicMax(words[kVoxelizeDispatchLarge + 1u], groupMost);
    atomicMax(words[kVoxelizeDispatchLarge + 2u], groupLayers);
  }
}
