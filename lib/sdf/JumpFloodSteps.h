#pragma once
/// @file JumpFloodSteps.h
/// @brief The step sequences of the jump-flooding variants (shared by the GPU pass and the CPU reference).
#include "util/EnumNames.h"

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

template <> struct EnumNames<JfaVariant> {
  static constexpr const char* kSetting = "jump-flooding variant";
  static constexpr std::pair<const char*, JfaVariant> kValues[] = {
      {"jfa", JfaVariant::Jfa}, {"1+jfa", JfaVariant::OnePlusJfa}, {"jfa+2", JfaVariant::JfaPlusTwo}};
};

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
