#pragma once
/// @file PassTimes.h
/// @brief Milliseconds per named pass, in recording order: what the GPU profiler reads back and what every
///        frame, bake and benchmark reports.
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief (pass name, milliseconds) in recording order; a pass recorded several times appears several times.
using PassTimes = std::vector<std::pair<std::string, double>>;

/// @brief Sum of the milliseconds of every entry named @a pass (0 when there is none).
inline double passTotal(const PassTimes& times, const std::string& pass) {
  double t = 0.0;
  for (const auto& [name, ms] : times)
    if (name == pass) t += ms;
  return t;
}

/// @brief Sum over every pass.
inline double passSum(const PassTimes& times) {
  double t = 0.0;
  for (const auto& entry : times) t += entry.second;
  return t;
}

} // namespace rtsdf
