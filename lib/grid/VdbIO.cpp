#include "grid/VdbIO.h"

#include "util/AtomicFile.h"
#include "util/Text.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <openvdb/tools/LevelSetUtil.h>
#include <openvdb/tools/SignedFloodFill.h>
#include <tbb/blocked_range3d.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <cmath>
#include <memory>

namespace rtsdf {
namespace fs = std::filesystem;
using openvdb::Coord;
using openvdb::FloatGrid;
using LeafT = FloatGrid::TreeType::LeafNodeType;

namespace {
void ensureOpenVdb() {
  static const bool done = [] { openvdb::initialize(); return true; }();
  (void)done;
}
constexpr int kLeafDim = LeafT::DIM;
static_assert(kLeafDim == 8, "rtsdf's block functions assume 8^3 OpenVDB leaves");
} // namespace

double minVdbVoxelSize() {
  // ScaleMap refuses |h^3| < 3 * Tolerance<double> (1e-15); stay a little above it.
  return std::cbrt(3.0 * openvdb::math::Tolerance<double>::value()) * (1.0 + 1e-9);
}

namespace {

/// The turn of a Y-up frame to a Z-up one, (x, y, z) -> (x, -z, y), in OpenVDB's row-vector convention
/// (world = index * M); @a inverse turns back. Only 0 and +-1: products with it are exact.
openvdb::Mat4d upTurn(bool inverse) {
  const double s = inverse ? -1.0 : 1.0;
  return openvdb::Mat4d(1.0, 0.0, 0.0, 0.0, //
                        0.0, 0.0, s, 0.0,   //
                        0.0, -s, 0.0, 0.0,  //
                        0.0, 0.0, 0.0, 1.0);
}

} // namespace

openvdb::math::Transform::Ptr makeTransform(const GridSpec& spec, UpAxis up) {
  if (!(spec.voxelSize >= minVdbVoxelSize()))
    throw Error(fmt::format("OpenVDB grid: voxel size {:.3g} is below the smallest OpenVDB transforms accept "
                            "({:.3g}): the scene's units are too small for this resolution (scale the scene up or "
                            "lower the resolution)", spec.voxelSize, minVdbVoxelSize()));
  auto xf = openvdb::math::Transform::createLinearTransform(spec.voxelSize);
  const glm::dvec3 c = spec.origin + 0.5 * spec.voxelSize;
  xf->postTranslate(openvdb::Vec3d(c.x, c.y, c.z));
  if (up == UpAxis::Z) xf->postMult(upTurn(false));
  return xf;
}

FloatGrid::Ptr buildLevelSet(const GridSpec& spec, float band, const LevelSetBlockFn& fill) {
  ensureOpenVdb();
  if (!(band > 0.0f) || !std::isfinite(band)) throw Error(fmt::format("level set: band {} must be positive", band));
  const glm::ivec3 blocks = (spec.dims + (kLeafDim - 1)) / kLeafDim;
  const std::size_t count = std::size_t(blocks.x) * blocks.y * blocks.z;
  std::vector<std::unique_ptr<LeafT>> leaves(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, 1), [&](const tbb::blocked_range<std::size_t>& r) {
    float values[LeafT::SIZE];
    bool active[LeafT::SIZE];
    for (std::size_t b = r.begin(); b != r.end(); ++b) {
      const glm::ivec3 bi(int(b % blocks.x), int((b / blocks.x) % blocks.y), int(b / (std::size_t(blocks.x) * blocks.y)));
      const glm::ivec3 origin = bi * kLeafDim;
      std::fill(values, values + LeafT::SIZE, band);
      std::fill(active, active + LeafT::SIZE, false);
      if (!fill(origin, values, active)) continue;
      auto leaf = std::make_unique<LeafT>(Coord(origin.x, origin.y, origin.z), band, false);
      for (openvdb::Index i = 0; i < LeafT::SIZE; ++i) {
        // Inactive voxels hold ±band so that sign flood fill and level-set tools see a clean band.
        const float v = values[i];
        leaf->setValueOnly(i, active[i] ? v : std::copysign(band, v));
        leaf->setActiveState(i, active[i]);
      }
      leaves[b] = std::move(leaf);
    }
  });
  FloatGrid::Ptr grid = FloatGrid::create(band);
  auto& tree = grid->tree();
  for (auto& leaf : leaves)
    if (leaf) tree.addLeaf(leaf.release());
  openvdb::tools::signedFloodFill(tree);
  grid->setTransform(makeTransform(spec));
  grid->setGridClass(openvdb::GRID_LEVEL_SET);
  return grid;
}

