#pragma once
/// @file Log.h
/// @brief Logging set-up: spdlog to stderr, so stdout carries only results.
#include <spdlog/spdlog.h>

namespace rtsdf {

/// @brief Route spdlog's default logger to stderr with a short pattern.
/// @param verbosity -1 quiet (warnings and errors), 0 info, 1 debug, 2 trace.
void initLogging(int verbosity);

} // namespace rtsdf
