#include "sdf/coarse/CoarseCpu.h"

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <atomic>
#include <cmath>
#include <limits>
#include <optional>

namespace rtsdf {
using namespace gpu::shared;

namespace {
void checkDims(const glm::ivec3& dims) {
  if (dims.x < 1 || dims.y < 1 || dims.z < 1 || dims.x > kMaxSeedAxis || dims.y > kMaxSeedAxis || dims.z > kMaxSeedAxis)
    throw Error(fmt::format("coarse SDF: grid {}x{}x{} exceeds {} voxels per axis", dims.x, dims.y, dims.z, kMaxSeedAxis));
}
std::size_t lin(const glm::ivec3& p, const glm::ivec3& d) {
  return (std::size_t(p.z) * d.y + p.y) * d.x + p.x;
}
} // namespace

VoxelizeParams voxelizeParams(const GridSpec& spec, std::uint32_t triangleCount,
                              const std::optional<glm::ivec3>& latticeCell) {
  VoxelizeParams p{};
  const glm::ivec3 cell = latticeCell.value_or(glm::ivec3(0));
  // The lattice's corner in the spec's frame: exactly 0 where the spec's corner is that many of its voxels from it.
  const glm::dvec3 latticeOrigin = spec.origin - glm::dvec3(cell) * spec.voxelSize;
  p.originInvH = glm::vec4(glm::vec3(latticeOrigin), float(1.0 / spec.voxelSize));
  p.cornerCell = glm::ivec4(cell, 0);
  p.dims = glm::ivec4(spec.dims, 0);
  p.clipLo = glm::ivec4(0);
  p.clipHi = glm::ivec4(spec.dims - 1, 0);
  p.triangleCount = triangleCount;
  p.chunkSize = kVoxelizeChunkVoxelsCpu; // the GPU's: CoarseSdfBuilder picks it per device
  return p;
}

std::vector<glm::vec4> placeInstanceCorners(const std::vector<glm::vec4>& corners,
                                            const std::vector<VoxelizeInstance>& instances) {
  std::vector<glm::vec4> out;
  for (const VoxelizeInstance& inst : instances)
    for (std::uint32_t t = inst.firstTriangle; t < inst.firstTriangle + inst.triangleCount; ++t)
      for (int c = 0; c < 3; ++c)
        out.emplace_back(transformToFrame(inst.objectToFrame[0], inst.objectToFrame[1], inst.objectToFrame[2],
                                          glm::vec3(corners.at(3 * std::size_t(t) + c))), 1.0f);
  return out;
}

std::vector<std::uint32_t> voxelizeCpu(const std::vector<glm::vec4>& corners, const GridSpec& spec,
                                       const std::optional<glm::ivec3>& latticeCell) {
  checkDims(spec.dims);
  const std::size_t tris = corners.size() / 3;
  const VoxelizeParams params = voxelizeParams(spec, std::uint32_t(tris), latticeCell);
  const ivec3 corner(params.cornerCell);
  std::vector<std::uint32_t> seeds(spec.voxelCount(), kNoSeed);
  // Writes race only with writes of the same value (a voxel's own packed coordinate).
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, tris), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t t = r.begin(); t != r.end(); ++t) {
      const vec3 t0 = toVoxelSpace(glm::vec3(corners[3 * t]), params.originInvH);
      const vec3 t1 = toVoxelSpace(glm::vec3(corners[3 * t + 1]), params.originInvH);
      const vec3 t2 = toVoxelSpace(glm::vec3(corners[3 * t + 2]), params.originInvH);
      const ivec3 lo = voxelRangeLo(t0, t1, t2, ivec3(params.clipLo) + corner);
      const ivec3 hi = voxelRangeHi(t0, t1, t2, ivec3(params.clipHi) + corner);
      for (int z = lo.z; z <= hi.z; ++z)
        for (int y = lo.y; y <= hi.y; ++y)
          for (int x = lo.x; x <= hi.x; ++x)
            if (voxelOverlaps(ivec3(x, y, z), t0, t1, t2)) {
              const ivec3 v = ivec3(x, y, z) - corner;
              auto* slot = reinterpret_cast<std::atomic<std::uint32_t>*>(&seeds[lin(v, spec.dims)]);
              slot->store(packSeed(v), std::memory_order_relaxed);
            }
    }
  });
  return seeds;
}

