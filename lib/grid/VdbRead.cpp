// The defensive .vdb reader: the whole file is walked and bounded before OpenVDB reads it (grid/VdbLayout.h), and
// OpenVDB then reads from memory through a stream that throws at its first read past the end. Without the walk a
// truncated or corrupt file makes OpenVDB allocate what a garbage length says (a 1.2 GB string of spaces,
// gigabytes of nodes) before it notices, or read a chunk into a node's buffer for the length the file states
// (OpenVDB 10's bloscFromStream and unzipFromStream compare it with the buffer's size only afterwards).
#include "grid/VdbIO.h"
#include "grid/VdbLayout.h"

#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Text.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <openvdb/io/Stream.h>

#include <sstream>

namespace rtsdf {
namespace fs = std::filesystem;

openvdb::GridPtrVec readVdbBytes(const std::string& bytes, const std::string& name) {
  openvdb::initialize();
  vdblayout::walkVdb(bytes, name);
  std::istringstream in(bytes);
  // The first read past the end throws, before a garbage count can loop on.
  in.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
  try {
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    openvdb::GridPtrVec grids = *stream.getGrids();
    // A map whose matrix is singular reads without complaint; OpenVDB throws only when the transform is copied,
    // from a constructor whose exception ends the process: ask for each affine map here, where it is an error.
    for (const auto& g : grids)
      if (g) (void)g->transform().baseMap()->getAffineMap();
    return grids;
  } catch (const std::ios_base::failure&) {
    throw Error(fmt::format("{}: not a readable .vdb file: it ends early or is corrupt (a read ran past its end)",
                            name));
  } catch (const std::bad_alloc&) {
    throw Error(fmt::format("{}: not a readable .vdb file: it is corrupt (it asks for more memory than there is)",
                            name));
  } catch (const std::exception& e) {
    throw Error(fmt::format("{}: not a readable .vdb file: {}", name, oneLine(e.what())));
  }
}

openvdb::GridPtrVec readVdb(const fs::path& path) {
  // A grid in memory takes at least its compressed file size: refuse what cannot fit before reading.
  const std::uint64_t available = availableHostMemory();
  const std::uint64_t cap = available ? available / 2 : std::uint64_t(1) << 34;
  return readVdbBytes(readFileBytes(path, ".vdb file", cap), path.string());
}

} // namespace rtsdf
