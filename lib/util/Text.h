#pragma once
/// @file Text.h
/// @brief Small text helpers shared by the readers and error messages.
#include <cstddef>
#include <string>

namespace rtsdf {

/// @brief @a s with ASCII letters in lower case (file extensions, device names).
std::string toLower(std::string s);

/// @brief An error message from a third-party reader cut down to one short line: control characters become
///        spaces, runs of spaces collapse, and text past @a maxChars is replaced by "...".
std::string oneLine(const std::string& message, std::size_t maxChars = 200);

/// @brief Raw bytes from a file for a message: printable ASCII as it is, any other byte as \xNN, past @a maxBytes
///        cut to "...". Unlike oneLine, the result is valid UTF-8 whatever the bytes (Python decodes messages).
std::string escapedBytes(const std::string& bytes, std::size_t maxBytes);

} // namespace rtsdf
