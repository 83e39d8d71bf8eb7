#include "metrics/FieldError.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <openvdb/tree/LeafManager.h>
#include <tbb/parallel_reduce.h>

#include <cmath>

namespace rtsdf {
namespace {

struct Accum {
  std::uint64_t n = 0, sign = 0, onlyA = 0;
  double sum = 0.0, sum2 = 0.0, max = 0.0;
  void add(double a, double b, double h) {
    const double e = std::fabs(a - b) / h;
    ++n;
    sum += e;
    sum2 += e * e;
    max = std::max(max, e);
    // A voxel centre on the surface has no sign to get wrong.
    const double onSurface = kOnSurfaceVoxels * h;
    if ((a < 0.0) != (b < 0.0) && std::fabs(a) > onSurface && std::fabs(b) > onSurface) ++sign;
  }
  void join(const Accum& o) {
    n += o.n; sign += o.sign; onlyA += o.onlyA; sum += o.sum; sum2 += o.sum2; max = std::max(max, o.max);
  }
};

FieldError finish(const Accum& acc) {
  FieldError e;
  e.voxels = acc.n;
  e.signMismatches = acc.sign;
  e.onlyInA = acc.onlyA;
  if (acc.n) {
    e.meanAbs = acc.sum / double(acc.n);
    e.rms = std::sqrt(acc.sum2 / double(acc.n));
    e.maxAbs = acc.max;
  }
  return e;
}

using LeafRange = openvdb::tree::LeafManager<const openvdb::FloatTree>::LeafRange;

/// Calls visit(coord, value, acc) on every active voxel of @a tree in parallel and joins the tasks' sums. Each task
/// visits with its own copy of @a visit, so value accessors it captures by value are never shared between threads.
template <class Visit>
Accum accumulateActiveVoxels(const openvdb::FloatTree& tree, const Visit& visit) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(tree);
  return tbb::parallel_reduce(
      leaves.leafRange(), Accum{},
      [&](const LeafRange& r, Accum acc) {
        Visit taskVisit = visit;
        for (auto leaf = r.begin(); leaf; ++leaf)
          for (auto it = leaf->cbeginValueOn(); it; ++it) taskVisit(it.getCoord(), *it, acc);
        return acc;
      },
      [](Accum x, const Accum& y) { x.join(y); return x; });
}

} // namespace

std::string FieldError::summary() const {
  return fmt::format("{} voxels: mean {:.4f}, RMS {:.4f}, max {:.4f} voxels; wrong sign {} ({:.4f}%)", voxels, meanAbs,
                     rms, maxAbs, signMismatches, 100.0 * signErrorRate());
}

FieldError compareFields(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  if (a.transform() != b.transform())
    throw Error(fmt::format("cannot compare grids '{}' and '{}': their transforms differ (voxel size {} vs {})",
                            a.getName(), b.getName(), a.voxelSize()[0], b.voxelSize()[0]));
  const double h = a.voxelSize()[0];
  const Accum acc = accumulateActiveVoxels(
      a.tree(), [h, bAcc = b.getConstAccessor()](const openvdb::Coord& c, float av, Accum& acc) {
        float bv;
        if (bAcc.probeValue(c, bv)) acc.add(av, bv, h);
        else ++acc.onlyA;
      });
  FieldError e = finish(acc);
  e.onlyInB = b.activeVoxelCount() - e.voxels;
  return e;
}

FieldError compareWithFunction(const openvdb::FloatGrid& field,
                               const std::function<double(const openvdb::Vec3d&)>& reference, double ignoreWithin) {
  const double h = field.voxelSize()[0];
  const auto& xf = field.transform();
  const Accum acc = accumulateActiveVoxels(field.tree(), [&](const openvdb::Coord& c, float v, Accum& acc) {
    const double ref = reference(xf.indexToWorld(c));
    if (std::fabs(ref) < ignoreWithin) return;
    acc.add(v, ref, h);
  });
  return finish(acc);
}

FieldError compareDenseWithReference(const std::vector<float>& dense, const GridSpec& spec,
                                     const openvdb::FloatGrid& reference) {
  if (dense.size() != spec.voxelCount())
    throw Error(fmt::format("cannot compare a dense field of {} values with grid '{}': {} needs {}", dense.size(),
                            reference.getName(), spec.describe(), spec.voxelCount()));
  const double h = spec.voxelSize;
  const Accum acc = accumulateActiveVoxels(reference.tree(), [&](const openvdb::Coord& c, float v, Accum& acc) {
    if (c.x() < 0 || c.y() < 0 || c.z() < 0 || c.x() >= spec.dims.x || c.y() >= spec.dims.y || c.z() >= spec.dims.z) {
      ++acc.onlyA; // counted as "only in the reference" below
      return;
    }
    acc.add(dense[spec.linear(c.x(), c.y(), c.z())], v, h);
  });
  FieldError e = finish(acc);
  e.onlyInB = e.onlyInA;
  e.onlyInA = 0;
  return e;
}

} // namespace rtsdf