FloatGrid::Ptr denseToLevelSet(const std::vector<float>& dense, const GridSpec& spec, float band) {
  if (dense.size() != spec.voxelCount())
    throw Error(fmt::format("level set: dense array has {} values, grid {} needs {}", dense.size(), spec.describe(),
                            spec.voxelCount()));
  return buildLevelSet(spec, band, [&](const glm::ivec3& o, float* values, bool* active) {
    bool any = false;
    const glm::ivec3 hi = glm::min(o + kLeafDim, spec.dims);
    for (int x = o.x; x < hi.x; ++x)
      for (int y = o.y; y < hi.y; ++y)
        for (int z = o.z; z < hi.z; ++z) {
          const int i = ((x - o.x) * kLeafDim + (y - o.y)) * kLeafDim + (z - o.z);
          values[i] = dense[spec.linear(x, y, z)];
          active[i] = std::fabs(values[i]) <= band;
          any |= active[i];
        }
    return any;
  });
}

FloatGrid::Ptr activeVoxelsToLevelSet(std::vector<std::pair<std::uint64_t, float>> voxels, const GridSpec& spec,
                                      float band) {
  const std::uint64_t count = spec.voxelCount();
  const glm::ivec3 blocks = (spec.dims + (kLeafDim - 1)) / kLeafDim;
  auto coordOf = [&](std::uint64_t i) {
    return glm::ivec3(int(i % spec.dims.x), int((i / spec.dims.x) % spec.dims.y),
                      int(i / (std::uint64_t(spec.dims.x) * spec.dims.y)));
  };
  auto blockOf = [&](std::uint64_t i) {
    const glm::ivec3 b = coordOf(i) / kLeafDim;
    return (std::uint64_t(b.z) * blocks.y + b.y) * blocks.x + b.x;
  };
  for (const auto& v : voxels)
    if (v.first >= count)
      throw Error(fmt::format("level set: active voxel {} lies outside grid {} ({} voxels)", v.first, spec.describe(),
                              count));
  // Bucketed by block: each block's fill finds its voxels by binary search.
  std::vector<std::pair<std::uint64_t, std::size_t>> order(voxels.size());
  for (std::size_t k = 0; k < voxels.size(); ++k) order[k] = {blockOf(voxels[k].first), k};
  tbb::parallel_sort(order.begin(), order.end());
  return buildLevelSet(spec, band, [&](const glm::ivec3& o, float* values, bool* active) {
    const glm::ivec3 b = o / kLeafDim;
    const std::uint64_t block = (std::uint64_t(b.z) * blocks.y + b.y) * blocks.x + b.x;
    auto it = std::lower_bound(order.begin(), order.end(), std::make_pair(block, std::size_t(0)));
    bool any = false;
    for (; it != order.end() && it->first == block; ++it) {
      const auto& [linear, value] = voxels[it->second];
      const glm::ivec3 c = coordOf(linear) - o;
      const int i = (c.x * kLeafDim + c.y) * kLeafDim + c.z;
      values[i] = value;
      active[i] = any = true;
    }
    return any;
  });
}

std::vector<float> levelSetToDense(const FloatGrid& grid, const GridSpec& spec) {
  std::vector<float> out(spec.voxelCount());
  tbb::parallel_for(tbb::blocked_range<int>(0, spec.dims.z), [&](const tbb::blocked_range<int>& r) {
    auto acc = grid.getConstAccessor();
    for (int z = r.begin(); z != r.end(); ++z)
      for (int y = 0; y < spec.dims.y; ++y)
        for (int x = 0; x < spec.dims.x; ++x) out[spec.linear(x, y, z)] = acc.getValue(Coord(x, y, z));
  });
  return out;
}

