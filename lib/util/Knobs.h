#pragma once
/// @file Knobs.h
/// @brief One table per settings struct: each knob's setting name (as errors name it), member, range, flags,
///        Python keyword and help, read by the struct's validate(), the command line's bindings, the Python
///        module's keywords and the generated docs/settings.md. A knob is described once, as one row; its default
///        stays the struct's own member initializer.
///
/// A struct opts in with a specialisation next to its declaration:
/// @code
/// template <> struct KnobTable<PipelineSettings> {
///   static constexpr auto kKnobs = std::make_tuple(
///       knob("band", &PipelineSettings::band, "-d,--band", KnobRange::atLeast(0), "Narrow-band half-width [d]"),
///       enumKnob(&PipelineSettings::mode, "--refine", "rays: the paper's random rays; closest: ..."));
/// };
/// @endcode
/// and a front end walks it with forEachKnob<S>(visitor), the visitor called with each row (a Knob<S, T>).
#include "util/EnumNames.h"
#include "util/Error.h"
#include "util/Length.h"

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>

namespace rtsdf {

/// @brief The values a numeric knob accepts, with one special value ("automatic") where the struct has one.
struct KnobRange {
  enum class Kind {
    Any,      ///< every value (enums, flags, text)
    Finite,   ///< every finite value
    Closed,   ///< [lo, hi]
    HalfOpen, ///< (lo, hi]
    AtLeast,  ///< finite and >= lo
    Above     ///< finite and > lo
  };
  /// A value outside the range that means "choose for me" (the member's default), e.g. a padding < 0.
  enum class Auto { None, Negative, NaN };

  Kind kind = Kind::Any;
  double lo = 0.0, hi = 0.0;
  const char* unit = "";      ///< follows the range in messages and docs (" fine voxels")
  Auto special = Auto::None;
  const char* meaning = "";   ///< what the special value (or a noted value within the range) means

  static constexpr KnobRange any() { return {}; }
  static constexpr KnobRange finite() { return {Kind::Finite}; }
  static constexpr KnobRange closed(double lo, double hi) { return {Kind::Closed, lo, hi}; }
  static constexpr KnobRange halfOpen(double lo, double hi) { return {Kind::HalfOpen, lo, hi}; }
  static constexpr KnobRange atLeast(double lo) { return {Kind::AtLeast, lo}; }
  static constexpr KnobRange above(double lo) { return {Kind::Above, lo}; }

  /// @brief The range with @a u after its numbers (" fine voxels").
  constexpr KnobRange in(const char* u) const { return {kind, lo, hi, u, special, meaning}; }
  /// @brief The range, or any finite value < 0 meaning @a m ("by the refinement mode").
  constexpr KnobRange orNegative(const char* m) const { return {kind, lo, hi, unit, Auto::Negative, m}; }
  /// @brief The range, or NaN meaning @a m.
  constexpr KnobRange orNaN(const char* m) const { return {kind, lo, hi, unit, Auto::NaN, m}; }
  /// @brief The range with a note on a value within it ("0: sized by the first frame's band").
  constexpr KnobRange noting(const char* m) const { return {kind, lo, hi, unit, special, m}; }

