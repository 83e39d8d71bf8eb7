#include "sdf/mask/MaskCpu.h"

#include "sdf/mask/MaskPasses.h"

#include <tbb/parallel_sort.h>

#include <cmath>

namespace rtsdf {
using namespace gpu::shared;

MaskDecisions maskDecisionsCpu(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs,
                               std::vector<glm::uvec2> state, const MaskParams& p, const std::vector<MovedBox>& moved,
                               const ChangedBox& changed, const MaskRegion* visit) {
  MaskDecisions out;
  const std::vector<glm::ivec2> ranges = maskFineRanges(cs, fs);
  const bool none = visit && glm::any(glm::greaterThan(glm::uvec3(visit->lo), glm::uvec3(visit->hi)));
  const glm::ivec3 lo = visit && !none ? glm::ivec3(glm::uvec3(visit->lo)) : glm::ivec3(0);
  const glm::ivec3 hi = none ? glm::ivec3(-1) : visit ? glm::min(glm::ivec3(glm::uvec3(visit->hi)), cs.dims - 1)
                                                       : cs.dims - 1;
  for (int z = lo.z; z <= hi.z; ++z)
    for (int y = lo.y; y <= hi.y; ++y)
      for (int x = lo.x; x <= hi.x; ++x) {
        const auto i = std::uint32_t(cs.linear(x, y, z));
        const float c = coarse[i];
        if (!(std::fabs(c) <= p.band)) {
          if (state[i].x != kNotInBand) state[i] = glm::uvec2(kNotInBand); // left the band
          continue;
        }
        const bool fresh = startsFresh(p, state[i]);
        if (!withinViewReach(p, {x, y, z})) {
          if (outOfViewRewritten(p, state[i], {x, y, z}, changed.lo, changed.hi))
            appendFineVoxelsUnder(ranges, cs.dims, {x, y, z}, kMaskOutOfView, out.rewritten);
          state[i] = {p.frame, 0u};
          continue;
        }
        bool nearMoved = false;
        for (std::size_t b = 0; b < moved.size() && !fresh && !nearMoved; ++b)
          nearMoved = movedWithinReach(p, {x, y, z}, c, moved[b]);
        const std::uint32_t before = state[i].y;
        const bool refined = refinesThisFrame(p, fresh, nearMoved, before, i);
        state[i] = {p.frame, refinementsAfter(p, refined, fresh, nearMoved, before)};
        if (refined) appendFineVoxelsUnder(ranges, cs.dims, {x, y, z}, fresh ? kMaskFineFresh : 0u, out.refined);
        if (refinedForMotionAlone(p, fresh, nearMoved, before, i)) out.movedOnly.push_back(i);
      }
  tbb::parallel_sort(out.refined.begin(), out.refined.end());
  tbb::parallel_sort(out.rewritten.begin(), out.rewritten.end());
  out.state = std::move(state);
  return out;
}

std::vector<std::uint32_t> bandBricksCpu(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs,
                                         double band) {
  std::vector<std::uint32_t> bricks;
  if (band <= 0.0) return bricks;
  const std::vector<glm::ivec2> ranges = maskFineRanges(cs, fs);
  const glm::ivec3 bd = (fs.dims + (RTSDF_BRICK - 1)) / RTSDF_BRICK;
  std::vector<char> needed(std::size_t(bd.x) * bd.y * bd.z, 0);
  for (int z = 0; z < cs.dims.z; ++z)
    for (int y = 0; y < cs.dims.y; ++y)
      for (int x = 0; x < cs.dims.x; ++x) {
        if (!(std::fabs(coarse[cs.linear(x, y, z)]) <= float(band))) continue;
        const glm::ivec2 rx = ranges[x], ry = ranges[cs.dims.x + y], rz = ranges[cs.dims.x + cs.dims.y + z];
        if (rx.x > rx.y || ry.x > ry.y || rz.x > rz.y) continue;
        for (int bz = rz.x / RTSDF_BRICK; bz <= rz.y / RTSDF_BRICK; ++bz)
          for (int by = ry.x / RTSDF_BRICK; by <= ry.y / RTSDF_BRICK; ++by)
            for (int bx = rx.x / RTSDF_BRICK; bx <= rx.y / RTSDF_BRICK; ++bx)
              needed[(std::size_t(bz) * bd.y + by) * bd.x + bx] = 1;
      }
  for (std::size_t b = 0; b < needed.size(); ++b)
    if (needed[b]) bricks.push_back(std::uint32_t(b));
  return bricks;
}

} // namespace rtsdf
