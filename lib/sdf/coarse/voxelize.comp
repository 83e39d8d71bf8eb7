#version 450
#extension GL_GOOGLE_include_directive : require
// VoxelizePass, the two indirect dispatches after voxelize_chunks.comp: every voxel of the clip box whose box a
// triangle touches becomes a seed (its own packed coordinate). The triangles are placed in the cells of a lattice
// whose cell params.cornerCell is the grid's voxel (0,0,0), and each cell is tested alone. One invocation per
// (triangle as voxelize_chunks.comp placed it, chunk of chunkSize voxels of its voxel range inside the clip box),
// dispatched indirectly from voxelize_chunks.comp's counts (kVoxelizeDispatchWords): with largePass 0, invocation x
// is triangle x, left to the other dispatch where it has more than kVoxelizeFirstChunks chunks; with largePass 1, the
// x-th listed triangle. The chunk is z * groups along y + y. Empty voxels keep kNoSeed (reset before: the whole buffer, or voxelize_clear.comp).
// Loops stay short on purpose: lavapipe cut off a single loop of ~100k iterations (lost writes), and an invocation
// that strided through several chunks lost writes too, so each runs at most one chunk.
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = 64) in;
layout(push_constant) uniform Push { VoxelizeParams params; };
layout(std430, binding = kVoxelizeBindingPlaced) readonly buffer Placed { vec4 placed[]; }; // voxel space, 3 each
layout(std430, binding = kVoxelizeBindingSeeds) buffer Seeds { uint seeds[]; };
layout(std430, binding = kVoxelizeBindingDispatch) readonly buffer Dispatch { uint words[]; };
layout(std430, binding = kVoxelizeBindingLarge) readonly buffer Large { uint large[]; };

void main() {
  uint g = gl_GlobalInvocationID.x;
  uint chunk = gl_WorkGroupID.z * gl_NumWorkGroups.y + gl_WorkGroupID.y;
  if (params.largePass != 0u) {
    if (g >= words[kVoxelizeLargeCount]) return;
    g = large[g];
  }
  if (g >= params.triangleCount) return;
  vec3 t0 = placed[3u * g].xyz, t1 = placed[3u * g + 1u].xyz, t2 = placed[3u * g + 2u].xyz;
  ivec3 corner = params.cornerCell.xyz; // lattice cells: the grid's voxel v is cell v + corner
  ivec3 lo = voxelRangeLo(t0, t1, t2, params.clipLo.xyz + corner);
  ivec3 n = voxelRangeHi(t0, t1, t2, params.clipHi.xyz + corner) - lo + ivec3(1);
  int total = (n.x > 0 && n.y > 0 && n.z > 0) ? n.x * n.y * n.z : 0;
  if (chunk * params.chunkSize >= uint(total)) return;
  if (params.largePass == 0u && uint(total) > kVoxelizeFirstChunks * params.chunkSize) return; // listed
  int first = int(chunk * params.chunkSize);
  int last = min(total, first + int(params.chunkSize));
  for (int i = first; i < last; ++i) {
    ivec3 cell = lo + ivec3(i % n.x, (i / n.x) % n.y, i / (n.x * n.y)), v = cell - corner;
    if (voxelOverlaps(cell, t0, t1, t2)) seeds[(v.z * params.dims.y + v.y) * params.dims.x + v.x] = packSeed(v);
  }
}