void stampLevelSet(FloatGrid& grid, const GridSpec& spec, const std::map<std::string, MetaValue>& settings) {
  grid.setName("surface");
  grid.setGridClass(openvdb::GRID_LEVEL_SET);
  grid.setTransform(makeTransform(spec));
  grid.insertMeta("rtsdf:dims", openvdb::Vec3IMetadata(openvdb::Vec3i(spec.dims.x, spec.dims.y, spec.dims.z)));
  grid.insertMeta("rtsdf:origin", openvdb::Vec3DMetadata(openvdb::Vec3d(spec.origin.x, spec.origin.y, spec.origin.z)));
  grid.insertMeta("rtsdf:voxel_size", openvdb::DoubleMetadata(spec.voxelSize));
  for (const auto& [k, v] : settings) {
    const std::string key = "rtsdf:" + k;
    if (const auto* text = std::get_if<std::string>(&v)) grid.insertMeta(key, openvdb::StringMetadata(*text));
    else if (const auto* real = std::get_if<double>(&v)) grid.insertMeta(key, openvdb::DoubleMetadata(*real));
    else if (const auto* i32 = std::get_if<int>(&v)) grid.insertMeta(key, openvdb::Int32Metadata(*i32));
    else grid.insertMeta(key, openvdb::Int64Metadata(std::get<std::int64_t>(v)));
  }
}

std::string recordedScenePath(const std::string& scene) {
  if (scene.empty() || scene.front() == '<') return scene; // a scene in memory has no file
  std::error_code ec;
  const fs::path absolute = fs::absolute(scene, ec);
  return ec ? scene : absolute.lexically_normal().string();
}

std::optional<double> numberMeta(const openvdb::GridBase& grid, const std::string& key) {
  const openvdb::Metadata::ConstPtr m = grid[key];
  if (!m) return std::nullopt;
  if (const auto d = grid.getMetadata<openvdb::DoubleMetadata>(key)) return d->value();
  if (const auto f = grid.getMetadata<openvdb::FloatMetadata>(key)) return double(f->value());
  if (const auto i = grid.getMetadata<openvdb::Int32Metadata>(key)) return double(i->value());
  if (const auto l = grid.getMetadata<openvdb::Int64Metadata>(key)) return double(l->value());
  if (const auto t = grid.getMetadata<openvdb::StringMetadata>(key)) {
    // Older files stored numbers as text ("0.3", "inf").
    const std::string& text = t->value();
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size()) return v;
  }
  return std::nullopt;
}

std::string stringMeta(const openvdb::GridBase& grid, const std::string& key) {
  const openvdb::Metadata::ConstPtr m = grid[key];
  return m ? m->str() : std::string();
}

UpAxis upAxisOf(const openvdb::GridBase& grid) {
  const std::string up = stringMeta(grid, "rtsdf:up");
  if (up.empty() || up == "y") return UpAxis::Y;
  if (up == "z") return UpAxis::Z;
  throw Error(fmt::format("grid '{}': rtsdf:up is '{}' (y or z)", oneLine(grid.getName(), 80), oneLine(up, 80)));
}

FloatGrid::Ptr inSceneFrame(const FloatGrid::Ptr& grid) {
  if (upAxisOf(*grid) == UpAxis::Y) return grid;
  FloatGrid::Ptr copy = grid->copy(); // shares the tree
  auto xf = grid->transform().copy();
  xf->postMult(upTurn(true));
  copy->setTransform(xf);
  copy->insertMeta("rtsdf:up", openvdb::StringMetadata("y"));
  return copy;
}

GridSpec gridSpecOf(const FloatGrid& grid) {
  const auto dims = grid.getMetadata<openvdb::Vec3IMetadata>("rtsdf:dims");
  const auto origin = grid.getMetadata<openvdb::Vec3DMetadata>("rtsdf:origin");
  const auto h = grid.getMetadata<openvdb::DoubleMetadata>("rtsdf:voxel_size");
  if (!dims || !origin || !h)
    throw Error(fmt::format("grid '{}' has no rtsdf:dims/origin/voxel_size metadata", grid.getName()));
  GridSpec spec;
  spec.dims = glm::ivec3(dims->value().x(), dims->value().y(), dims->value().z());
  spec.origin = glm::dvec3(origin->value().x(), origin->value().y(), origin->value().z());
  spec.voxelSize = h->value();
  if (!(spec.voxelSize > 0) || spec.dims.x < 1 || spec.dims.y < 1 || spec.dims.z < 1)
    throw Error(fmt::format("grid '{}': invalid rtsdf layout metadata", grid.getName()));
  if (*makeTransform(spec, upAxisOf(grid)) != grid.transform())
    throw Error(fmt::format("grid '{}': transform disagrees with its rtsdf layout metadata", grid.getName()));
  return spec;
}

