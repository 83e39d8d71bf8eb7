#pragma once
// Shared by the cascade tests (test_cascade_set.cpp, test_cascade_view.cpp): small levels of the default room and
// the difference of two fields.
#include "sdf/PipelineSettings.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace rtsdf::test {

/// Three levels of coarse 16 / fine 32 in closest mode without sign rays; level 0 is 0.6 wide, level 2 spans the room.
inline PipelineSettings threeLevels() {
  PipelineSettings s;
  s.coarseRes = 16;
  s.fineRes = 32;
  s.mode = RefineMode::Closest;
  s.rays = 0;
  s.band = 0.05;
  s.cascades = 3;
  s.cascadeExtent = 0.6;
  return s;
}

/// The largest |a - b| over the voxels (infinite when the fields differ in size).
inline double largestDifference(const std::vector<float>& a, const std::vector<float>& b) {
  if (a.size() != b.size()) return HUGE_VAL;
  double worst = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double(std::fabs(a[i] - b[i])));
  return worst;
}

} // namespace rtsdf::test
