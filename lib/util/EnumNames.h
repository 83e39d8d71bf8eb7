#pragma once
/// @file EnumNames.h
/// @brief One table of names per settings enum: parsing, printing and the command line's choices all read
///        it, so a knob has one form (the enum) and one spelling per value.
///
/// An enum opts in with a specialisation next to its declaration:
/// @code
/// template <> struct EnumNames<RefineMode> {
///   static constexpr const char* kSetting = "refinement mode";
///   static constexpr std::pair<const char*, RefineMode> kValues[] = {{"rays", RefineMode::Rays}, ...};
/// };
/// @endcode
#include "util/Error.h"

#include <iterator>
#include <map>
#include <string>
#include <utility>

namespace rtsdf {

/// @brief Specialised per enum: kSetting (what the value sets, for errors) and kValues (name, value) pairs.
template <class E> struct EnumNames;

/// @brief The name of @a value; "?" for a value outside the table.
template <class E, class = decltype(EnumNames<E>::kValues)> const char* toString(E value) {
  for (const auto& [name, v] : EnumNames<E>::kValues)
    if (v == value) return name;
  return "?";
}

/// @brief The names of E's values, "a, b or c".
template <class E> std::string enumChoices() {
  std::string s;
  const std::size_t n = std::size(EnumNames<E>::kValues);
  for (std::size_t i = 0; i < n; ++i)
    s += std::string(i == 0 ? "" : i + 1 == n ? " or " : ", ") + EnumNames<E>::kValues[i].first;
  return s;
}

/// @brief The value named @a text. @throw SettingError naming the setting and the choices otherwise.
template <class E> E parseEnum(const std::string& text) {
  for (const auto& [name, v] : EnumNames<E>::kValues)
    if (text == name) return v;
  throw SettingError(EnumNames<E>::kSetting,
                     "unknown " + std::string(EnumNames<E>::kSetting) + " '" + text + "' (" + enumChoices<E>() + ")");
}

/// @brief Name -> value, for command-line transforms (CLI::CheckedTransformer).
template <class E> std::map<std::string, E> enumMap() {
  std::map<std::string, E> m;
  for (const auto& [name, v] : EnumNames<E>::kValues) m.emplace(name, v);
  return m;
}

} // namespace rtsdf
