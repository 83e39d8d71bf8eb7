#pragma once
/// @file Settings.h
/// @brief Range checks for settings structs: each struct's validate() states its ranges once, and the error
///        names the setting as the library calls it (SettingError), never a command-line flag.
#include "util/Error.h"

#include <fmt/format.h>

#include <cmath>
#include <string>

namespace rtsdf {

/// @brief @a value must lie in [lo, hi] (NaN never does). @a unit, if any, follows the range in the message.
/// @throw SettingError "<setting> <value> is out of range [lo, hi]<unit>".
template <class T> void requireInRange(const char* setting, T value, T lo, T hi, const char* unit = "") {
  if (!(value >= lo && value <= hi))
    throw SettingError(setting, fmt::format("{} {} is out of range [{}, {}]{}", setting, value, lo, hi, unit));
}

/// @brief @a value must be finite. @throw SettingError "<setting> <value> must be finite".
inline void requireFinite(const char* setting, double value) {
  if (!std::isfinite(value)) throw SettingError(setting, fmt::format("{} {} must be finite", setting, value));
}

} // namespace rtsdf
