#pragma once
/// @file CoarseMethod.h
/// @brief How the coarse SDF finds each voxel's nearest seed: the jump-flooding variants (their step sequences are
///        shared by the GPU pass and the CPU copy) or the exact separable transform.
#include "util/EnumNames.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace rtsdf {

/// @brief Nearest-seed transforms of the coarse SDF.
enum class CoarseMethod {
  Jfa,        ///< jump flooding (Rong and Tan 2006): steps N/2, N/4, ..., 1 (N: the largest dim rounded up to a
              ///< power of two)
  OnePlusJfa, ///< a step of 1 first, then JFA: fewer errors for the cost of one step (the paper's choice)
  JfaPlusTwo, ///< JFA, then steps of 2 and 1 again: fewer errors still
  Edt         ///< exact: Meijster's separable Euclidean feature transform, one line per invocation, three passes
              ///< (x, y, z). No error, and cheaper than any JFA variant (docs/results.md): the default.
};

template <> struct EnumNames<CoarseMethod> {
  static constexpr const char* kSetting = "coarse method";
  static constexpr std::pair<const char*, CoarseMethod> kValues[] = {{"edt", CoarseMethod::Edt},
                                                                     {"jfa", CoarseMethod::Jfa},
                                                                     {"1+jfa", CoarseMethod::OnePlusJfa},
                                                                     {"jfa+2", CoarseMethod::JfaPlusTwo}};
};

/// @brief Whether @a method is a jump-flooding variant (has steps).
inline bool isJumpFlooding(CoarseMethod method) { return method != CoarseMethod::Edt; }

/// @brief The step lengths, in order, of a jump-flooding variant for a grid of @a dims voxels (none for Edt).
inline std::vector<int> jumpFloodSteps(const glm::ivec3& dims, CoarseMethod variant) {
  if (!isJumpFlooding(variant)) return {};
  const int n = std::max(dims.x, std::max(dims.y, dims.z));
  int p = 1;
  while (p < n) p *= 2;
  std::vector<int> steps;
  if (variant == CoarseMethod::OnePlusJfa) steps.push_back(1);
  for (int k = p / 2; k >= 1; k /= 2) steps.push_back(k);
  if (steps.empty()) steps.push_back(1); // a single voxel still runs one (no-op) step
  if (variant == CoarseMethod::JfaPlusTwo) { steps.push_back(2); steps.push_back(1); }
  return steps;
}

} // namespace rtsdf
