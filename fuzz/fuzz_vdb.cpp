// Fuzz target: the defensive .vdb reader used by `compare`. Any bytes must give grids or an rtsdf::Error.
#include "grid/VdbIO.h"
#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const openvdb::GridPtrVec grids =
        rtsdf::readVdbBytes(std::string(reinterpret_cast<const char*>(data), size), "fuzz.vdb");
    for (const auto& g : grids) (void)g->activeVoxelCount(); // walk the tree that was read
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
