#version 450
#extension GL_GOOGLE_include_directive : require
// ExactEdtPass, one axis: the exact nearest seed of every voxel of one grid line (Meijster, Roerdink and Hesselink
// 2000, carrying the seeds: a feature transform). Each voxel's input is the nearest seed on its own line of the
// previous axes (the x pass starts from the seeds), i.e. a parabola rooted at its position with height g = the
// squared distance to that seed; the line's lower envelope of those parabolas gives every voxel its nearest seed.
// Integer arithmetic only; ties go to the smaller position on the line, so over three axes to the smaller packed
// seed, the same rule as exactEdtNearestCpu() (sdf/coarse/CoarseCpu.cpp) and jump flooding.
// The envelope's stack lives in the line's own output slots (slot k <= the position being written), so there is
// no private array; every loop runs at most 2n iterations (n <= 1024). A dispatch runs the lines (a, b) of a box:
// all of an axis in a full build; in a build over what changed, the z lines of the columns of blocks a change can
// reach (the CoarseRegion's listed columns, RTSDF_COARSE_BLOCK^2 lines each).
#include "sdf/coarse/CoarseParams.h"

layout(local_size_x = RTSDF_EDT_GROUP_X) in;
layout(push_constant) uniform Push { ExactEdtParams params; };
layout(std430, binding = kExactEdtBindingSrc) readonly buffer Src { uint src[]; };
layout(std430, binding = kExactEdtBindingDst) buffer Dst { uint dst[]; };
layout(std430, binding = kExactEdtBindingLists) readonly buffer Lists { uvec4 counts; uint lists[]; };

ivec3 gDims;
ivec3 gStart;
ivec3 gStep;
int gBase;
int gStride;

// Height of the parabola at line position s (its input seed exists).
int heightAt(int s) { return distance2(gStart + s * gStep, unpackSeed(src[gBase + s * gStride])); }

// The line (a, b) this invocation runs, or false where it runs none.
bool lineOf(int axis, out int a, out int b) {
  if (params.fromRegion != 0) { // invocation i: line i % 16 of listed column i / 16 (z lines)
    const uint perColumn = uint(RTSDF_COARSE_BLOCK * RTSDF_COARSE_BLOCK);
    uint i = gl_GlobalInvocationID.x;
    if (i >= counts.y * perColumn) return false;
    uint column = lists[coarseRegionColumnsAt(gDims) - kCoarseRegionCountWords + i / perColumn];
    uint line = i % perColumn;
    int blocksX = coarseBlockDims(gDims).x;
    a = int(column) % blocksX * RTSDF_COARSE_BLOCK + int(line) % RTSDF_COARSE_BLOCK;
    b = int(column) / blocksX * RTSDF_COARSE_BLOCK + int(line) / RTSDF_COARSE_BLOCK;
    return a < gDims.x && b < gDims.y;
  }
  ivec4 lines = params.lines;
  a = lines.x + int(gl_GlobalInvocationID.x);
  b = lines.y + int(gl_GlobalInvocationID.y);
  return a < min(lines.z, axis == 0 ? gDims.y : gDims.x) && b < min(lines.w, axis == 2 ? gDims.y : gDims.z);
}

void main() {
  gDims = params.dims.xyz;
  int axis = params.axis;
  int a, b;
  if (!lineOf(axis, a, b)) return;
  gStart = edtLineStart(axis, a, b);
  gStep = ivec3(axis == 0 ? 1 : 0, axis == 1 ? 1 : 0, axis == 2 ? 1 : 0);
  gBase = (gStart.z * gDims.y + gStart.y) * gDims.x + gStart.x;
  gStride = edtLineStride(gDims, axis);
  int n = gDims[axis];

  // Forward: the envelope as a stack of (seed position s, first owned position t); its top also in registers.
  int q = -1, topS = 0, topT = 0, topG = 0;
  for (int u = 0; u < n; ++u) {
    uint f = src[gBase + u * gStride];
    if (f == kNoSeed) continue;
    int gu = distance2(gStart + u * gStep, unpackSeed(f));
    while (q >= 0 && (topT - topS) * (topT - topS) + topG > (topT - u) * (topT - u) + gu) {
      if (--q < 0) break;
      uint e = dst[gBase + q * gStride];
      topS = edtEntrySeed(e);
      topT = edtEntryStart(e);
      topG = heightAt(topS);
    }
    int w = 0;
    if (q < 0) {
      q = 0;
    } else {
      w = 1 + edtSeparation(topS, topG, u, gu);
      if (w >= n) continue; // u is never the nearest on this line
      ++q;
    }
    topS = u; topT = w; topG = gu;
    dst[gBase + q * gStride] = packEdtEntry(u, w);
  }
  // Backward: every position takes the seed of the parabola that owns it.
  for (int u = n - 1; u >= 0; --u) {
    dst[gBase + u * gStride] = q >= 0 ? src[gBase + topS * gStride] : kNoSeed;
    if (q >= 0 && u == topT && --q >= 0) {
      uint e = dst[gBase + q * gStride];
      topS = edtEntrySeed(e);
      topT = edtEntryStart(e);
    }
  }
}
