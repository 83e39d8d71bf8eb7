#include "util/Log.h"

#include <spdlog/sinks/stdout_color_sinks.h>

namespace rtsdf {

void initLogging(int verbosity) {
  auto logger = spdlog::stderr_color_mt("rtsdf");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("%^[%l]%$ %v");
  spdlog::level::level_enum level = spdlog::level::info;
  if (verbosity < 0) level = spdlog::level::warn;
  if (verbosity == 1) level = spdlog::level::debug;
  if (verbosity >= 2) level = spdlog::level::trace;
  spdlog::set_level(level);
}

} // namespace rtsdf
