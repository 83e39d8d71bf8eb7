#include "jobs/Compare.h"

#include "grid/VdbIO.h"
#include "jobs/Bake.h"
#include "jobs/CascadeBake.h"
#include "util/Error.h"
#include "util/Text.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <vector>

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

/// One line when A and B look like fields of different scenes: they record different scenes, or their active
/// voxels' boxes overlap by less than half of the smaller box.
std::string differentScenes(const FloatGrid& a, const FloatGrid& b, const FileComparison& c) {
  const fs::path sa = stringMeta(a, "rtsdf:scene"), sb = stringMeta(b, "rtsdf:scene");
  if (!sa.empty() && !sb.empty() && sa.lexically_normal() != sb.lexically_normal())
    return fmt::format("{} and {} are fields of different scenes ({} and {}): their differences measure the scenes, "
                       "not the methods", c.nameA, c.nameB, oneLine(sa.string(), 60), oneLine(sb.string(), 60));
  const openvdb::BBoxd ba = activeWorldBox(a), bb = activeWorldBox(b);
  if (!ba.hasOverlap(bb)) return {}; // requireSharedVoxels has refused it: nothing was compared
  const openvdb::BBoxd both(openvdb::math::maxComponent(ba.min(), bb.min()),
                            openvdb::math::minComponent(ba.max(), bb.max()));
  const double overlap = both.volume() / std::min(ba.volume(), bb.volume());
  if (overlap >= 0.5) return {};
  return fmt::format("{} and {} may be fields of different scenes: their active voxels' boxes overlap by {:.0f}% of "
                     "the smaller (A {}, B {})", c.nameA, c.nameB, 100.0 * overlap, bboxText(ba), bboxText(bb));
}

/// @a anchored: B was baked from A's scene (no warning about different scenes).
FileComparison compareGrids(const FloatGrid& a, const FloatGrid& b, std::string nameA, std::string nameB,
                            bool anchored) {
  FileComparison c;
  c.nameA = std::move(nameA);
  c.nameB = std::move(nameB);
  c.activeA = a.activeVoxelCount();
  c.activeB = b.activeVoxelCount();
  c.alignment = matchGrids(a, b).description;
  c.error = compareFields(a, b);
  c.voxelSize = voxelUnit(a);
  requireSharedVoxels(a, b, c);
  if (!anchored) c.warning = differentScenes(a, b, c);
  if (!c.warning.empty()) spdlog::warn("{}", c.warning);
  return c;
}

/// The anchor's scene: as given; else A's rtsdf:scene, an absolute path; else rtsdf:scene_relative beside A; else
/// (older files recorded the path as given to bake) rtsdf:scene as written, then beside A.
std::string anchorScene(const FloatGrid& a, const CompareOptions& o) {
  if (!o.scene.empty()) return o.scene;
  const std::string recorded = stringMeta(a, "rtsdf:scene");
  if (recorded.empty())
    throw SettingError("scene", fmt::format("{} records no scene (no rtsdf:scene metadata): give the scene to bake "
                                            "the anchor from", o.a.string()));
  std::error_code ec;
  std::vector<fs::path> tried{recorded};
  const std::string relative = stringMeta(a, "rtsdf:scene_relative");
  if (!relative.empty()) tried.push_back(o.a.parent_path() / relative);
  if (fs::path(recorded).is_relative()) tried.push_back(o.a.parent_path() / recorded);
  for (const fs::path& p : tried)
    if (fs::exists(p, ec)) return p.lexically_normal().string();
  throw SettingError("scene", fmt::format("{} records the scene '{}'{}, which is not found: give the scene to bake "
                                          "the anchor from", o.a.string(), recorded,
                                          relative.empty() ? "" : fmt::format(" ('{}' from its folder)", relative)));
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
  const double recorded = numberMeta(a, "rtsdf:band").value_or(NAN);
  bo.fullDomain = std::isinf(recorded) && bo.method == BakeMethod::Exact;
  bo.pipeline.band = recorded > 0.0 && std::isfinite(recorded) ? recorded : double(a.background());
  bo.time = numberMeta(a, "rtsdf:time").value_or(0.0);
  return bo;
}

/// A against the anchor @a o asks for, baked on A's voxels, band and moment.
FileComparison compareWithAnchor(const FloatGrid& a, const std::string& nameA, const CompareOptions& o,
                                 const JobControl& control) {
  // Before baking: an empty level set has no voxels to bake the anchor on.
  if (a.activeVoxelCount() == 0) throw Error(fmt::format("{}: the level set has no active voxels", nameA));
  const BakeOptions bo = anchorBake(a, o);
  spdlog::info("baking the {} anchor of {} on {}, band {:.6g}", toString(bo.method), bo.scene, bo.grid->describe(),
               double(bo.pipeline.band));
  control.report("baking the anchor", 0, 1);
  const BakeResult anchor = bake(bo, control);
  control.report("baking the anchor", 1, 1);
  return compareGrids(a, *anchor.grid, nameA,
                      fmt::format("{} bake of {} on A's voxels (band {:.6g}{}, time {})", toString(bo.method),
                                  bo.scene, double(bo.pipeline.band), bo.fullDomain ? ", full domain" : "", bo.time),
                      true);
}

/// Each cascade level of A against the anchor on the level's own voxels.
FileComparison compareCascade(const std::vector<FloatGrid::Ptr>& levels, const CompareOptions& o,
                              const JobControl& control) {
  if (!o.against)
    throw SettingError("anchor", fmt::format("{} holds {} cascade levels: compare it against an anchor (exact or "
                                             "openvdb), which checks each level on its own voxels", o.a.string(),
                                             levels.size()));
  std::vector<FileComparison> each;
  for (const FloatGrid::Ptr& level : levels) {
    const std::string name = fmt::format("{} ({})", o.a.string(), level->getName());
    if (level->activeVoxelCount() > 0) {
      each.push_back(compareWithAnchor(*level, name, o, control));
    } else { // a level in empty air: nothing to compare
      each.emplace_back();
      each.back().nameA = name;
      each.back().voxelSize = voxelUnit(*level);
    }
  }
  FileComparison c = each.front();
  c.levels = std::move(each);
  return c;
}

} // namespace

FileComparison compare(const CompareOptions& o, const JobControl& control) {
  o.validate();
  std::vector<FloatGrid::Ptr> levels = cascadeLevelGrids(readVdb(o.a));
  for (FloatGrid::Ptr& level : levels) level = inSceneFrame(level);
  if (!levels.empty()) return compareCascade(levels, o, control);
  const FloatGrid::Ptr a = inSceneFrame(readLevelSet(o.a, o.grid));
  if (!o.against) return compareGrids(*a, *inSceneFrame(readLevelSet(o.b, o.grid)), o.a.string(), o.b.string(),
                                        false);
  return compareWithAnchor(*a, o.a.string(), o, control);
}

FileComparison compareFiles(const fs::path& a, const fs::path& b) {
  CompareOptions o;
  o.a = a;
  o.b = b;
  return compare(o);
}

std::string FileComparison::report() const {
  if (!levels.empty()) {
    std::string t;
    for (std::size_t i = 0; i < levels.size(); ++i)
      t += fmt::format("cascade level {}\n{}", i, levels[i].activeA ? levels[i].report()
                                                                      : "no active voxel: nothing to compare\n");
    return t;
  }
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
