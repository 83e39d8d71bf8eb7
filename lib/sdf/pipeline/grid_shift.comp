#version 450
#extension GL_GOOGLE_include_directive : require
// GridShiftPass: a dense grid moved by whole cells in one dispatch (a scrolled cascade level's mask state and brick
// tables): each cell reads the cell it lies at after the shift from the old grid's copy, or takes the fill word where
// that cell lies outside. On a GPU it replaces transfer commands that took a copy region and a fill per row along x:
// 16384 of each for a coarse grid of 128^3, about 35 ms a level on an NVIDIA H200 (a CPU device keeps them:
// recordGridShift).
#include "sdf/pipeline/GridShiftParams.h"

layout(local_size_x = RTSDF_GRID_SHIFT_GROUP_X, local_size_y = RTSDF_GRID_SHIFT_GROUP_Y,
       local_size_z = RTSDF_GRID_SHIFT_GROUP_Z) in;
layout(push_constant) uniform Push { GridShiftParams params; };
layout(std430, binding = kGridShiftBindingSource) readonly buffer Source { uint source[]; };
layout(std430, binding = kGridShiftBindingTarget) writeonly buffer Target { uint target[]; };

void main() {
  ivec3 v = ivec3(gl_GlobalInvocationID);
  ivec3 d = params.dims.xyz;
  if (any(greaterThanEqual(v, d))) return;
  int words = params.dims.w;
  int to = ((v.z * d.y + v.y) * d.x + v.x) * words;
  int from = gridShiftSource(v, d, params.shift.xyz);
  for (int k = 0; k < words; ++k) target[to + k] = from < 0 ? params.fillWord : source[from * words + k];
}
