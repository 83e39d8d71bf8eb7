#include "metrics/FieldError.h"

#include "util/Error.h"

#include <fmt/format.h>
#include <openvdb/tools/Interpolation.h>
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
/// The split and the joins are deterministic (fixed chunks of leaves), so the same grids give the same sums to the
/// last bit whatever the threads' timing.
template <class Visit>
Accum accumulateActiveVoxels(const openvdb::FloatTree& tree, const Visit& visit) {
  openvdb::tree::LeafManager<const openvdb::FloatTree> leaves(tree);
  return tbb::parallel_deterministic_reduce(
      leaves.leafRange(/*grainsize=*/32), Accum{},
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

namespace {

std::string vec3(const openvdb::Vec3d& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z()); }

/// B's voxels that A does not cover: those whose centre lies in no active voxel of A.
std::uint64_t resampledOnlyInB(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  const auto& xa = a.transform();
  const auto& xb = b.transform();
  return accumulateActiveVoxels(b.tree(), [&xa, &xb, aAcc = a.getConstAccessor()](const openvdb::Coord& c, float,
                                                                                    Accum& acc) {
           const openvdb::Coord ca = openvdb::Coord::round(xa.worldToIndex(xb.indexToWorld(c)));
           if (!aAcc.isValueOn(ca)) ++acc.onlyA;
         }).onlyA;
}

/// B sampled trilinearly at A's voxel centres, where all 8 voxels of the stencil are active in B.
Accum accumulateResampled(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b, double h) {
  const auto& xa = a.transform();
  const auto& xb = b.transform();
  return accumulateActiveVoxels(a.tree(), [&xa, &xb, h, bAcc = b.getConstAccessor()](const openvdb::Coord& c,
                                                                                      float av, Accum& acc) {
    const openvdb::Vec3d p = xb.worldToIndex(xa.indexToWorld(c));
    const openvdb::Coord lo = openvdb::Coord::floor(p);
    for (int n = 0; n < 8; ++n)
      if (!bAcc.isValueOn(lo.offsetBy(n & 1, (n >> 1) & 1, (n >> 2) & 1))) {
        ++acc.onlyA;
        return;
      }
    acc.add(av, openvdb::tools::BoxSampler::sample(bAcc, p), h);
  });
}

} // namespace

double voxelUnit(const openvdb::FloatGrid& g) {
  return g.hasUniformVoxels() ? g.voxelSize()[0] : std::cbrt(g.transform().voxelVolume(openvdb::Vec3d(0.0)));
}

GridMatch matchGrids(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  GridMatch m;
  const auto& xa = a.transform();
  const auto& xb = b.transform();
  if (xa == xb) return m;
  const openvdb::Vec3d s = xb.worldToIndex(xa.indexToWorld(openvdb::Vec3d(0.0)));
  // The same lattice: every unit step in A is the same unit step in B, and the offset is whole voxels.
  constexpr double kTolerance = 1e-6;
  bool lattice = xa.isLinear() && xb.isLinear();
  for (int axis = 0; axis < 3 && lattice; ++axis) {
    openvdb::Vec3d e(0.0);
    e[axis] = 1.0;
    lattice = (xb.worldToIndex(xa.indexToWorld(e)) - s - e).length() < kTolerance;
  }
  const openvdb::Coord shift = openvdb::Coord::round(s);
  if (lattice && (s - shift.asVec3d()).length() < kTolerance) {
    m.alignment = GridAlignment::Shifted;
    m.shift = shift;
    m.description = fmt::format("B's voxels are A's shifted by ({}, {}, {}) voxels: compared without resampling",
                                shift.x(), shift.y(), shift.z());
    return m;
  }
  m.alignment = GridAlignment::Resampled;
  // Say why: another voxel size, or the same size on a lattice offset by a fraction of a voxel.
  const std::string why = lattice ? fmt::format("the same voxel size ({:.6g}) on a lattice offset by a fraction of a "
                                                "voxel: A's voxel (0,0,0) is at B's index {}", voxelUnit(a), vec3(s))
                                  : fmt::format("voxel size {:.6g} vs {:.6g}, A's voxel (0,0,0) at B's index {}",
                                                voxelUnit(a), voxelUnit(b), vec3(s));
  m.description = fmt::format("B resampled at A's voxel centres by trilinear interpolation (OpenVDB BoxSampler, where "
                              "all 8 neighbours are active in B): {}", why);
  return m;
}

FieldError compareFields(const openvdb::FloatGrid& a, const openvdb::FloatGrid& b) {
  const double h = voxelUnit(a);
  const GridMatch match = matchGrids(a, b);
  if (match.alignment == GridAlignment::Resampled) {
    FieldError e = finish(accumulateResampled(a, b, h));
    e.onlyInB = resampledOnlyInB(a, b);
    e.alignment = match.alignment;
    return e;
  }
  const Accum acc = accumulateActiveVoxels(
      a.tree(), [h, shift = match.shift, bAcc = b.getConstAccessor()](const openvdb::Coord& c, float av, Accum& acc) {
        float bv;
        if (bAcc.probeValue(c + shift, bv)) acc.add(av, bv, h);
        else ++acc.onlyA;
      });
  FieldError e = finish(acc);
  e.onlyInB = b.activeVoxelCount() - e.voxels;
  e.alignment = match.alignment;
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
