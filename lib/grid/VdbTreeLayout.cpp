// The tree part of the .vdb walk (VdbLayout.h): topology and value blocks, read as OpenVDB 10's RootNode,
// InternalNode, LeafNode (and its bool and mask forms) and io::readCompressedValues read them, so that every
// chunk length OpenVDB will believe has been checked before it reads one.
#include "grid/VdbLayout.h"

#include <fmt/format.h>
#include <openvdb/io/Compression.h>
#include <openvdb/openvdb.h>

#include <type_traits>

namespace rtsdf::vdblayout {
namespace io = openvdb::io;

namespace {

/// The layout of tree type TreeT, taken from OpenVDB's own node types (sizes, Log2Dims, half types).
template <class TreeT> TreeLayout layoutOf(TreeLayout::Leaf leaf) {
  using UpperT = typename TreeT::RootNodeType::ChildNodeType;
  using LowerT = typename UpperT::ChildNodeType;
  using LeafT = typename LowerT::ChildNodeType;
  using ValueT = typename TreeT::ValueType;
  using Half = io::RealToHalf<ValueT>;
  TreeLayout t;
  t.type = TreeT::treeType();
  t.valueSize = sizeof(ValueT);
  t.real = Half::isReal;
  t.halfSize = Half::isReal ? sizeof(typename Half::HalfT) : sizeof(ValueT);
  t.boolValues = std::is_same_v<ValueT, bool>;
  t.leaf = leaf;
  t.log2[0] = int(UpperT::LOG2DIM);
  t.log2[1] = int(LowerT::LOG2DIM);
  t.log2[2] = int(LeafT::LOG2DIM);
  t.nodeBytes[0] = sizeof(UpperT);
  t.nodeBytes[1] = sizeof(LowerT);
  // A LeafNode's values live in a separate array; bool and mask leaves hold theirs as bits.
  t.nodeBytes[2] = sizeof(LeafT) + (leaf == TreeLayout::Leaf::Values ? LeafT::SIZE * sizeof(ValueT) : 0);
  return t;
}

const std::vector<TreeLayout>& layouts() {
  using L = TreeLayout::Leaf;
  static const std::vector<TreeLayout> all{
      layoutOf<openvdb::FloatTree>(L::Values),  layoutOf<openvdb::DoubleTree>(L::Values),
      layoutOf<openvdb::Int32Tree>(L::Values),  layoutOf<openvdb::Int64Tree>(L::Values),
      layoutOf<openvdb::Vec3STree>(L::Values),  layoutOf<openvdb::Vec3DTree>(L::Values),
      layoutOf<openvdb::Vec3ITree>(L::Values),  layoutOf<openvdb::BoolTree>(L::Bool),
      layoutOf<openvdb::MaskTree>(L::Mask)};
  return all;
}

/// A bound on a zip chunk's compressed size: zlib's compressBound is below it (OpenVDB itself only writes a
/// compressed chunk that is smaller than its data).
std::uint64_t zipBound(std::uint64_t bytes) { return bytes + bytes / 1000 + 64; }

constexpr std::uint64_t kBloscHeader = 16; // BLOSC_MAX_OVERHEAD: the header every blosc chunk starts with

/// The value (or bool) of a tile, a background or an inactive value.
void walkValue(ByteWalker& w, const TreeLayout& t, const char* what, std::uint64_t end) {
  if (t.boolValues) w.flag(what, end);
  else w.skip(t.valueSize, what, end);
}

/// io::readCompressedValues for a node of @a count values whose value mask (@a maskBytes long) has @a activeCount
/// bits on: the flag saying which inactive values were left out, those values, the selection mask, the chunk.
void walkValues(ByteWalker& w, const TreeLayout& t, const GridCodec& c, std::uint64_t count,
                std::uint64_t activeCount, std::uint64_t maskBytes, std::uint64_t end) {
  // OpenVDB writes 0 to 6; it reads any other flag as one that left inactive values out but stored none.
  const int meta = w.read<std::int8_t>("value compression flag", end);
  const bool oneValue = meta == io::NO_MASK_AND_ONE_INACTIVE_VAL || meta == io::MASK_AND_ONE_INACTIVE_VAL ||
                        meta == io::MASK_AND_TWO_INACTIVE_VALS;
  if (oneValue) walkValue(w, t, "inactive value", end);
  if (meta == io::MASK_AND_TWO_INACTIVE_VALS) walkValue(w, t, "inactive value", end);
  if (meta == io::MASK_AND_NO_INACTIVE_VALS || meta == io::MASK_AND_ONE_INACTIVE_VAL ||
      meta == io::MASK_AND_TWO_INACTIVE_VALS)
    w.skip(maskBytes, "selection mask", end);
  std::uint64_t n = count;
  if ((c.compression & io::COMPRESS_ACTIVE_MASK) && meta != io::NO_MASK_AND_ALL_VALS) n = activeCount;
  // HalfReader reads nothing at all for no values; readData still reads a chunk (its size field) for them.
  if (c.half && t.real) {
    if (n > 0) walkChunk(w, c.compression, n * t.halfSize, end, "values");
  } else {
    walkChunk(w, c.compression, n * t.valueSize, end, "values");
  }
}

openvdb::Coord readCoord(ByteWalker& w, const char* what, std::uint64_t end) {
  const auto x = w.read<std::int32_t>(what, end), y = w.read<std::int32_t>(what, end);
  return {x, y, w.read<std::int32_t>(what, end)};
}

/// One tree's topology walk: the walker, the layout and what was found so far.
struct Topology {
  ByteWalker& w;
  const TreeLayout& t;
  const GridCodec& c;
  std::uint64_t end;
  TreeWalk out;
};

/// InternalNode::readTopology at @a level (0 upper, 1 lower): child and value masks, the node's values, then each
/// child in the child mask's order (a lower node's children are leaves: their value masks).
void walkInternal(Topology& k, int level, const openvdb::Coord& origin) {
  ByteWalker& w = k.w;
  const int log2 = k.t.log2[level];
  const std::uint64_t count = std::uint64_t(1) << (3 * log2), maskBytes = count / 8;
  const int childTotal = level == 0 ? k.t.log2[1] + k.t.log2[2] : k.t.log2[2];
  w.setNode(level == 0 ? "upper internal node" : "lower internal node", origin);
  const std::uint64_t childMask = w.pos();
  w.skip(maskBytes, "child mask", k.end);
  const std::uint64_t valueMask = w.pos();
  w.skip(maskBytes, "value mask", k.end);
  walkValues(w, k.t, k.c, count, w.countOn(valueMask, maskBytes), maskBytes, k.end);
  k.out.memoryBytes += k.t.nodeBytes[level];
  const std::uint64_t dim = std::uint64_t(1) << log2, leafMaskBytes = (std::uint64_t(1) << (3 * k.t.log2[2])) / 8;
  for (std::uint64_t i = 0; i < count; ++i) {
    if (!w.isOn(childMask, i)) continue;
    // InternalNode::offsetToGlobalCoord: x, y, z of the child's slot (z fastest), scaled to the child's size.
    const openvdb::Coord child =
        origin + (openvdb::Coord(int(i >> (2 * log2)), int((i >> log2) & (dim - 1)), int(i & (dim - 1))) << childTotal);
    if (level == 0) {
      walkInternal(k, 1, child);
    } else {
      w.setNode("leaf", child);
      w.skip(leafMaskBytes, "leaf value mask", k.end);
      k.out.leaves.push_back(child);
      k.out.memoryBytes += k.t.nodeBytes[2];
    }
  }
}

/// RootNode::readTopology's tiles and the origins of its children: aligned to a child's size and in increasing
/// order, the order of the root's map (its buffers are read in map order, not in file order).
openvdb::Coord rootKey(ByteWalker& w, const char* what, std::uint64_t end, int rootTotal,
                       const openvdb::Coord* previous) {
  const openvdb::Coord c = readCoord(w, what, end);
  const std::int32_t mask = (std::int32_t(1) << rootTotal) - 1;
  if ((c.x() & mask) || (c.y() & mask) || (c.z() & mask))
    w.fail(fmt::format("a root {} at ({}, {}, {}) is not aligned to {} voxels", what, c.x(), c.y(), c.z(), mask + 1));
  if (previous && !(*previous < c))
    w.fail(fmt::format("the root's {}s are not in increasing order at ({}, {}, {})", what, c.x(), c.y(), c.z()));
  return c;
}

} // namespace

const TreeLayout* treeLayoutOf(const std::string& gridType) {
  for (const TreeLayout& t : layouts())
    if (t.type == gridType) return &t;
  return nullptr;
}

const char* readableGridTypes() { return "float, double, int32, int64, vec3s, vec3d, vec3i, bool and mask"; }

void walkChunk(ByteWalker& w, std::uint32_t compression, std::uint64_t bytes, std::uint64_t end, const char* what) {
  const bool blosc = compression & io::COMPRESS_BLOSC, zip = !blosc && (compression & io::COMPRESS_ZIP);
  if (!blosc && !zip) return w.skip(bytes, what, end);
  const char* codec = blosc ? "blosc" : "zip";
  const auto stated = w.read<std::int64_t>(blosc ? "blosc chunk size" : "zip chunk size", end);
  if (stated <= 0) { // uncompressed: OpenVDB reads the stated length into a buffer of `bytes` before comparing
    const std::uint64_t n = std::uint64_t(0) - std::uint64_t(stated);
    if (n != bytes)
      w.fail(fmt::format("a {} chunk of {} states {} uncompressed bytes where {} are expected", codec, what, n, bytes));
    return w.skip(bytes, what, end);
  }
  const std::uint64_t n = std::uint64_t(stated), left = end > w.pos() ? end - w.pos() : 0;
  if (n > left)
    w.fail(fmt::format("a {} chunk of {} states {} compressed bytes, past the grid's end ({} bytes left)", codec,
                       what, n, left));
  if (blosc) {
    if (n < kBloscHeader || n > bytes + kBloscHeader)
      w.fail(fmt::format("a blosc chunk of {} states {} compressed bytes for {} (blosc takes {} to {})", what, n,
                         bytes, kBloscHeader, bytes + kBloscHeader));
    // blosc_decompress_ctx trusts the chunk's own header: its sizes must be the chunk's.
    const std::uint32_t headerBytes = w.peek32(w.pos() + 4), headerCompressed = w.peek32(w.pos() + 12);
    if (headerBytes != bytes || headerCompressed != n)
      w.fail(fmt::format("a blosc chunk of {} whose header says {} bytes in {} where {} in {} are expected", what,
                         headerBytes, headerCompressed, bytes, n));
  } else if (n > zipBound(bytes)) {
    w.fail(fmt::format("a zip chunk of {} states {} compressed bytes for {}", what, n, bytes));
  }
  w.skip(n, what, end);
}

TreeWalk walkTopology(ByteWalker& w, const TreeLayout& tree, const GridCodec& codec, std::uint64_t end) {
  Topology k{w, tree, codec, end, {}};
  w.read<std::int32_t>("buffer count", end); // OpenVDB only warns when it is not 1
  walkValue(w, tree, "background", end);
  const auto tiles = w.read<std::uint32_t>("root tile count", end);
  const auto children = w.read<std::uint32_t>("root child count", end);
  const std::uint64_t left = end > w.pos() ? end - w.pos() : 0;
  const std::uint64_t tileBytes = 12 + tree.valueSize + 1;
  const std::uint64_t childBytes = 12 + 2 * ((std::uint64_t(1) << (3 * tree.log2[0])) / 8) + 1;
  if (tiles > left / tileBytes) w.fail(fmt::format("{} root tiles cannot fit in the {} bytes left", tiles, left));
  if (children > (left - tiles * tileBytes) / childBytes)
    w.fail(fmt::format("{} root children cannot fit in the {} bytes left", children, left - tiles * tileBytes));
  const int rootTotal = tree.log2[0] + tree.log2[1] + tree.log2[2];
  openvdb::Coord previous;
  for (std::uint32_t i = 0; i < tiles; ++i) {
    previous = rootKey(w, "tile", end, rootTotal, i ? &previous : nullptr);
    walkValue(w, tree, "tile value", end);
    w.flag("tile's active flag", end);
    k.out.memoryBytes += 64; // a std::map node
  }
  for (std::uint32_t i = 0; i < children; ++i) {
    w.clearNode();
    previous = rootKey(w, "child", end, rootTotal, i ? &previous : nullptr);
    walkInternal(k, 0, previous);
  }
  w.clearNode();
  return std::move(k.out);
}

void walkBuffers(ByteWalker& w, const TreeLayout& tree, const GridCodec& codec, const TreeWalk& walk,
                 std::uint64_t end) {
  const std::uint64_t count = std::uint64_t(1) << (3 * tree.log2[2]), maskBytes = count / 8;
  for (const openvdb::Coord& origin : walk.leaves) {
    w.setNode("leaf", origin);
    const std::uint64_t mask = w.pos();
    w.skip(maskBytes, tree.leaf == TreeLayout::Leaf::Mask ? "leaf values" : "leaf value mask", end);
    if (tree.leaf == TreeLayout::Leaf::Values) {
      walkValues(w, tree, codec, count, w.countOn(mask, maskBytes), maskBytes, end);
      continue;
    }
    // Bool and mask leaves store their origin with their bits; OpenVDB takes it as the leaf's.
    const openvdb::Coord stored = readCoord(w, "leaf origin", end);
    if (stored != origin)
      w.fail(fmt::format("its stored origin ({}, {}, {}) is not its place in the tree", stored.x(), stored.y(),
                         stored.z()));
    if (tree.leaf == TreeLayout::Leaf::Bool) w.skip(maskBytes, "leaf values", end);
  }
  w.clearNode();
}

} // namespace rtsdf::vdblayout
