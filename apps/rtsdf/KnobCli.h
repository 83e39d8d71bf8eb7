#pragma once
/// @file KnobCli.h
/// @brief A settings struct's knob table (util/Knobs.h) bound onto a CLI11 command: one option per row with a
///        flag, its help, its range check in plain numbers and its default; and the flag of each setting, for
///        error messages that name a setting (SettingError::setting()).
#include "util/EnumNames.h"
#include "util/Knobs.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cerrno>
#include <cstdlib>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <type_traits>

namespace rtsdf::app {

/// @brief Setting name (as the library's errors give it) -> the flag that sets it ("band" -> "--band").
class SettingFlags {
public:
  void add(const std::string& setting, const std::string& flag) {
    if (flag.empty()) return;
    mFlags.emplace(setting, flag);
    mSettings.emplace(flag, setting);
  }
  /// @brief The flag of @a setting, or the setting itself when no flag sets it.
  std::string flagOf(const std::string& setting) const {
    const auto it = mFlags.find(setting);
    return it == mFlags.end() ? setting : it->second;
  }
  /// @brief The setting @a flag ("--band") sets, or "" when it sets none (an output, a file format).
  std::string settingOf(const std::string& flag) const {
    const auto it = mSettings.find(flag);
    return it == mSettings.end() ? std::string() : it->second;
  }

private:
  std::map<std::string, std::string> mFlags, mSettings;
};

namespace detail {

/// The number in @a text, or nothing when it is not one (trailing characters included).
inline std::optional<double> number(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE) return std::nullopt;
  return v;
}

} // namespace detail

/// @brief A numeric check whose message says the range in plain numbers (CLI11's own prints the largest double
///        in full): "5000 is out of range: it must be in [1, 1024]".
inline CLI::Validator numberCheck(std::function<bool(double)> ok, const std::string& range) {
  return CLI::Validator(
      [ok = std::move(ok), range](std::string& text) -> std::string {
        const std::optional<double> v = detail::number(text);
        if (!v) return "'" + text + "' is not a number (or is beyond the range of a double)";
        if (!ok(*v)) return text + " is out of range: it must be " + range;
        return {};
      },
      range, range);
}
/// @brief The check of @a r's range proper: the special value ("< 0: automatic") is what leaving the flag out
///        gives, so the command line refuses it.
inline CLI::Validator rangeCheck(const KnobRange& r) {
  return numberCheck([r](double v) { return r.contains(v); }, r.text());
}
inline CLI::Validator inRange(double lo, double hi) { return rangeCheck(KnobRange::closed(lo, hi)); }

/// @brief The check of a length option (util/Length.h): "0.02" or "3vox", its number in @a r.
inline CLI::Validator lengthCheck(const KnobRange& r) {
  return CLI::Validator(
      [r](std::string& text) -> std::string {
        const std::optional<Length> l = Length::parse(text);
        if (!l)
          return "'" + text + "' is not a length: not a number (or beyond the range of a double) nor a number of "
                 "voxels (" + kLengthSyntax + ")";
        if (!r.contains(l->value)) return text + " is out of range: it must be " + r.text();
        return {};
      },
      "LENGTH", "length");
}

/// @brief An enum option: its choices come from the enum's name table (names only), its default is printed by name.
template <class E> CLI::Option* addEnum(CLI::App* cmd, const std::string& flag, E& value, const std::string& help) {
  const CLI::Validator byName(
      [](std::string& text) -> std::string {
        for (const auto& [name, v] : EnumNames<E>::kValues)
          if (text == name) {
            text = std::to_string(static_cast<int>(v));
            return {};
          }
        return "'" + text + "' is not one of " + enumChoices<E>();
      },
      "", "enum name");
  std::string names;
  for (const auto& entry : EnumNames<E>::kValues) names += std::string(names.empty() ? "" : "|") + entry.first;
  return cmd->add_option(flag, value, help)
      ->transform(byName)
      ->type_name("{" + names + "}")
      ->default_str(toString(value));
}

/// @brief Row @a k bound onto @a cmd for @a value (nothing when the row has no flag); its flag noted in @a flags.
template <class K, class T> void bindKnob(CLI::App* cmd, const K& k, T& value, SettingFlags& flags) {
  if (!*k.flags) return;
  flags.add(k.setting, longFlag(k.flags));
  const KnobRange& r = k.range;
  std::string help = k.help;
  if (r.special != KnobRange::Auto::None) help += fmt::format(" (default: {})", r.meaning);
  else if (*r.meaning) help += fmt::format(" ({})", r.meaning);
  if constexpr (std::is_same_v<T, bool>) {
    // A flag that turns a knob off ("!--no-taa") sets false; bound as a callback so that the help does not print
    // CLI11's default flag value ("--no-taa{false}").
    if (*k.flags == '!') cmd->add_flag_callback(k.flags + 1, [&value] { value = false; }, help);
    else cmd->add_flag(k.flags, value, help);
  } else if constexpr (std::is_same_v<T, Length>) {
    CLI::Option* o = cmd->add_option_function<std::string>(
        k.flags, [&value](const std::string& text) { value = *Length::parse(text); },
        help + " (" + kLengthSyntax + ")");
    o->check(lengthCheck(r))->type_name("LENGTH");
    if (!r.isSpecial(value.value)) o->default_str(value.text());
  } else if constexpr (IsNamedEnum<T>::value) {
    addEnum(cmd, k.flags, value, help);
  } else {
    CLI::Option* o = cmd->add_option(k.flags, value, help);
    if constexpr (kIsNumericKnob<T>) {
      // Finiteness alone is left to validate(): the command line checks bounds.
      if (r.kind != KnobRange::Kind::Any && r.kind != KnobRange::Kind::Finite) o->check(rangeCheck(r));
      if (!r.isSpecial(double(value))) o->capture_default_str();
    }
  }
}

/// @brief Whether the flag of row @a k was given on @a cmd's command line.
template <class K> bool givenOn(const CLI::App* cmd, const K& k) {
  const std::string flag = longFlag(k.flags);
  if (flag.empty()) return false;
  const CLI::Option* o = cmd->get_option_no_throw(flag);
  return o && o->count() > 0;
}

/// @brief Every member of @a s whose flag @a cmd was not given, from @a preset (a named preset under the flags).
template <class S> void applyPreset(const CLI::App* cmd, S& s, const S& preset) {
  forEachKnob<S>([&](const auto& k) {
    if (*k.flags && !givenOn(cmd, k)) s.*(k.member) = preset.*(k.member);
  });
}

/// @brief Every row of S's table that has a flag, bound onto @a cmd for the members of @a s.
template <class S> void bindKnobs(CLI::App* cmd, S& s, SettingFlags& flags) {
  forEachKnob<S>([&](const auto& k) { bindKnob(cmd, k, s.*(k.member), flags); });
}

} // namespace rtsdf::app
