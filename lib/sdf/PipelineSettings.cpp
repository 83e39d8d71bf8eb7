#include "sdf/PipelineSettings.h"

#include "sdf/coarse/CoarseParams.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace rtsdf {

void PipelineSettings::validate() const {
  validateKnobs(*this);
  if (fineRes < coarseRes)
    throw SettingError("fine resolution", fmt::format("fine resolution {} must be in [the coarse resolution ({}), "
                                                      "1024]", fineRes, coarseRes));
}

int settleFramesFor(const PipelineSettings& s) {
  if (s.fullRecompute) return 0;
  if (s.settleFrames > 0) return s.settleFrames;
  if (s.mode == RefineMode::Closest) return s.rays == 0 ? 1 : 4;
  return 32;
}

int refreshPeriodFor(const PipelineSettings& s) {
  if (s.refreshPeriod >= 0) return s.refreshPeriod;
  return s.mode == RefineMode::Closest ? 0 : 8;
}

PipelineSettings pipelinePreset(Preset preset) {
  PipelineSettings s;
  if (preset == Preset::Paper) {
    s.coarseRes = 128;
    s.fineRes = 256;
    s.mode = RefineMode::Rays;
    s.rays = 10;
    s.alpha = 0.95;
    s.coarseMethod = CoarseMethod::OnePlusJfa;
  }
  return s;
}

double fineVoxelSize(const Bounds& bounds, const PipelineSettings& s) {
  return bounds.maxExtent() / std::max(1, s.fineRes);
}

PipelineSettings withLengthsResolved(const PipelineSettings& s, double voxelSize) {
  PipelineSettings r = s;
  r.band = s.band.sceneUnits(voxelSize);
  r.padding = s.padding.sceneUnits(voxelSize);
  return r;
}

PipelineSettings withLengthsResolved(const PipelineSettings& s, const Bounds& bounds) {
  return withLengthsResolved(s, fineVoxelSize(bounds, s));
}

void requireBandOfAVoxel(double band, double voxelSize) {
  if (band > 0.0 && band < voxelSize * (1.0 - 1e-9))
    throw SettingError("band", fmt::format("band {:g} is {:.3g} voxels (voxel size {:g}): a level set needs at least "
                                           "one voxel on each side of the surface; give at least {:g} or 1vox",
                                           band, band / voxelSize, voxelSize, voxelSize));
}

double defaultPadding(const Bounds& bounds, double band) { return std::min(band, 0.25 * bounds.maxExtent()); }

double pipelinePadding(const Bounds& bounds, const PipelineSettings& given) {
  const PipelineSettings s = withLengthsResolved(given, bounds);
  if (s.padding < 0.0) return defaultPadding(bounds, s.band);
  // A margin wider than the scene models mostly empty space (and at 1e30 overflows the grid's size).
  const double longest = bounds.maxExtent();
  if (longest > 0.0 && s.padding > longest)
    throw SettingError("padding", fmt::format("padding {:g} is more than the scene's longest side ({:g}): at most "
                                              "{:g}", double(s.padding), longest, longest));
  return s.padding;
}

void requireBandWithin(const GridSpec& grid, double band) {
  const double d = grid.diagonal();
  if (band > d)
    throw SettingError("band", fmt::format("band {:g} is longer than the grid's diagonal ({:g}): every voxel would be "
                                           "in it; at most {:g} (for an exact field everywhere, ask for the full "
                                           "domain)", band, d, d));
}

void requireBetaWithin(const GridSpec& coarse, double beta) {
  const double d = coarse.diagonal();
  if (beta > d)
    throw SettingError("beta", fmt::format("beta {:g} is longer than the coarse grid's diagonal ({:g}): the shell "
                                           "would swallow every voxel; at most {:g} (default: half a coarse voxel, "
                                           "{:g})", beta, d, d, 0.5 * coarse.voxelSize));
}

GridSpec coarseGridOver(const GridSpec& fine, const Bounds& bounds, int coarseRes, double padding) {
  GridSpec c;
  // The fine and coarse voxel (0,0,0) share their corner: the ray mask maps coarse to fine voxels by index.
  c.origin = fine.origin;
  c.voxelSize = GridSpec::fromBounds(bounds, coarseRes, padding).voxelSize;
  const glm::dvec3 ext = glm::dvec3(fine.dims) * fine.voxelSize;
  for (int a = 0; a < 3; ++a) c.dims[a] = std::max(1, int(std::ceil(ext[a] / c.voxelSize - 1e-9)));
  return c;
}

void requirePipelineGrids(const GridSpec& coarse, const GridSpec& fine, const PipelineSettings& s) {
  // No band limit here: a ray-mask band beyond the grid masks every voxel, a knob's legitimate extreme.
  requireBetaWithin(coarse, s.beta);
  for (int a = 0; a < 3; ++a)
    if (fine.dims[a] > gpu::shared::kMaxSeedAxis)
      throw SettingError("fine resolution", fmt::format("fine grid {}: more than {} voxels along an axis (lower the "
                                                        "fine resolution)", fine.describe(), gpu::shared::kMaxSeedAxis));
}

std::pair<GridSpec, GridSpec> pipelineGrids(const Bounds& bounds, const PipelineSettings& given) {
  given.validate();
  const PipelineSettings s = withLengthsResolved(given, bounds);
  const double padding = pipelinePadding(bounds, s);
  const GridSpec fine = GridSpec::fromBounds(bounds, s.fineRes, padding);
  const GridSpec coarse = coarseGridOver(fine, bounds, s.coarseRes, padding);
  requirePipelineGrids(coarse, fine, s);
  return {coarse, fine};
}

} // namespace rtsdf
