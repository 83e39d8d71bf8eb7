#include "util/Memory.h"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace rtsdf {
namespace {

std::uint64_t statusField(const char* key) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string prefix = std::string(key) + ":";
  while (std::getline(in, line)) {
    if (line.rfind(prefix, 0) != 0) continue;
    std::istringstream s(line.substr(prefix.size()));
    std::uint64_t kib = 0;
    s >> kib;
    return kib * 1024u;
  }
  return 0;
}

} // namespace

std::uint64_t physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES);
  const long size = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && size > 0 ? std::uint64_t(pages) * std::uint64_t(size) : 0;
}

std::uint64_t availableHostMemory() {
  std::ifstream in("/proc/meminfo");
  std::string key, unit;
  std::uint64_t value = 0;
  while (in >> key >> value) {
    std::getline(in, unit);
    if (key == "MemAvailable:") return value * 1024;
  }
  return physicalMemoryBytes();
}

std::uint64_t peakResidentMemory() { return statusField("VmHWM"); }

std::uint64_t currentResidentMemory() { return statusField("VmRSS"); }

bool resetPeakResidentMemory() {
  // "5" resets the peak RSS to the current RSS (Linux >= 4.0, Documentation/filesystems/proc.rst).
  std::ofstream out("/proc/self/clear_refs");
  if (!out) return false;
  out << "5";
  out.flush();
  return bool(out);
}

} // namespace rtsdf
