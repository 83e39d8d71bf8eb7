// The file part of the .vdb walk (VdbLayout.h): header, metadata tables, grid descriptors and transforms, read as
// OpenVDB 10's io::Stream, MetaMap, the registered Metadata types and math::Transform read them; the trees are
// walked by VdbTreeLayout.cpp.
#include "grid/VdbLayout.h"

#include "util/Error.h"
#include "util/Memory.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <openvdb/io/DelayedLoadMetadata.h>
#include <openvdb/math/Maps.h>
#include <openvdb/openvdb.h>

#include <bitset>
#include <cctype>
#include <limits>
#include <map>
#include <optional>

namespace rtsdf::vdblayout {

void ByteWalker::fail(const std::string& what) const {
  std::string where = mContext.empty() ? "" : mContext + ": ";
  if (mNodeKind) where += fmt::format("the {} at ({}, {}, {}): ", mNodeKind, mNode.x(), mNode.y(), mNode.z());
  throw Error(fmt::format("{}: not a readable .vdb file: {}{} (at byte {} of {})", mName, where, what, mPos,
                          mBytes.size()));
}

void ByteWalker::failEnds(const char* what) const { fail(fmt::format("the file ends inside the {}", what)); }

std::string ByteWalker::text(const char* what, std::uint64_t end) {
  const std::uint32_t n = read<std::uint32_t>(what, end);
  skip(n, what, end);
  return mBytes.substr(mPos - n, n);
}

void ByteWalker::skip(std::uint64_t n, const char* what, std::uint64_t end) {
  if (mPos > end || n > end - mPos) fail(fmt::format("a {} of {} bytes runs past the end", what, n));
  mPos += n;
}

bool ByteWalker::flag(const char* what, std::uint64_t end) {
  const auto v = read<std::uint8_t>(what, end);
  if (v > 1) fail(fmt::format("a {} of {} (a bool: 0 or 1)", what, int(v)));
  return v != 0;
}

std::uint64_t ByteWalker::countOn(std::uint64_t pos, std::uint64_t n) const {
  std::uint64_t on = 0;
  for (std::uint64_t i = 0; i < n; ++i) on += std::bitset<8>(static_cast<unsigned char>(mBytes[pos + i])).count();
  return on;
}

namespace {

/// A name from the file, cut for a message.
std::string shown(const std::string& s) { return oneLine(s.substr(0, 60)); }

/// Bytes per value of the registered Metadata types whose readValue reads sizeof(T) whatever size the file
/// states (TypedMetadata<T>): a stated size that differs would leave OpenVDB reading elsewhere than the walk.
const std::map<std::string, std::uint32_t>& fixedMetadataSizes() {
  using namespace openvdb;
  static const std::map<std::string, std::uint32_t> sizes{
      {BoolMetadata::staticTypeName(), 1},       {DoubleMetadata::staticTypeName(), 8},
      {FloatMetadata::staticTypeName(), 4},      {Int32Metadata::staticTypeName(), 4},
      {Int64Metadata::staticTypeName(), 8},      {Vec2IMetadata::staticTypeName(), 8},
      {Vec2SMetadata::staticTypeName(), 8},      {Vec2DMetadata::staticTypeName(), 16},
      {Vec3IMetadata::staticTypeName(), 12},     {Vec3SMetadata::staticTypeName(), 12},
      {Vec3DMetadata::staticTypeName(), 24},     {Vec4IMetadata::staticTypeName(), 16},
      {Vec4SMetadata::staticTypeName(), 16},     {Vec4DMetadata::staticTypeName(), 32},
      {Mat4SMetadata::staticTypeName(), 64},     {Mat4DMetadata::staticTypeName(), 128},
      {typeNameAsString<PointIndex32>(), 4},     {typeNameAsString<PointIndex64>(), 8},
      {typeNameAsString<PointDataIndex32>(), 4}, {typeNameAsString<PointDataIndex64>(), 8}};
  return sizes;
}

/// One blosc buffer of DelayedLoadMetadata: OpenVDB reserves what its header says and decompresses trusting it.
void walkBloscBuffer(ByteWalker& w, std::uint32_t bytes, std::uint64_t expected, std::uint64_t end) {
  constexpr std::uint64_t kHeader = 16, kPad = 128; // BLOSC_MAX_OVERHEAD; StreamCompression's BLOSC_PAD_BYTES
  if (bytes < kHeader || bytes > (end > w.pos() ? end - w.pos() : 0))
    w.fail(fmt::format("a delayed-load table of {} compressed bytes", bytes));
  const std::uint32_t headerBytes = w.peek32(w.pos() + 4), headerCompressed = w.peek32(w.pos() + 12);
  // Small tables are padded to kPad bytes before compression.
  if (headerCompressed != bytes || !(headerBytes == expected || (expected < kPad && headerBytes == kPad)))
    w.fail(fmt::format("a delayed-load table whose header says {} bytes in {} where {} in {} are expected",
                       headerBytes, headerCompressed, expected, bytes));
  w.skip(bytes, "delayed-load table", end);
}

/// io::DelayedLoadMetadata::readValue: a leaf count, the per-leaf masks and compressed sizes (blosc or raw), then
/// whatever of the stated size is left. Returns the leaf count it states.
std::uint32_t walkDelayedLoad(ByteWalker& w, std::uint32_t size, std::uint64_t end) {
  if (size == 0) return 0;
  const std::uint64_t start = w.pos();
  const auto count = w.read<std::uint32_t>("delayed-load count", end);
  if (const auto bytes = w.read<std::uint32_t>("delayed-load size", end)) walkBloscBuffer(w, bytes, count, end);
  else w.skip(count, "delayed-load masks", end);
  const auto bytes = w.read<std::uint32_t>("delayed-load size", end);
  if (bytes != std::numeric_limits<std::uint32_t>::max()) {
    if (bytes) walkBloscBuffer(w, bytes, std::uint64_t(count) * 8, end);
    else w.skip(std::uint64_t(count) * 8, "delayed-load sizes", end);
  }
  if (w.pos() - start > size)
    w.fail(fmt::format("delayed-load metadata of {} bytes holds {}", size, w.pos() - start));
  w.skip(size - (w.pos() - start), "delayed-load metadata", end);
  return count;
}

/// What a grid's metadata tells the reader of its tree.
struct GridMetadata {
  std::vector<std::uint32_t> delayed; ///< the leaf counts of its delayed-load entries
  bool half = false;                  ///< is_saved_as_half_float: the tree's buffers hold half floats
};

/// MetaMap::readMeta: a count, then (name, type, size, value) per entry, each value read as its registered type
/// reads it.
GridMetadata walkMetadata(ByteWalker& w, const char* what, std::uint64_t end) {
  const std::uint32_t count = w.read<std::uint32_t>(what, end);
  if (count > (end - w.pos()) / 12) w.fail(fmt::format("{} entries of {} cannot fit", count, what));
  GridMetadata found;
  // GridBase::saveFloatAsHalf() is this entry (any type, read as a bool), not the "_HalfFloat" of the type name:
  // readMeta drops what the descriptor set. A bool is all OpenVDB writes; other types are refused.
  const std::string halfKey = openvdb::GridBase::META_SAVE_HALF_FLOAT;
  for (std::uint32_t i = 0; i < count; ++i) {
    const std::string name = w.text("metadata name", end), type = w.text("metadata type", end);
    const auto size = w.read<std::uint32_t>("metadata size", end);
    const auto fixed = fixedMetadataSizes().find(type);
    if (type == openvdb::io::DelayedLoadMetadata::staticTypeName()) {
      found.delayed.push_back(walkDelayedLoad(w, size, end));
    } else if (fixed != fixedMetadataSizes().end()) {
      if (size != fixed->second)
        w.fail(fmt::format("metadata '{}' of type {} has {} bytes, not {}", shown(name), type, size, fixed->second));
      if (type == openvdb::BoolMetadata::staticTypeName()) {
        const bool value = w.flag("bool metadata value", end);
        if (name == halfKey) found.half = value;
      } else {
        w.skip(size, "metadata value", end);
      }
    } else if (type == openvdb::StringMetadata::staticTypeName() || !openvdb::Metadata::isRegisteredType(type)) {
      w.skip(size, "metadata value", end); // a string, or raw bytes (UnknownMetadata)
    } else {
      w.fail(fmt::format("metadata '{}' of type {}, which this reader cannot check", shown(name), shown(type)));
    }
    if (name == halfKey && type != openvdb::BoolMetadata::staticTypeName())
      w.fail(fmt::format("metadata '{}' of type {}, not bool", halfKey, shown(type)));
  }
  return found;
}

/// math::Transform::read (format 219 on): the map's type, then its fields; a frustum holds a second, affine map.
void walkTransform(ByteWalker& w, std::uint64_t end) {
  using namespace openvdb::math;
  static const std::map<std::string, std::uint64_t> mapBytes{
      {AffineMap::mapType(), 128},     {UnitaryMap::mapType(), 128},        {ScaleMap::mapType(), 120},
      {UniformScaleMap::mapType(), 120}, {TranslationMap::mapType(), 24}, {ScaleTranslateMap::mapType(), 144},
      {UniformScaleTranslateMap::mapType(), 144}};
  const std::string type = w.text("transform type", end);
  if (type == NonlinearFrustumMap::mapType()) {
    w.skip(48 + 8 + 8, "frustum", end); // its bounding box (doubles), taper and depth
    const std::string second = w.text("frustum's map type", end);
    if (second != AffineMap::mapType()) w.fail(fmt::format("a frustum over a map of type '{}'", shown(second)));
    return w.skip(128, "frustum's map", end);
  }
  const auto it = mapBytes.find(type);
  if (it == mapBytes.end()) w.fail(fmt::format("a transform of unknown type '{}'", shown(type)));
  w.skip(it->second, "transform", end);
}

/// Header: magic, format version (222 and newer: OpenVDB 3 on), library version, offsets flag, UUID, metadata.
bool walkHeader(ByteWalker& w) {
  const std::uint64_t end = w.size();
  if (w.read<std::int64_t>("magic number", end) != 0x56444220) w.fail("no VDB magic number at its start");
  const std::uint32_t version = w.read<std::uint32_t>("format version", end);
  if (version < openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION || version > openvdb::OPENVDB_FILE_VERSION)
    w.fail(fmt::format("file format version {} (this reader takes {} to {})", version,
                       int(openvdb::OPENVDB_FILE_VERSION_NODE_MASK_COMPRESSION), openvdb::OPENVDB_FILE_VERSION));
  w.read<std::uint32_t>("library version", end);
  w.read<std::uint32_t>("library version", end);
  const bool offsets = w.read<char>("grid offsets flag", end) != 0;
  // The UUID is read as text with >>, which skips whitespace: it must be exactly 36 characters of one.
  const std::uint64_t uuid = w.pos();
  w.skip(36, "UUID", end);
  for (std::uint64_t i = 0; i < 36; ++i) {
    const char c = w.byteAt(uuid + i);
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? c != '-' : !std::isxdigit(static_cast<unsigned char>(c))) w.fail("a UUID that is not one");
  }
  if (!walkMetadata(w, "file metadata", end).delayed.empty()) w.fail("delayed-load metadata in the file's metadata");
  return offsets;
}

/// The rest of a grid after its descriptor's names: its offsets, compression, metadata, transform, topology and
/// blocks, as io::Stream reads them one after the other. With offsets (io::File) they must say where the walk
/// is: Stream ignores them, so a file whose offsets disagree with its contents is not what it claims.
std::uint64_t walkGridData(ByteWalker& w, const TreeLayout& tree, GridCodec codec, bool instance, bool offsets) {
  const auto gridPos = w.read<std::int64_t>("grid offsets", w.size());
  const auto blockPos = w.read<std::int64_t>("grid offsets", w.size());
  const auto endPos = w.read<std::int64_t>("grid offsets", w.size());
  std::uint64_t end = w.size();
  if (offsets) {
    if (endPos > std::int64_t(end)) w.fail(fmt::format("it is truncated: it ends at byte {}", endPos));
    if (gridPos != std::int64_t(w.pos()) || endPos < gridPos)
      w.fail(fmt::format("inconsistent offsets ({}, {}, {}): its data follows its descriptor at byte {}", gridPos,
                         blockPos, endPos, w.pos()));
    end = std::uint64_t(endPos);
  }
  codec.compression = w.read<std::uint32_t>("grid compression", end);
  const GridMetadata meta = walkMetadata(w, "grid metadata", end);
  codec.half = meta.half;
  walkTransform(w, end);
  TreeWalk walk;
  if (!instance) { // an instance shares its parent's tree: it has no topology or blocks of its own
    walk = walkTopology(w, tree, codec, end);
    if (offsets && std::int64_t(w.pos()) != blockPos)
      w.fail(fmt::format("its topology ends at byte {}, not at its block offset {}", w.pos(), blockPos));
    walkBuffers(w, tree, codec, walk, end);
  }
  for (const std::uint32_t count : meta.delayed)
    if (count != walk.leaves.size())
      w.fail(fmt::format("its delayed-load metadata counts {} leaves where its tree has {}", count, walk.leaves.size()));
  if (offsets && std::int64_t(w.pos()) != endPos)
    w.fail(fmt::format("its data ends at byte {}, not at its end offset {}", w.pos(), endPos));
  return walk.memoryBytes;
}

/// One grid: its descriptor (GridDescriptor::read: unique name, type with "_HalfFloat" when saved as half,
/// instance parent, offsets), then its data. Types rtsdf does not read are refused before OpenVDB sees them.
std::uint64_t walkGrid(ByteWalker& w, int index, bool offsets) {
  w.setContext(fmt::format("grid {}", index));
  const std::string name = w.text("grid name", w.size());
  std::string type = w.text("grid type", w.size());
  const std::string parent = w.text("instance parent name", w.size());
  // The descriptor marks half floats in the type name; the grid's metadata decides (walkMetadata).
  const std::string half = "_HalfFloat";
  if (type.size() >= half.size() && type.compare(type.size() - half.size(), half.size(), half) == 0)
    type.erase(type.size() - half.size());
  w.setContext(fmt::format("grid {} ('{}' of type {})", index, shown(name), shown(type)));
  const TreeLayout* tree = treeLayoutOf(type);
  if (!tree) w.fail(fmt::format("rtsdf reads grids of {} values only", readableGridTypes()));
  const std::uint64_t memory = walkGridData(w, *tree, GridCodec{}, !parent.empty(), offsets);
  w.setContext({});
  return memory;
}

} // namespace

void walkVdb(const std::string& bytes, const std::string& name) {
  ByteWalker w(bytes, name);
  const bool offsets = walkHeader(w);
  const auto count = w.read<std::int32_t>("grid count", w.size());
  if (count < 0 || std::uint64_t(count) > (w.size() - w.pos()) / 36)
    w.fail(fmt::format("a grid count of {} cannot fit", count));
  std::uint64_t memory = 0;
  for (int i = 0; i < count; ++i) memory += walkGrid(w, i, offsets);
  // Each node is allocated whole whatever the file spent on it: refuse a tree that cannot be held.
  const std::uint64_t available = availableHostMemory();
  if (available && memory > available)
    w.fail(fmt::format("its trees would take {:.1f} GiB, more than the {:.1f} GiB of memory available",
                       double(memory) / double(1ull << 30), double(available) / double(1ull << 30)));
}

} // namespace rtsdf::vdblayout
