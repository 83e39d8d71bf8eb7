#pragma once
/// @file KnobDocs.h
/// @brief A settings struct's knob table (util/Knobs.h) as a Markdown table, for the generated docs/settings.md:
///        one line per row with its setting name, flag, Python keyword, default(s), range and help.
#include "util/Knobs.h"

#include <fmt/format.h>

#include <filesystem>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace rtsdf {
namespace detail {

/// @a text with the characters that would end a Markdown table cell escaped.
inline std::string markdownCell(const std::string& text) {
  std::string s;
  for (char c : text) s += c == '|' ? std::string("\\|") : std::string(1, c);
  return s;
}

/// The value @a v of row @a k as the docs show a default.
template <class K, class T> std::string knobValueText(const K& k, const T& v) {
  if constexpr (std::is_same_v<T, bool>) return v ? "on" : "off";
  else if constexpr (IsNamedEnum<T>::value) return toString(v);
  else if constexpr (kIsNumericKnob<T>) return k.range.isSpecial(double(v)) ? "auto" : fmt::format("{}", v);
  else if constexpr (std::is_same_v<T, Length>) return k.range.isSpecial(v.value) ? "auto" : v.text();
  else if constexpr (std::is_same_v<T, std::filesystem::path>) return v.empty() ? "none" : v.string();
  else return v.empty() ? "none" : std::string(v);
}

/// What row @a k accepts, in words.
template <class K> std::string knobRangeText(const K& k) {
  using T = typename K::Value;
  if constexpr (std::is_same_v<T, bool>) return "on, off";
  else if constexpr (IsNamedEnum<T>::value) return enumChoices<T>();
  else if constexpr (kIsNumericKnob<T> || std::is_same_v<T, Length>) {
    std::string s = k.range.text();
    if (s.empty()) s = std::is_integral_v<T> ? "any integer" : "any number";
    s += k.range.unit;
    if (const std::string note = k.range.note(); !note.empty()) s += "; " + note;
    if constexpr (std::is_same_v<T, Length>) s += std::string("; ") + kLengthSyntax;
    return s;
  } else return "text";
}

} // namespace detail

/// @brief The rows of S's table as a Markdown table. Each of @a defaults (a column title and an instance) gives
///        one column of defaults, read from the instance (the struct's initializers, or a job's own defaults).
/// @param python whether to show each row's Python keyword.
template <class S>
std::string knobMarkdown(const std::vector<std::pair<std::string, S>>& defaults, bool python) {
  std::string head = "| setting | flag |", rule = "| --- | --- |";
  if (python) head += " Python |", rule += " --- |";
  for (const auto& column : defaults) head += fmt::format(" {} |", column.first), rule += " --- |";
  std::string md = head + " range | meaning |\n" + rule + " --- | --- |\n";
  forEachKnob<S>([&](const auto& k) {
    std::string flags = k.flags;
    if (!flags.empty() && flags[0] == '!') flags.erase(0, 1);
    md += fmt::format("| {} | {} |", k.setting, flags.empty() ? "" : fmt::format("`{}`", flags));
    if (python) md += fmt::format(" `{}` |", keywordOf(k));
    for (const auto& column : defaults) md += fmt::format(" {} |", detail::knobValueText(k, column.second.*(k.member)));
    md += fmt::format(" {} | {} |\n", detail::markdownCell(detail::knobRangeText(k)), detail::markdownCell(k.help));
  });
  return md;
}

} // namespace rtsdf
