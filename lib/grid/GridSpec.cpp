#include "grid/GridSpec.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <cmath>

namespace rtsdf {

std::string GridSpec::describe() const {
  return fmt::format("{}x{}x{} voxels of {:.6g} from ({:.6g}, {:.6g}, {:.6g})", dims.x, dims.y, dims.z, voxelSize,
                     origin.x, origin.y, origin.z);
}

GridSpec GridSpec::fromBounds(const Bounds& bounds, int resolution, double padding) {
  if (bounds.empty()) throw Error("grid: the scene has no geometry to bound");
  for (int a = 0; a < 3; ++a)
    if (!std::isfinite(bounds.min[a]) || !std::isfinite(bounds.max[a]))
      throw Error("grid: scene bounds are not finite");
  if (resolution < 1 || resolution > kMaxResolution)
    throw Error(fmt::format("grid: resolution {} is out of range [1, {}]", resolution, kMaxResolution));
  if (!std::isfinite(padding) || padding < 0.0)
    throw Error(fmt::format("grid: padding {} must be finite and >= 0", padding));

  const Bounds padded{bounds.min - padding, bounds.max + padding};
  // The voxel size follows the scene, not the padding: `resolution` voxels span the scene's longest axis.
  const double longest = bounds.maxExtent() > 0.0 ? bounds.maxExtent() : padded.maxExtent();
  if (!(longest > 0.0)) throw Error("grid: the scene has zero size and no padding: nothing to grid");
  GridSpec spec;
  spec.voxelSize = longest / resolution;
  const glm::dvec3 ext = padded.extent();
  for (int a = 0; a < 3; ++a) {
    // A tiny tolerance keeps an axis of exactly n voxels from rounding up to n+1.
    const double n = std::ceil(ext[a] / spec.voxelSize - 1e-9);
    if (!(n <= 4.0 * kMaxResolution))
      throw Error(fmt::format("grid: the padding {:g} makes axis {} {:.4g} voxels long (at most {}): lower the padding",
                              padding, "xyz"[a], n, 4 * kMaxResolution));
    spec.dims[a] = std::max(1, int(n));
  }
  spec.origin = padded.center() - 0.5 * glm::dvec3(spec.dims) * spec.voxelSize;
  return spec;
}

void checkDenseMemory(const GridSpec& spec, std::size_t bytesPerVoxel, std::uint64_t maxBytes, const std::string& what) {
  const long double need = (long double)spec.voxelCount() * bytesPerVoxel;
  if (need > (long double)maxBytes)
    throw Error(fmt::format("{}: a {}x{}x{} grid needs {:.1f} GiB, more than the {:.1f} GiB available", what,
                            spec.dims.x, spec.dims.y, spec.dims.z, double(need / (1024.0L * 1024 * 1024)),
                            double(maxBytes) / (1024.0 * 1024 * 1024)));
}

} // namespace rtsdf
