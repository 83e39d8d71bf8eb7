#include "sdf/refine/RefineCpu.h"

#include "reference/ExactSdf.h"
#include "sdf/refine/RefinePasses.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <cstring>

namespace rtsdf {
using namespace gpu::shared;

float upsampleCoarse(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs, const glm::ivec3& v) {
  const glm::vec3 originH(fs.origin);
  const glm::vec3 p = originH + (glm::vec3(v) + 0.5f) * float(fs.voxelSize);
  const glm::vec3 g = (p - glm::vec3(cs.origin)) * float(1.0 / cs.voxelSize) - 0.5f;
  const glm::ivec3 i0 = glm::clamp(glm::ivec3(glm::floor(g)), glm::ivec3(0), cs.dims - 1);
  const glm::ivec3 i1 = glm::min(i0 + 1, cs.dims - 1);
  const glm::vec3 t = glm::clamp(g - glm::vec3(i0), 0.0f, 1.0f);
  auto at = [&](int x, int y, int z) { return coarse[cs.linear(x, y, z)]; };
  const float c00 = glm::mix(at(i0.x, i0.y, i0.z), at(i1.x, i0.y, i0.z), t.x);
  const float c10 = glm::mix(at(i0.x, i1.y, i0.z), at(i1.x, i1.y, i0.z), t.x);
  const float c01 = glm::mix(at(i0.x, i0.y, i1.z), at(i1.x, i0.y, i1.z), t.x);
  const float c11 = glm::mix(at(i0.x, i1.y, i1.z), at(i1.x, i1.y, i1.z), t.x);
  return glm::mix(glm::mix(c00, c10, t.y), glm::mix(c01, c11, t.y), t.z);
}

std::vector<float> refineRaysCpu(const SceneGeometry& geometry, const std::vector<float>& coarse,
                                 const GridSpec& coarseSpec, const GridSpec& fineSpec,
                                 const std::vector<std::uint32_t>& mask, std::uint32_t rays, std::uint32_t frame,
                                 std::uint32_t seed, float beta, const ClosedPieceUnionCpu* pieces) {
  // Voxel centres in the geometry's frame, as SdfPipeline hands the grids to the GPU.
  const GridSpec cs = coarseSpec.inFrame(geometry.origin), fs = fineSpec.inFrame(geometry.origin);
  const ExactDistanceField field(geometry);
  std::vector<float> out(mask.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, mask.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      const glm::ivec3 v(mask[k] & 1023u, (mask[k] >> 10) & 1023u, (mask[k] >> 20) & 1023u);
      const auto i = std::uint32_t(fs.linear(v.x, v.y, v.z));
      const glm::vec3 p = glm::vec3(fs.origin) + (glm::vec3(v) + 0.5f) * float(fs.voxelSize);
      const float c = upsampleCoarse(coarse, cs, fs, v) + beta + 0.8660254f * float(cs.voxelSize);
      const float reach = 3.0e38f; // as refine.comp: rays are not cut short, every hit votes for the sign
      float nearest = INFINITY, front = 0.0f, back = 0.0f;
      for (std::uint32_t ray = 0; ray < rays; ++ray) {
        const std::uint32_t h = rayHash(i, frame, ray, seed);
        const float z = 1.0f - 2.0f * unitFloat(h);
        const float phi = 6.28318530718f * unitFloat(pcgHash(h));
        const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        float t;
        bool isFront;
        if (field.intersect(p, {s * std::cos(phi), s * std::sin(phi), z}, reach, t, isFront)) {
          nearest = std::min(nearest, t);
          (isFront ? front : back) += 1.0f;
        }
      }
      const float f = std::min(c, nearest);
      const bool inside = back > front || (pieces && pieces->insideAny(p));
      out[k] = inside ? -f : f;
    }
  });
  return out;
}

std::vector<float> resolveFineCpu(const std::vector<float>& coarse, const GridSpec& cs, const GridSpec& fs, float band,
                                  const std::vector<std::uint32_t>& brickSlots, const std::vector<float>& poolValues) {
  const std::vector<int> coarseOf = maskCoarseOfFine(cs, fs);
  const glm::ivec3 bd = (fs.dims + (RTSDF_BRICK - 1)) / RTSDF_BRICK;
  std::vector<float> out(fs.voxelCount());
  tbb::parallel_for(0, fs.dims.z, [&](int z) {
    for (int y = 0; y < fs.dims.y; ++y)
      for (int x = 0; x < fs.dims.x; ++x) {
        const glm::ivec3 v(x, y, z);
        const glm::ivec3 c(coarseOf[x], coarseOf[fs.dims.x + y], coarseOf[fs.dims.x + fs.dims.y + z]);
        const bool masked = band > 0.0f && c.x >= 0 && c.y >= 0 && c.z >= 0 &&
                            std::fabs(coarse[cs.linear(c.x, c.y, c.z)]) <= band;
        const std::uint32_t slot = masked ? brickSlots.at(brickIndexOf(v, bd)) : kNoBrick;
        out[fs.linear(x, y, z)] = slot != kNoBrick ? poolValues.at(std::size_t(slot) * kBrickVoxels + brickLocalOf(v))
                                                   : upsampleCoarse(coarse, cs, fs, v);
      }
  });
  return out;
}

std::vector<std::uint32_t> changedBlockMarksCpu(const std::vector<float>& before, const std::vector<float>& after,
                                                const glm::ivec3& dims) {
  using namespace gpu::shared;
  const glm::ivec3 bd = coarseBlockDims(dims);
  std::vector<std::uint32_t> marks(std::size_t(bd.x) * bd.y * bd.z, 0u);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x) {
        const std::size_t i = (std::size_t(z) * dims.y + y) * dims.x + x;
        if (std::memcmp(&before[i], &after[i], sizeof(float)) == 0) continue;
        const glm::ivec3 v(x, y, z);
        marks[coarseBlockIndex(v, bd)] |= changedBlockReach(v % RTSDF_COARSE_BLOCK);
      }
  return marks;
}

std::vector<std::uint32_t> upsampleBlocksCpu(const std::vector<std::uint32_t>& marks, const glm::ivec3& dims,
                                             const gpu::shared::UpsampleBoxes& boxes) {
  using namespace gpu::shared;
  const glm::ivec3 bd = coarseBlockDims(dims);
  std::vector<std::uint32_t> listed;
  for (int z = 0; z < bd.z; ++z)
    for (int y = 0; y < bd.y; ++y)
      for (int x = 0; x < bd.x; ++x) {
        const glm::ivec3 b(x, y, z);
        bool reached = false;
        for (int k = 0; k < 27 && !reached; ++k) {
          const glm::ivec3 d(k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1), n = b + d;
          if (glm::any(glm::lessThan(n, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(n, bd))) continue;
          reached = (marks[std::size_t((n.z * bd.y + n.y) * bd.x + n.x)] & changedReachBit(-d)) != 0u;
        }
        for (int k = 0; k < boxes.count.x && k < RTSDF_UPSAMPLE_MAX_BOXES && !reached; ++k)
          reached = upsampleBlockMeetsBox(b, dims, glm::ivec3(boxes.lo[k]), glm::ivec3(boxes.hi[k]));
        if (reached) listed.push_back(std::uint32_t((z * bd.y + y) * bd.x + x));
      }
  return listed;
}

} // namespace rtsdf
