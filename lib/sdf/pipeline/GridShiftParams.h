// Shared by C++ and GLSL: grid_shift.comp (GridShiftPass) moves a dense grid buffer by whole cells in one dispatch,
// the cells that entered set to a fill word. gridShiftSource is the shader's rule; the tests check the pass against
// gridShiftPlan's copies and fills applied on the host (applyGridShift), written independently of it.
#ifndef RTSDF_SDF_PIPELINE_GRIDSHIFTPARAMS_H
#define RTSDF_SDF_PIPELINE_GRIDSHIFTPARAMS_H
#include "gpu/shared/Common.h"

RTSDF_SHARED_BEGIN

/// Bindings of grid_shift.comp.
const uint kGridShiftBindingSource = 0u; // the grid as it was (a copy in a scratch buffer)
const uint kGridShiftBindingTarget = 1u; // the grid shifted
const uint kGridShiftBindingCount = 2u;

/// Work-group shape of grid_shift.comp (one invocation per cell).
#define RTSDF_GRID_SHIFT_GROUP_X 8
#define RTSDF_GRID_SHIFT_GROUP_Y 8
#define RTSDF_GRID_SHIFT_GROUP_Z 2

/// Push constants of grid_shift.comp.
struct GridShiftParams {
  ivec4 dims;    // cells per axis (x fastest); w: 32-bit words per cell
  ivec4 shift;   // cell v afterwards holds what cell v + shift held; w: unused
  uint fillWord; // every word of a cell that entered
  uint pad0, pad1, pad2;
};

/// The linear index of the cell that cell @a v reads, or -1 where v + shift lies outside the grid (v entered).
RTSDF_FN int gridShiftSource(ivec3 v, ivec3 dims, ivec3 shift) {
  ivec3 s = v + shift;
  if (s.x < 0 || s.y < 0 || s.z < 0 || s.x >= dims.x || s.y >= dims.y || s.z >= dims.z) return -1;
  return (s.z * dims.y + s.y) * dims.x + s.x;
}

RTSDF_SHARED_END

#endif
