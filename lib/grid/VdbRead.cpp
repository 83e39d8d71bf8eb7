// The defensive .vdb reader: the file's layout is walked and bounded before OpenVDB reads it, and OpenVDB then
// reads from memory through a stream that throws at its first read past the end. Without the walk a truncated
// or corrupt file makes OpenVDB allocate what a garbage length says (a 1.2 GB string of spaces, gigabytes of
// nodes) before it notices.
#include "grid/VdbIO.h"

#include "util/Error.h"
#include "util/InputFile.h"
#include "util/Text.h"
#include "util/Memory.h"

#include <fmt/format.h>
#include <openvdb/io/Stream.h>

#include <algorithm>
#include <cstring>
#include <sstream>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

/// Bounded little-endian reads over the file's bytes; every failure names the file and the byte offset.
class LayoutWalker {
public:
  LayoutWalker(const std::string& bytes, const std::string& name) : mBytes(bytes), mName(name) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw Error(fmt::format("{}: not a readable .vdb file: {} (at byte {} of {})", mName, what, mPos, mBytes.size()));
  }
  template <class T> T read(const char* what, std::uint64_t end) {
    if (mPos + sizeof(T) > end) fail(fmt::format("the file ends inside the {}", what));
    T v;
    std::memcpy(&v, mBytes.data() + mPos, sizeof(T));
    mPos += sizeof(T);
    return v;
  }
  std::string string(const char* what, std::uint64_t end) {
    const std::uint32_t n = read<std::uint32_t>(what, end);
    skip(n, what, end);
    return oneLine(mBytes.substr(mPos - n, std::min<std::uint32_t>(n, 200)));
  }
  void skip(std::uint64_t n, const char* what, std::uint64_t end) {
    if (n > end - mPos) fail(fmt::format("a {} of {} bytes runs past the end", what, n));
    mPos += n;
  }
  /// A metadata table: its count, then (name, type, byte size, value) per entry.
  void metadata(const char* what, std::uint64_t end) {
    const std::uint32_t count = read<std::uint32_t>(what, end);
    if (count > (end - mPos) / 12) fail(fmt::format("{} entries of {} cannot fit", count, what));
    for (std::uint32_t i = 0; i < count; ++i) {
      string("metadata name", end);
      string("metadata type", end);
      skip(read<std::uint32_t>("metadata size", end), "metadata value", end);
    }
  }
  std::uint64_t pos() const { return mPos; }
  void seek(std::uint64_t p) { mPos = p; }
  std::uint64_t size() const { return mBytes.size(); }

private:
  const std::string& mBytes;
  const std::string& mName;
  std::uint64_t mPos = 0;
};

/// Header: magic, format version (222 and newer: OpenVDB 3 on), library version, offsets flag, UUID.
bool walkHeader(LayoutWalker& w) {
  const std::uint64_t end = w.size();
  if (w.read<std::int64_t>("magic number", end) != 0x56444220) w.fail("no VDB magic number at its start");
  const std::uint32_t version = w.read<std::uint32_t>("format version", end);
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION || version > openvdb::OPENVDB_FILE_VERSION)
    w.fail(fmt::format("file format version {} (this reader takes {} to {})", version,
                       int(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION), openvdb::OPENVDB_FILE_VERSION));
  w.read<std::uint32_t>("library version", end);
  w.read<std::uint32_t>("library version", end);
  const bool offsets = w.read<char>("grid offsets flag", end) != 0;
  w.skip(36, "UUID", end);
  w.metadata("file metadata", end);
  return offsets;
}

/// One grid: its descriptor, then its compression, metadata and transform type. With offsets these must lie
/// before its block data and the grid must end inside the file; without (a file written to a stream) only the
/// first grid can be walked, up to the end of the file.
void walkGrid(LayoutWalker& w, int index, bool offsets) {
  const std::uint64_t end = w.size();
  const std::string name = w.string("grid name", end);
  const std::string type = w.string("grid type", end);
  w.string("instance parent name", end);
  const auto gridPos = w.read<std::int64_t>("grid offsets", end);
  const auto blockPos = w.read<std::int64_t>("grid offsets", end);
  const auto endPos = w.read<std::int64_t>("grid offsets", end);
  std::uint64_t headerEnd = end;
  if (offsets) {
    const std::string grid = fmt::format("grid {} ('{}' of type {})", index, name, type);
    if (endPos > std::int64_t(end)) w.fail(fmt::format("it is truncated: {} ends at byte {}", grid, endPos));
    if (!(std::int64_t(w.pos()) <= gridPos && gridPos <= blockPos && blockPos <= endPos))
      w.fail(fmt::format("{} has inconsistent offsets ({}, {}, {})", grid, gridPos, blockPos, endPos));
    w.seek(std::uint64_t(gridPos));
    headerEnd = std::uint64_t(blockPos);
  }
  w.read<std::uint32_t>("grid compression", headerEnd);
  w.metadata("grid metadata", headerEnd);
  w.string("transform type", headerEnd);
  if (offsets) w.seek(std::uint64_t(endPos));
}

void walkLayout(const std::string& bytes, const std::string& name) {
  LayoutWalker w(bytes, name);
  const bool offsets = walkHeader(w);
  const auto count = w.read<std::int32_t>("grid count", w.size());
  if (count < 0 || std::uint64_t(count) > (w.size() - w.pos()) / 36)
    w.fail(fmt::format("a grid count of {} cannot fit", count));
  // Files written to a stream have no offsets: past the first grid OpenVDB reads them bounded by the stream only.
  for (int i = 0; i < (offsets ? count : std::min(count, 1)); ++i) walkGrid(w, i, offsets);
}

} // namespace

openvdb::GridPtrVec readVdbBytes(const std::string& bytes, const std::string& name) {
  openvdb::initialize();
  walkLayout(bytes, name);
  std::istringstream in(bytes);
  // The first read past the end throws, before a garbage count can loop on.
  in.exceptions(std::ios::failbit | std::ios::badbit | std::ios::eofbit);
  try {
    openvdb::io::Stream stream(in, /*delayLoad=*/false);
    return *stream.getGrids();
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
