#include "jobs/Compare.h"

#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cmath>

namespace rtsdf {
namespace fs = std::filesystem;
using openvdb::FloatGrid;

void CompareOptions::validate() const {
  if (b.empty() == !against)
    throw SettingError("anchor", against ? "compare with a second file or with an anchor, not both"
                                         : "compare needs a second file or an anchor to bake");
  if (!scene.empty() && !against) throw SettingError("scene", "a scene is only used to bake an anchor");
}

namespace {

std::string bboxText(const openvdb::BBoxd& b) {
  return fmt::format("({:.4g}, {:.4g}, {:.4g}) to ({:.4g}, {:.4g}, {:.4g})", b.min().x(), b.min().y(), b.min().z(),
                     b.max().x(), b.max().y(), b.max().z());
}

/// The world box of a grid's active voxels, grown by half a voxel (the voxels' extent, not their centres).
openvdb::BBoxd activeWorldBox(const FloatGrid& g) {
  openvdb::CoordBBox ib = g.evalActiveVoxelBoundingBox();
  const openvdb::BBoxd box(ib.min().asVec3d() - 0.5, ib.max().asVec3d() + 0.5);
  return g.transform().indexToWorld(box);
}

/// Refuse comparisons that would print nothing: an empty level set, no overlap, no voxel defined in both.
void requireSharedVoxels(const FloatGrid& a, const FloatGrid& b, const FileComparison& c) {
  if (c.activeA == 0) throw Error(fmt::format("{}: the level set has no active voxels", c.nameA));
  if (c.activeB == 0) throw Error(fmt::format("{}: the level set has no active voxels", c.nameB));
  if (c.error.voxels > 0) return;
  const openvdb::BBoxd ba = activeWorldBox(a), bb = activeWorldBox(b);
  if (!ba.hasOverlap(bb))
    throw Error(fmt::format("{} and {} do not overlap: A's active voxels cover {}, B's cover {}", c.nameA, c.nameB,
                            bboxText(ba), bboxText(bb)));
  throw Error(fmt::format("{} and {} share no voxel active in both{}", c.nameA, c.nameB,
                          c.alignment.empty() ? "" : " (" + c.alignment + ")"));
}

FileComparison compareGrids(const FloatGrid& a, const FloatGrid& b, std::string nameA, std::string nameB) {
  FileComparison c;
  c.nameA = std::move(nameA);
  c.nameB = std::move(nameB);
  c.activeA = a.activeVoxelCount();
  c.activeB = b.activeVoxelCount();
  c.alignment = matchGrids(a, b).description;
  c.error = compareFields(a, b);
  c.voxelSize = voxelUnit(a);
  requireSharedVoxels(a, b, c);
  return c;
}

std::string stringMeta(const FloatGrid& g, const std::string& key) {
  const auto m = g.getMetadata<openvdb::StringMetadata>(key);
  return m ? m->value() : std::string();
}

/// The anchor's scene: as given, else A's rtsdf:scene as written (relative to the working folder), else beside A.
std::string anchorScene(const FloatGrid& a, const CompareOptions& o) {
  if (!o.scene.empty()) return o.scene;
  const std::string recorded = stringMeta(a, "rtsdf:scene");
  if (recorded.empty())
    throw SettingError("scene", fmt::format("{} records no scene (no rtsdf:scene metadata): give the scene to bake "
                                            "the anchor from", o.a.string()));
  std::error_code ec;
  if (fs::exists(recorded, ec)) return recorded;
  const fs::path beside = o.a.parent_path() / recorded;
  if (fs::path(recorded).is_relative() && fs::exists(beside, ec)) return beside.string();
  throw SettingError("scene", fmt::format("{} records the scene '{}', which is not found: give the scene to bake the "
                                          "anchor from", o.a.string(), recorded));
}

/// A's voxels: its rtsdf layout, or for a file from another tool the box of its active voxels on its lattice.
GridSpec anchorGrid(const FloatGrid& a) {
  if (a.getMetadata<openvdb::Vec3IMetadata>("rtsdf:dims")) return gridSpecOf(a);
  const openvdb::CoordBBox box = a.evalActiveVoxelBoundingBox();
  GridSpec spec;
  spec.voxelSize = voxelUnit(a);
  const openvdb::Vec3d first = a.indexToWorld(box.min());
  spec.origin = glm::dvec3(first.x(), first.y(), first.z()) - 0.5 * spec.voxelSize;
  spec.dims = glm::ivec3(box.dim().x(), box.dim().y(), box.dim().z());
  return spec;
}

/// The bake of the anchor on A's voxels, band and moment.
BakeOptions anchorBake(const FloatGrid& a, const CompareOptions& o) {
  BakeOptions bo;
  bo.scene = anchorScene(a, o);
  bo.method = *o.against == CompareAnchor::Exact ? BakeMethod::Exact : BakeMethod::OpenVdb;
  bo.grid = anchorGrid(a);
  // A level set's background is its band's half-width; an exact full-domain file records an infinite band.
  const std::string band = stringMeta(a, "rtsdf:band");
  const double recorded = band.empty() ? NAN : std::strtod(band.c_str(), nullptr);
  bo.fullDomain = std::isinf(recorded) && bo.method == BakeMethod::Exact;
  bo.pipeline.band = recorded > 0.0 && std::isfinite(recorded) ? recorded : double(a.background());
  const std::string time = stringMeta(a, "rtsdf:time");
  bo.time = time.empty() ? 0.0 : std::strtod(time.c_str(), nullptr);
  return bo;
}

} // namespace

FileComparison compare(const CompareOptions& o, const JobControl& control) {
  o.validate();
  const FloatGrid::Ptr a = readLevelSet(o.a);
  if (!o.against) return compareGrids(*a, *readLevelSet(o.b), o.a.string(), o.b.string());
  // Before baking: an empty level set has no voxels to bake the anchor on.
  if (a->activeVoxelCount() == 0) throw Error(fmt::format("{}: the level set has no active voxels", o.a.string()));
  const BakeOptions bo = anchorBake(*a, o);
  spdlog::info("baking the {} anchor of {} on {}, band {:.6g}", toString(bo.method), bo.scene, bo.grid->describe(),
               double(bo.pipeline.band));
  control.report("baking the anchor", 0, 1);
  const BakeResult anchor = bake(bo, control);
  control.report("baking the anchor", 1, 1);
  return compareGrids(*a, *anchor.grid, o.a.string(),
                      fmt::format("{} bake of {} on A's voxels (band {:.6g}{}, time {})", toString(bo.method),
                                  bo.scene, double(bo.pipeline.band), bo.fullDomain ? ", full domain" : "", bo.time));
}

FileComparison compareFiles(const fs::path& a, const fs::path& b) {
  CompareOptions o;
  o.a = a;
  o.b = b;
  return compare(o);
}

std::string FileComparison::report() const {
  const FieldError& e = error;
  std::string t = fmt::format("A          {} ({} active voxels)\n", nameA, activeA);
  t += fmt::format("B          {} ({} active voxels)\n", nameB, activeB);
  t += fmt::format("voxel size {}\n", voxelSize);
  if (!alignment.empty()) t += fmt::format("voxels     {}\n", alignment);
  t += fmt::format("compared   {} voxels active in both ({} only in A, {} only in B)\n", e.voxels, e.onlyInA,
                   e.onlyInB);
  t += fmt::format("|A - B|    mean {:.4f}, RMS {:.4f}, max {:.4f} voxels\n", e.meanAbs, e.rms, e.maxAbs);
  t += fmt::format("sign       {} voxels disagree ({:.4f}%)\n", e.signMismatches, 100.0 * e.signErrorRate());
  return t;
}

} // namespace rtsdf