std::vector<std::uint32_t> shiftSeedsCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                         const glm::ivec3& shift) {
  checkDims(dims);
  if (seeds.size() != std::size_t(dims.x) * dims.y * dims.z)
    throw Error("shiftSeedsCpu: the seeds are not the grid's");
  std::vector<std::uint32_t> out(seeds.size(), kNoSeed);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y)
      for (int x = 0; x < dims.x; ++x) {
        const ivec3 v(x, y, z), from = v + shift;
        if (glm::any(glm::lessThan(from, ivec3(0))) || glm::any(glm::greaterThanEqual(from, dims))) continue;
        const std::uint32_t seed = seeds[lin(from, dims)];
        if (seed == kNoSeed) continue;
        const ivec3 u = unpackSeed(seed) - shift;
        if (glm::all(glm::greaterThanEqual(u, ivec3(0))) && glm::all(glm::lessThan(u, dims)))
          out[lin(v, dims)] = packSeed(u);
      }
  return out;
}

std::vector<std::uint32_t> jumpFloodCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                        CoarseMethod variant) {
  checkDims(dims);
  if (!isJumpFlooding(variant)) throw Error("jumpFloodCpu: the coarse method is not a jump-flooding variant");
  std::vector<std::uint32_t> a = seeds, b(seeds.size());
  for (int step : jumpFloodSteps(dims, variant)) {
    tbb::parallel_for(tbb::blocked_range<int>(0, dims.z), [&](const tbb::blocked_range<int>& r) {
      for (int z = r.begin(); z != r.end(); ++z)
        for (int y = 0; y < dims.y; ++y)
          for (int x = 0; x < dims.x; ++x) {
            const ivec3 p(x, y, z);
            std::uint32_t best = a[lin(p, dims)];
            for (int dz = -1; dz <= 1; ++dz)
              for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                  const ivec3 q = p + step * ivec3(dx, dy, dz);
                  if (q.x < 0 || q.y < 0 || q.z < 0 || q.x >= dims.x || q.y >= dims.y || q.z >= dims.z) continue;
                  best = nearerSeed(p, best, a[lin(q, dims)]);
                }
            b[lin(p, dims)] = best;
          }
    });
    a.swap(b);
  }
  return a;
}

namespace {

/// One line of the exact feature transform, as exact_edt.comp does it (a private stack instead of the output
/// slots: the same entries in the same order).
void exactEdtLine(const std::uint32_t* src, std::uint32_t* dst, int n, std::ptrdiff_t stride, ivec3 start,
                  ivec3 step, std::vector<ivec3>& stack) {
  stack.clear(); // (seed position s, first owned position t, height g)
  for (int u = 0; u < n; ++u) {
    const std::uint32_t f = src[u * stride];
    if (f == kNoSeed) continue;
    const int gu = distance2(start + u * step, unpackSeed(f));
    while (!stack.empty()) {
      const ivec3 top = stack.back();
      if ((top.y - top.x) * (top.y - top.x) + top.z <= (top.y - u) * (top.y - u) + gu) break;
      stack.pop_back();
    }
    int w = 0;
    if (!stack.empty()) {
      w = 1 + edtSeparation(stack.back().x, stack.back().z, u, gu);
      if (w >= n) continue;
    }
    stack.push_back(ivec3(u, w, gu));
  }
  for (int u = n - 1; u >= 0; --u) {
    dst[u * stride] = stack.empty() ? kNoSeed : src[stack.back().x * stride];
    if (!stack.empty() && u == stack.back().y) stack.pop_back();
  }
}

} // namespace

std::vector<std::uint32_t> exactEdtNearestCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims) {
  checkDims(dims);
  std::vector<std::uint32_t> a = seeds, b(seeds.size());
  for (int axis = 0; axis < 3; ++axis) {
    const int na = axis == 0 ? dims.y : dims.x, nb = axis == 2 ? dims.y : dims.z;
    const std::ptrdiff_t stride = edtLineStride(dims, axis);
    const ivec3 step(axis == 0, axis == 1, axis == 2);
    tbb::parallel_for(0, nb, [&](int lb) {
      std::vector<ivec3> stack;
      for (int la = 0; la < na; ++la) {
        const ivec3 start = edtLineStart(axis, la, lb);
        const std::size_t base = lin(start, dims);
        exactEdtLine(&a[base], &b[base], dims[axis], stride, start, step, stack);
      }
    });
    a.swap(b);
  }
  return a;
}

std::vector<std::uint32_t> nearestSeedsCpu(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims,
                                           CoarseMethod method) {
  return method == CoarseMethod::Edt ? exactEdtNearestCpu(seeds, dims) : jumpFloodCpu(seeds, dims, method);
}

