#pragma once
/// @file Error.h
/// @brief The one exception type rtsdf throws for bad input, bad settings and failed I/O.
#include <stdexcept>
#include <string>

namespace rtsdf {

/// @brief An error a user can act on: the message names the file or setting and the problem.
class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

} // namespace rtsdf
