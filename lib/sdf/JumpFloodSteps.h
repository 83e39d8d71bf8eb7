#pragma once
/// @file JumpFloodSteps.h
/// @brief The step sequences of the jump-flooding variants (shared by the GPU pass and the CPU reference).
#include "util/Error.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace rtsdf {

/// @brief Jump-flooding variants (Rong and Tan 2006).
enum class JfaVariant {
  Jfa,        ///< steps N/2, N/4, ..., 1 (N: the largest dim rounded up to a power of two)
  OnePlusJfa, ///< a step of 1 first, then JFA: fewer errors for the cost of one step (the default)
  JfaPlusTwo  ///< JFA, then steps of 2 and 1 again: fewer errors still
};

inline JfaVariant parseJfaVariant(const std::string& s) {
  if (s == "jfa") return JfaVariant::Jfa;
  if (s == "1+jfa") return JfaVariant::OnePlusJfa;
  if (s == "jfa+2") return JfaVariant::JfaPlusTwo;
  throw Error("unknown jump-flooding variant '" + s + "' (jfa, 1+jfa or jfa+2)");
}

inline const char* toString(JfaVariant v) {
  switch (v) {
  case JfaVariant::Jfa: return "jfa";
  case JfaVariant::OnePlusJfa: return "1+jfa";
  case JfaVariant::JfaPlusTwo: return "jfa+2";
  }
  return "?";
}

/// @brief The step lengths, in order, for a grid of @a dims voxels.
inline std::vector<int> jumpFloodSteps(const glm::ivec3& dims, JfaVariant variant) {
  const int n = std::max(dims.x, std::max(dims.y, dims.z));
  int p = 1;
  while (p < n) p *= 2;
  std::vector<int> steps;
  if (variant == JfaVariant::OnePlusJfa) steps.push_back(1);
  for (int k = p / 2; k >= 1; k /= 2) steps.push_back(k);
  if (steps.empty()) steps.push_back(1); // a single voxel still runs one (no-op) step
  if (variant == JfaVariant::JfaPlusTwo) { steps.push_back(2); steps.push_back(1); }
  return steps;
}

} // namespace rtsdf