  /// @brief Whether @a v is the special value (automatic).
  bool isSpecial(double v) const {
    return (special == Auto::Negative && std::isfinite(v) && v < 0.0) || (special == Auto::NaN && std::isnan(v));
  }
  /// @brief Whether @a v lies in the range proper (the special value aside).
  bool contains(double v) const {
    switch (kind) {
    case Kind::Any: return true;
    case Kind::Finite: return std::isfinite(v);
    case Kind::Closed: return v >= lo && v <= hi;
    case Kind::HalfOpen: return v > lo && v <= hi;
    case Kind::AtLeast: return std::isfinite(v) && v >= lo;
    case Kind::Above: return std::isfinite(v) && v > lo;
    }
    return false;
  }
  bool accepts(double v) const { return isSpecial(v) || contains(v); }
  /// @brief The range proper in words: "in [1, 1024]", "in (0, 1]", ">= 0", "> 0", "finite" or "".
  std::string text() const {
    switch (kind) {
    case Kind::Any: return {};
    case Kind::Finite: return "finite";
    case Kind::Closed: return fmt::format("in [{}, {}]", lo, hi);
    case Kind::HalfOpen: return fmt::format("in ({}, {}]", lo, hi);
    case Kind::AtLeast: return fmt::format(">= {}", lo);
    case Kind::Above: return fmt::format("> {}", lo);
    }
    return {};
  }
  /// @brief The special value or the note in words, "< 0: by the refinement mode"; empty when none.
  std::string note() const {
    if (!*meaning) return {};
    return special == Auto::Negative ? fmt::format("< 0: {}", meaning)
           : special == Auto::NaN   ? fmt::format("NaN: {}", meaning)
                                    : std::string(meaning);
  }
  /// @throw SettingError naming @a setting when @a value is outside the range and not the special value:
  ///        "<setting> <value> is out of range [lo, hi]<unit>" (or "must be finite and >= lo", ...), followed by
  ///        the special value's meaning, "(or < 0: by the refinement mode)".
  template <class T> void check(const char* setting, T value) const {
    if (accepts(double(value))) return;
    std::string m;
    switch (kind) {
    case Kind::Closed:
    case Kind::HalfOpen: m = fmt::format("{} {} is out of range {}{}", setting, value, text().substr(3), unit); break;
    case Kind::Finite: m = fmt::format("{} {} must be finite", setting, value); break;
    default: m = fmt::format("{} {} must be finite and {}{}", setting, value, text(), unit); break;
    }
    if (*meaning) m += fmt::format(" ({}{})", special == Auto::None ? "" : "or ", note());
    throw SettingError(setting, m);
  }
};

/// @brief Whether knobs of type T hold an enum with a name table (EnumNames<T>).
template <class T, class = void> struct IsNamedEnum : std::false_type {};
template <class T> struct IsNamedEnum<T, std::void_t<decltype(EnumNames<T>::kValues)>> : std::true_type {};
/// @brief How a length knob (util/Length.h) is written, once for every such row (docs/settings.md, --help).
inline constexpr const char* kLengthSyntax = "a length: 0.02 (scene units) or 3vox (voxels of the output grid)";

/// @brief Whether knobs of type T are numbers with a range (not a flag, an enum or text).
template <class T> constexpr bool kIsNumericKnob = std::is_arithmetic_v<T> && !std::is_same_v<T, bool>;

/// @brief One row of a KnobTable: the knob @a member of S.
template <class S, class T> struct Knob {
  using Struct = S;
  using Value = T;
  const char* setting;      ///< the name errors give it (SettingError::setting()): "band", "coarse resolution"
  T S::*member;
  /// Command-line names as CLI11 takes them ("-d,--band"; "!--no-jitter": a flag that sets false); "": none.
  const char* flags;
  KnobRange range;
  const char* help;         ///< one plain line, the paper's symbol in brackets where it has one ("[d]")
  const char* keyword = ""; ///< the Python keyword; "": the long flag (else the setting) in snake case
};

/// @brief A numeric, on/off or text knob.
template <class S, class T>
constexpr Knob<S, T> knob(const char* setting, T S::*member, const char* flags, KnobRange range, const char* help,
                          const char* keyword = "") {
  return {setting, member, flags, range, help, keyword};
}
/// @brief An on/off knob (a flag on the command line).
template <class S>
constexpr Knob<S, bool> flagKnob(const char* setting, bool S::*member, const char* flags, const char* help,
                                 const char* keyword = "") {
  return {setting, member, flags, KnobRange::any(), help, keyword};
}
/// @brief An enum knob: its setting name and choices come from its name table (EnumNames<E>).
template <class S, class E>
constexpr Knob<S, E> enumKnob(E S::*member, const char* flags, const char* help, const char* keyword = "") {
  static_assert(IsNamedEnum<E>::value, "an enum knob needs EnumNames<E>");
  return {EnumNames<E>::kSetting, member, flags, KnobRange::any(), help, keyword};
}

/// @brief Specialised per settings struct: `static constexpr auto kKnobs = std::make_tuple(knob(...), ...)`.
template <class S> struct KnobTable;

/// @brief Call @a visit with every row of S's table, in order.
template <class S, class F> void forEachKnob(F&& visit) {
  std::apply([&](const auto&... row) { (visit(row), ...); }, KnobTable<S>::kKnobs);
}

/// @brief Check every numeric knob of @a s against its row's range (SettingError naming the first one out of it).
///        Rules between knobs (fine >= coarse) stay in the struct's validate(), after this.
template <class S> void validateKnobs(const S& s) {
  forEachKnob<S>([&](const auto& k) {
    using T = typename std::decay_t<decltype(k)>::Value;
    if constexpr (kIsNumericKnob<T>) k.range.check(k.setting, s.*(k.member));
    else if constexpr (std::is_same_v<T, Length>) k.range.check(k.setting, (s.*(k.member)).value);
  });
}

/// @brief The first long name in @a flags ("-d,--band" -> "--band", "!--no-jitter" -> "--no-jitter"); "" if none.
inline std::string longFlag(const char* flags) {
  const std::string f = flags;
  for (std::size_t at = 0; at < f.size();) {
    std::size_t end = f.find(',', at);
    if (end == std::string::npos) end = f.size();
    std::string name = f.substr(at, end - at);
    if (!name.empty() && name[0] == '!') name.erase(0, 1);
    if (name.rfind("--", 0) == 0) return name;
    at = end + 1;
  }
  return {};
}

/// @brief The Python keyword of row @a k: its own, else its long flag, else its setting, in snake case.
template <class K> std::string keywordOf(const K& k) {
  std::string w = *k.keyword ? k.keyword : longFlag(k.flags).empty() ? k.setting : longFlag(k.flags).substr(2);
  for (char& c : w)
    if (c == '-' || c == ' ') c = '_';
  return w;
}

/// @brief Call @a visit(row, s.*row.member) for the row of S whose Python keyword is @a keyword.
/// @return whether a row has it.
template <class S, class F> bool visitKnobByKeyword(S& s, const std::string& keyword, F&& visit) {
  bool found = false;
  forEachKnob<S>([&](const auto& k) {
    if (!found && keywordOf(k) == keyword) {
      found = true;
      visit(k, s.*(k.member));
    }
  });
  return found;
}

} // namespace rtsdf