std::vector<float> coarseDistanceCpu(const std::vector<std::uint32_t>& nearest, const glm::ivec3& dims,
                                     float voxelSize, float beta, float emptyDistance) {
  std::vector<float> out(nearest.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nearest.size()), [&](const tbb::blocked_range<std::size_t>& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) {
      if (nearest[i] == kNoSeed) { out[i] = emptyDistance; continue; }
      const ivec3 p(int(i % dims.x), int((i / dims.x) % dims.y), int(i / (std::size_t(dims.x) * dims.y)));
      out[i] = std::sqrt(float(distance2(p, unpackSeed(nearest[i])))) * voxelSize - beta;
    }
  });
  return out;
}

namespace {

/// 1D squared distance transform of the samples f[0], f[stride], ... (Felzenszwalb and Huttenlocher 2012):
/// the lower envelope of the parabolas rooted at the finite samples. Lines with no finite sample stay +inf.
void edt1d(float* f, int n, std::ptrdiff_t stride, std::vector<float>& d, std::vector<int>& v, std::vector<double>& z) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  d.resize(n); v.resize(n); z.resize(n + 1);
  int k = -1;
  for (int q = 0; q < n; ++q) {
    const double fq = f[q * stride];
    if (!std::isfinite(fq)) continue;
    if (k < 0) {
      k = 0; v[0] = q; z[0] = -inf; z[1] = inf;
      continue;
    }
    double s = 0.0;
    while (true) {
      const int p = v[k];
      s = ((fq + double(q) * q) - (double(f[p * stride]) + double(p) * p)) / (2.0 * (q - p));
      if (s > z[k]) break;
      --k; // z[0] = -inf ends this before k < 0
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = inf;
  }
  if (k < 0) return;
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double dq = double(q - v[k]);
    d[q] = float(dq * dq + f[v[k] * stride]);
  }
  for (int q = 0; q < n; ++q) f[q * stride] = d[q];
}

} // namespace

std::vector<float> exactEdtSquared(const std::vector<std::uint32_t>& seeds, const glm::ivec3& dims) {
  std::vector<float> f(seeds.size());
  for (std::size_t i = 0; i < seeds.size(); ++i)
    f[i] = seeds[i] == kNoSeed ? std::numeric_limits<float>::infinity() : 0.0f;
  const std::ptrdiff_t sx = 1, sy = dims.x, sz = std::ptrdiff_t(dims.x) * dims.y;
  // Along x (lines indexed by y, z), then y, then z.
  tbb::parallel_for(0, dims.y * dims.z, [&](int l) {
    std::vector<float> d; std::vector<int> v; std::vector<double> z;
    edt1d(&f[std::size_t(l) * dims.x], dims.x, sx, d, v, z);
  });
  tbb::parallel_for(0, dims.x * dims.z, [&](int l) {
    std::vector<float> d; std::vector<int> v; std::vector<double> z;
    const int x = l % dims.x, zz = l / dims.x;
    edt1d(&f[std::size_t(zz) * sz + x], dims.y, sy, d, v, z);
  });
  tbb::parallel_for(0, dims.x * dims.y, [&](int l) {
    std::vector<float> d; std::vector<int> v; std::vector<double> z;
    edt1d(&f[std::size_t(l)], dims.z, sz, d, v, z);
  });
  return f;
}

JfaAccuracy compareWithExact(const std::vector<std::uint32_t>& nearest, const std::vector<float>& exactSquared,
                             const glm::ivec3& dims) {
  struct Acc { std::uint64_t n = 0, wrong = 0; double max = 0.0; };
  const Acc acc = tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(0, nearest.size()), Acc{},
      [&](const tbb::blocked_range<std::size_t>& r, Acc a) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) {
          if (!std::isfinite(exactSquared[i])) continue;
          ++a.n;
          const ivec3 p(int(i % dims.x), int((i / dims.x) % dims.y), int(i / (std::size_t(dims.x) * dims.y)));
          const double j = nearest[i] == kNoSeed ? std::numeric_limits<double>::infinity()
                                                 : double(distance2(p, unpackSeed(nearest[i])));
          if (j > exactSquared[i]) {
            ++a.wrong;
            a.max = std::max(a.max, std::sqrt(j) - std::sqrt(double(exactSquared[i])));
          }
        }
        return a;
      },
      [](Acc a, const Acc& b) { a.n += b.n; a.wrong += b.wrong; a.max = std::max(a.max, b.max); return a; });
  return {acc.n, acc.wrong, acc.max};
}

} // namespace rtsdf
