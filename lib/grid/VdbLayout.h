#pragma once
/// @file VdbLayout.h
/// @brief The walk of a .vdb's bytes that readVdbBytes runs before OpenVDB reads them (internal to grid/): the
///        header, every metadata table, grid descriptor, transform, tree topology and block of values, read the way
///        OpenVDB 10's io::Stream reads them. Every length and count the file states is checked against the bytes
///        left and against what OpenVDB will do with it: OpenVDB allocates what a length says before it reads, and
///        its bloscFromStream/unzipFromStream read a chunk marked uncompressed into the node's buffer for the
///        length the file states before they compare it with the buffer's size.
#include <openvdb/Types.h>

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace rtsdf::vdblayout {

/// @brief Bounded little-endian reads over a file's bytes; every failure names the file, the grid being walked
///        and the byte offset.
class ByteWalker {
public:
  ByteWalker(const std::string& bytes, const std::string& name) : mBytes(bytes), mName(name) {}

  /// @throw Error "<file>: not a readable .vdb file: [<grid>: ]<what> (at byte <pos> of <size>)".
  [[noreturn]] void fail(const std::string& what) const;

  /// @brief A value of type T that must end at or before @a end.
  template <class T> T read(const char* what, std::uint64_t end) {
    if (mPos > end || sizeof(T) > end - mPos) failEnds(what);
    T v;
    std::memcpy(&v, mBytes.data() + mPos, sizeof(T));
    mPos += sizeof(T);
    return v;
  }
  /// @brief A length-prefixed string (OpenVDB's readString), whole; bounded by the bytes before @a end.
  std::string text(const char* what, std::uint64_t end);
  /// @brief Skip @a n bytes that must end at or before @a end.
  void skip(std::uint64_t n, const char* what, std::uint64_t end);
  /// @brief A byte OpenVDB reads into a bool: anything but 0 or 1 is no bool (and undefined behaviour to load).
  bool flag(const char* what, std::uint64_t end);
  /// @brief The number of set bits in the @a n bytes at @a pos (a node mask already walked over).
  std::uint64_t countOn(std::uint64_t pos, std::uint64_t n) const;
  /// @brief Whether bit @a i is set in the mask whose bytes start at @a pos (OpenVDB's NodeMask: 64-bit words).
  bool isOn(std::uint64_t pos, std::uint64_t i) const {
    return (static_cast<unsigned char>(mBytes[pos + i / 8]) >> (i % 8)) & 1u;
  }
  /// @brief A 32-bit little-endian field at @a pos (a compressed chunk's header, already bounded).
  std::uint32_t peek32(std::uint64_t pos) const {
    std::uint32_t v;
    std::memcpy(&v, mBytes.data() + pos, sizeof v);
    return v;
  }

  /// @brief The byte at @a pos (already walked over).
  char byteAt(std::uint64_t pos) const { return mBytes[pos]; }
  std::uint64_t pos() const { return mPos; }
  std::uint64_t size() const { return mBytes.size(); }
  /// @brief What errors say is being walked (a grid), empty between grids.
  void setContext(std::string context) { mContext = std::move(context); }
  /// @brief The tree node being walked, named by errors (kept unformatted: set once per node).
  void setNode(const char* kind, const openvdb::Coord& origin) {
    mNodeKind = kind;
    mNode = origin;
  }
  void clearNode() { mNodeKind = nullptr; }

private:
  [[noreturn]] void failEnds(const char* what) const;

  const std::string& mBytes;
  const std::string& mName;
  std::string mContext;
  const char* mNodeKind = nullptr;
  openvdb::Coord mNode;
  std::uint64_t mPos = 0;
};

/// @brief How one grid's values are stored: its compression flags (io::COMPRESS_*) and whether floating-point
///        values were saved as halves (a type name ending in "_HalfFloat").
struct GridCodec {
  std::uint32_t compression = 0;
  bool half = false;
};

/// @brief The byte layout of one tree type OpenVDB reads: a root over two internal levels over leaves.
struct TreeLayout {
  enum class Leaf { Values, Bool, Mask };
  std::string type;          ///< OpenVDB's tree type name, e.g. "Tree_float_5_4_3"
  std::size_t valueSize = 0; ///< sizeof(ValueType): tiles, backgrounds and inactive values
  std::size_t halfSize = 0;  ///< bytes per buffered value when saved as half (valueSize when not a real type)
  bool real = false;         ///< io::RealToHalf<ValueType>::isReal (half-float buffers)
  bool boolValues = false;   ///< value bytes are bools (0 or 1)
  Leaf leaf = Leaf::Values;  ///< LeafNode, LeafNode<bool> or LeafNode<ValueMask>
  int log2[3] = {0, 0, 0};   ///< Log2Dim of the upper and lower internal nodes and of the leaves
  std::uint64_t nodeBytes[3] = {0, 0, 0}; ///< sizeof of each node type in memory
};

/// @brief The layout of the tree type named @a gridType (without "_HalfFloat"); null when rtsdf does not read it
///        (the types rtsdf and level-set tools write: float, double, int32, int64, vec3s/d/i, bool and mask).
const TreeLayout* treeLayoutOf(const std::string& gridType);

/// @brief The grid types treeLayoutOf takes, for messages.
const char* readableGridTypes();

/// @brief What a tree walk found: its leaves (in the order their buffers follow) and its memory estimate.
struct TreeWalk {
  std::vector<openvdb::Coord> leaves;
  std::uint64_t memoryBytes = 0;
};

/// @brief RootNode/InternalNode/LeafNode::readTopology of a tree of layout @a tree, ending at or before @a end.
TreeWalk walkTopology(ByteWalker& w, const TreeLayout& tree, const GridCodec& codec, std::uint64_t end);

/// @brief Tree::readBuffers: each leaf's block of values, in the order of @a walk's leaves.
void walkBuffers(ByteWalker& w, const TreeLayout& tree, const GridCodec& codec, const TreeWalk& walk,
                 std::uint64_t end);

/// @brief One chunk of @a bytes bytes as io::readData reads it (blosc, zip or raw per @a compression): a blosc or
///        zip chunk's stated size must be what the reader expects (uncompressed: exactly @a bytes; compressed:
///        positive, inside @a end and within the codec's bound of @a bytes; a blosc header that agrees).
void walkChunk(ByteWalker& w, std::uint32_t compression, std::uint64_t bytes, std::uint64_t end, const char* what);

/// @brief The whole file, as io::Stream reads it.
/// @throw Error naming @a name (via ByteWalker::fail) at the first thing OpenVDB must not be given.
void walkVdb(const std::string& bytes, const std::string& name);

} // namespace rtsdf::vdblayout
