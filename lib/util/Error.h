#pragma once
/// @file Error.h
/// @brief The exceptions rtsdf throws for bad input, bad settings, failed I/O and interrupted work.
#include <stdexcept>
#include <string>

namespace rtsdf {

/// @brief An error a user can act on: the message names the file or setting and the problem.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// @brief A setting out of its range. The message names the setting as the library calls it ("band must be
///        finite and >= 0, got -1"); a front end maps setting() to its own spelling (a flag, a keyword).
class SettingError : public Error {
public:
  SettingError(std::string setting, const std::string& message) : Error(message), mSetting(std::move(setting)) {}
  const std::string& setting() const { return mSetting; }

private:
  std::string mSetting;
};

/// @brief Long work stopped because its caller asked (JobControl::stopRequested): not a failure of the input.
class Interrupted : public Error {
public:
  Interrupted() : Error("interrupted") {}
};

} // namespace rtsdf
