// Fuzz target: `rtsdf compare` of two files. The first 4 bytes (little-endian, modulo the rest's length) say
// where the first file ends; the two files are written to a private folder and compared as the command does.
// Any bytes must give a comparison or an rtsdf::Error.
#include "jobs/Compare.h"
#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

namespace fs = std::filesystem;

namespace {

fs::path privateFolder() {
  const fs::path dir = fs::temp_directory_path() / ("rtsdf-fuzz-compare-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

void writeBytes(const fs::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 4) return 0;
  static const fs::path dir = privateFolder();
  const std::size_t rest = size - 4;
  const std::uint32_t split = std::uint32_t(data[0]) | std::uint32_t(data[1]) << 8 | std::uint32_t(data[2]) << 16 |
                              std::uint32_t(data[3]) << 24;
  const std::size_t first = rest ? split % (rest + 1) : 0;
  writeBytes(dir / "a.vdb", data + 4, first);
  writeBytes(dir / "b.vdb", data + 4 + first, rest - first);
  try {
    (void)rtsdf::compareFiles(dir / "a.vdb", dir / "b.vdb").report();
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