FloatGrid::Ptr makeFogGrid(const FloatGrid& levelSet) {
  FloatGrid::Ptr fog = levelSet.deepCopy();
  openvdb::tools::sdfToFogVolume(*fog);
  fog->setName("density");
  return fog;
}

namespace {

/// OpenVDB's writer does not check its stream: a full disk leaves a truncated file and no error. Read @a tmp back
/// whole and compare its grids with @a written (names, types, active voxels).
void requireReadsBack(const fs::path& tmp, const openvdb::GridPtrVec& written, const fs::path& path) {
  const auto fail = [&](const std::string& why) {
    return Error(fmt::format("{}: cannot write .vdb: the file written does not read back ({}): is the disk full?",
                             path.string(), why));
  };
  openvdb::GridPtrVecPtr back;
  try {
    openvdb::io::File file(tmp.string());
    file.open(false); // no delayed loading: every voxel is read now
    back = file.getGrids();
    file.close();
  } catch (const std::exception& e) {
    throw fail(oneLine(e.what(), 120));
  }
  if (!back || back->size() != written.size())
    throw fail(fmt::format("{} grids of {}", back ? back->size() : 0, written.size()));
  // The file lists its grids by name, not in the order they were written.
  for (const auto& w : written) {
    const auto same = [&](const openvdb::GridBase::Ptr& g) {
      return g->getName() == w->getName() && g->type() == w->type() && g->activeVoxelCount() == w->activeVoxelCount();
    };
    if (std::none_of(back->begin(), back->end(), same)) throw fail(fmt::format("grid '{}' differs", w->getName()));
  }
}

/// Shallow copies of @a grids as they are written to @a path: turned to @a up, the scene's path relative to the file.
openvdb::GridPtrVec asWritten(const openvdb::GridPtrVec& grids, const fs::path& path, UpAxis up) {
  openvdb::GridPtrVec out;
  for (const auto& g : grids) {
    openvdb::GridBase::Ptr copy = g->copyGrid(); // shares the tree and the transform
    if (up == UpAxis::Z && upAxisOf(*g) == UpAxis::Y) {
      auto xf = g->transform().copy();
      xf->postMult(upTurn(false));
      copy->setTransform(xf);
      copy->insertMeta("rtsdf:up", openvdb::StringMetadata("z"));
    }
    const fs::path scene = stringMeta(*g, "rtsdf:scene");
    if (scene.is_absolute()) {
      std::error_code ec;
      const fs::path folder = fs::absolute(path, ec).parent_path().lexically_normal();
      if (!ec)
        copy->insertMeta("rtsdf:scene_relative",
                         openvdb::StringMetadata(scene.lexically_relative(folder).generic_string()));
    }
    out.push_back(copy);
  }
  return out;
}

} // namespace

void writeVdb(const fs::path& path, const openvdb::GridPtrVec& grids, const VdbWriteOptions& options) {
  ensureOpenVdb();
  if (grids.empty()) throw Error(fmt::format("{}: no grids to write", path.string()));
  for (const auto& g : grids)
    if (!g) throw Error(fmt::format("{}: cannot write a null grid", path.string()));
  const openvdb::GridPtrVec written = asWritten(grids, path, options.up);
  writeFileAtomically(path, [&](const fs::path& tmp) {
    try {
      for (const auto& g : written) g->setSaveFloatAsHalf(options.halfFloat);
      openvdb::io::File file(tmp.string());
      std::uint32_t flags = openvdb::io::COMPRESS_ACTIVE_MASK;
      if (options.compression == VdbCompression::Zip) flags |= openvdb::io::COMPRESS_ZIP;
      if (options.compression == VdbCompression::Blosc) flags |= openvdb::io::COMPRESS_BLOSC;
      file.setCompression(flags);
      file.write(written);
      file.close();
    } catch (const openvdb::Exception& e) {
      throw Error(fmt::format("{}: cannot write .vdb: {}", path.string(), e.what()));
    }
    requireReadsBack(tmp, written, path);
  });
}

} // namespace rtsdf
