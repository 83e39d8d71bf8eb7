#pragma once
/// @file Length.h
/// @brief A length setting given in scene units or in voxels of the grid it applies to, so that one default
///        fits a scene in metres and the same scene in millimetres. Written "0.02" (scene units) or "3vox".
#include "util/Error.h"

#include <fmt/format.h>

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

namespace rtsdf {

/// @brief A length in scene units or in voxels. A job resolves it against its grid (sceneUnits()) before the
///        length is used; reading an unresolved voxel length as a number is a programming error (logic_error).
struct Length {
  enum class Unit { Scene, Voxels };
  double value = 0.0;
  Unit unit = Unit::Scene;

  constexpr Length() = default;
  /// @brief A number is a length in scene units (so `settings.band = 0.1` keeps its meaning).
  constexpr Length(double sceneUnits) : value(sceneUnits) {} // NOLINT: implicit on purpose
  /// @brief @a n voxels of the grid the length applies to.
  static constexpr Length voxels(double n) {
    Length l(n);
    l.unit = Unit::Voxels;
    return l;
  }

  constexpr bool inVoxels() const { return unit == Unit::Voxels; }
  /// @brief The length in scene units on a grid of voxels @a voxelSize long.
  double sceneUnits(double voxelSize) const { return inVoxels() ? value * voxelSize : value; }
  /// @brief The length in scene units once resolved.
  /// @throw std::logic_error when it is still in voxels (a job must resolve it against its grid first).
  operator double() const { // NOLINT: implicit on purpose: resolved lengths read as numbers
    if (inVoxels())
      throw std::logic_error(fmt::format("a length of {} voxels was read before its grid resolved it", value));
    return value;
  }
  /// @brief "0.02" or "3vox", as parse() reads it.
  std::string text() const { return inVoxels() ? fmt::format("{}vox", value) : fmt::format("{}", value); }

  /// @brief "0.02", "1e-3" (scene units) or "3vox" / "3voxels" / "3 voxels"; nothing when @a text is neither.
  static std::optional<Length> parse(const std::string& text) {
    std::string number = text;
    bool inVoxels = false;
    for (const char* suffix : {"voxels", "voxel", "vox"}) {
      const std::string s = suffix;
      if (number.size() > s.size() && number.compare(number.size() - s.size(), s.size(), s) == 0) {
        number.erase(number.size() - s.size());
        while (!number.empty() && number.back() == ' ') number.pop_back();
        inVoxels = true;
        break;
      }
    }
    if (number.empty()) return std::nullopt;
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(number, &used);
    } catch (const std::exception&) {
      return std::nullopt;
    }
    if (used != number.size()) return std::nullopt;
    return inVoxels ? Length::voxels(v) : Length(v);
  }
};

} // namespace rtsdf

template <> struct fmt::formatter<rtsdf::Length> : fmt::formatter<std::string> {
  template <class Ctx> auto format(const rtsdf::Length& l, Ctx& ctx) const {
    return fmt::formatter<std::string>::format(l.text(), ctx);
  }
};
