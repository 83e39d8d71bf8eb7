#include "grid/GridSampling.h"

#include <openvdb/math/Stencils.h>
#include <openvdb/tools/Interpolation.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cmath>
#include <limits>

namespace rtsdf {
namespace {

template <class Real> bool finitePoint(const Real* p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

/// Points in chunks of a few thousand: each chunk has its own accessor (they cache the tree path, not thread-safe).
constexpr std::size_t kChunk = 4096;

} // namespace

template <class Real>
void sampleWorldPoints(const openvdb::FloatGrid& grid, const Real* points, std::size_t count, Real* values) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kChunk), [&](const tbb::blocked_range<std::size_t>& r) {
    // The sampler keeps a reference to the accessor: it must outlive the sampler.
    const openvdb::FloatGrid::ConstAccessor accessor = grid.getConstAccessor();
    const openvdb::tools::GridSampler<openvdb::FloatGrid::ConstAccessor, openvdb::tools::BoxSampler> sampler(
        accessor, grid.transform());
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Real* p = points + 3 * i;
      values[i] = finitePoint(p) ? Real(sampler.wsSample(openvdb::Vec3d(p[0], p[1], p[2])))
                                 : std::numeric_limits<Real>::quiet_NaN();
    }
  });
}

template <class Real>
void gradientWorldPoints(const openvdb::FloatGrid& grid, const Real* points, std::size_t count, Real* gradients) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, kChunk), [&](const tbb::blocked_range<std::size_t>& r) {
    openvdb::math::BoxStencil<openvdb::FloatGrid> stencil(grid);
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      const Real* p = points + 3 * i;
      Real* g = gradients + 3 * i;
      if (!finitePoint(p)) {
        g[0] = g[1] = g[2] = std::numeric_limits<Real>::quiet_NaN();
        continue;
      }
      const openvdb::Vec3d index = grid.transform().worldToIndex(openvdb::Vec3d(p[0], p[1], p[2]));
      stencil.moveTo(index);
      const openvdb::Vec3f d = stencil.gradient(openvdb::Vec3f(index));
      g[0] = Real(d[0]);
      g[1] = Real(d[1]);
      g[2] = Real(d[2]);
    }
  });
}

template void sampleWorldPoints<float>(const openvdb::FloatGrid&, const float*, std::size_t, float*);
template void sampleWorldPoints<double>(const openvdb::FloatGrid&, const double*, std::size_t, double*);
template void gradientWorldPoints<float>(const openvdb::FloatGrid&, const float*, std::size_t, float*);
template void gradientWorldPoints<double>(const openvdb::FloatGrid&, const double*, std::size_t, double*);

} // namespace rtsdf
