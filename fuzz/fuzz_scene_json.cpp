// Fuzz target: the scene JSON loader. Any bytes must give a Scene or an rtsdf::Error, nothing else.
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    // A folder that does not exist: relative mesh paths in the input never reach real files.
    rtsdf::parseScene(std::string(reinterpret_cast<const char*>(data), size), "/nonexistent/fuzz.json");
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
