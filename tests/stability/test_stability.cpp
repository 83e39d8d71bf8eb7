// Numerical stability (issue #6): every knob of the SDF pipeline driven to its extremes. Each test asserts
// finite values, correct signs where the surface is far (more than kSignMargin coarse voxels), the
// monotone behaviour theory predicts, and that results do not depend on the scene's scale or position.
// docs/stability.md lists what each test guarantees. Grids stay small (coarse 8-32, fine 16-48): the suite
// must run in well under two minutes on lavapipe with two cores.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "grid/VdbIO.h"
#include "reference/ExactSdf.h"
#include "sdf/refine/RefineCpu.h"
#include "scene/SceneGeometry.h"
#include "sdf/SdfPipeline.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>

using namespace rtsdf;

namespace {

struct StabilityTag : test::NoSuiteObjects {};
using Stability = test::VulkanSuite<StabilityTag>;

/// Signs are asserted where the exact distance is larger than this many coarse voxels.
constexpr double kSignMargin = 2.0;

/// A scene of placed meshes (validated, as loadScene would).
Scene makeScene(std::vector<std::pair<Mesh, Transform>> parts) {
  Scene scene;
  scene.path = "<stability>";
  for (auto& [mesh, xf] : parts) {
    Instance inst;
    inst.name = mesh.name + std::to_string(scene.instances.size());
    inst.mesh = scene.meshes.size();
    inst.transform = xf;
    scene.meshReports.push_back(validateMesh(mesh));
    scene.meshes.push_back(std::move(mesh));
    scene.instances.push_back(inst);
  }
  return scene;
}

Transform at(const glm::dvec3& t, double scale = 1.0) {
  Transform x;
  x.translation = t;
  x.scale = glm::dvec3(scale);
  return x;
}

Bounds boundsOf(const Scene& s) { return buildSceneGeometry(s, 0.0).bounds; }

// ------------------------------------------------------------------------------------------------ references

/// Closest point on a triangle in double (Ericson 5.1.5), with the degenerate cases it handles.
glm::dvec3 closestOnTriangleD(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
  const glm::dvec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

/// The exact signed distance of a convex closed mesh placed by @a xf, all in double (a reference that float
/// rounding of world coordinates far from the origin cannot touch).
struct ConvexReference {
  std::vector<glm::dvec3> a, b, c, n;
  ConvexReference(const Mesh& mesh, const Transform& xf) {
    const glm::dmat4 m = xf.matrix();
    auto w = [&](unsigned i) { return glm::dvec3(m * glm::dvec4(glm::dvec3(mesh.positions[i]), 1.0)); };
    for (const glm::uvec3& t : mesh.triangles) {
      a.push_back(w(t.x)); b.push_back(w(t.y)); c.push_back(w(t.z));
      n.push_back(glm::normalize(glm::cross(b.back() - a.back(), c.back() - a.back())));
    }
  }
  double operator()(const glm::dvec3& p) const {
    double best = std::numeric_limits<double>::infinity();
    bool inside = true;
    for (std::size_t t = 0; t < a.size(); ++t) {
      best = std::min(best, glm::length(p - closestOnTriangleD(p, a[t], b[t], c[t])));
      inside = inside && glm::dot(n[t], p - a[t]) < 0.0;
    }
    return inside ? -best : best;
  }
};

using Reference = std::function<double(const glm::dvec3&)>;

/// The unsigned distance to every triangle of @a geo, brute force in double (slivers included).
Reference bruteUnsigned(const SceneGeometry& geo) {
  std::vector<glm::dvec3> tri;
  for (const WorldMesh& m : geo.meshes)
    for (const glm::uvec3& t : m.triangles)
      for (int c = 0; c < 3; ++c) tri.push_back(glm::dvec3(m.positions[t[c]]));
  return [tri](const glm::dvec3& p) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < tri.size(); k += 3)
      best = std::min(best, glm::length(p - closestOnTriangleD(p, tri[k], tri[k + 1], tri[k + 2])));
    return best;
  };
}

glm::ivec3 unpack(std::uint32_t p) { return {int(p & 1023u), int((p >> 10) & 1023u), int((p >> 20) & 1023u)}; }

/// What one pipeline's fine field looks like against a reference, in fine voxels.
struct Report {
  std::uint64_t voxels = 0, masked = 0, nonFinite = 0;
  std::uint64_t wrongSignOutside = 0; ///< exact > margin, f <= 0 (anywhere)
  std::uint64_t wrongSignInside = 0;  ///< exact < -margin, f >= 0 (masked voxels)
  std::uint64_t belowCoarseShell = 0; ///< unmasked voxel with f < -beta (the coarse field is unsigned)
  std::uint64_t rayUnder = 0;         ///< ray-determined |f| below |exact| by more than the float tolerance
  std::uint64_t boundUnder = 0;       ///< |f| below |exact| by more than a coarse cell diagonal
  double maxAbs = 0.0, meanAbs = 0.0, meanExcess = 0.0; ///< over masked voxels, | |f| - |exact| | / h_fine
};

/// @param floatTol the float tolerance (scene units) of a distance measured along a ray or to a closest point
Report inspect(const SdfPipeline& pipe, const Reference& exact, double floatTol) {
  const GridSpec& cs = pipe.coarseSpec();
  const GridSpec& fs = pipe.fineSpec();
  const std::vector<float> fine = pipe.fineField();
  const std::vector<float> coarse = pipe.coarseField(); // read back once: each call downloads it
  const RayMask mask = buildRayMask(coarse, cs, fs, pipe.settings().band);
  const float beta = float(pipe.settings().beta >= 0.0 ? pipe.settings().beta : 0.5 * cs.voxelSize);
  const double margin = kSignMargin * cs.voxelSize;
  Report r;
  std::vector<char> masked(fs.voxelCount(), 0);
  for (std::uint32_t p : mask.fineVoxels) {
    const glm::ivec3 v = unpack(p);
    masked[fs.linear(v.x, v.y, v.z)] = 1;
  }
  for (float f : fine) r.nonFinite += !std::isfinite(f);
  r.voxels = fine.size();
  for (std::uint32_t p : mask.fineVoxels) {
    const glm::ivec3 v = unpack(p);
    const float f = fine[fs.linear(v.x, v.y, v.z)];
    const double d = exact(fs.indexToWorld(glm::dvec3(v)));
    ++r.masked;
    const double err = (std::fabs(double(f)) - std::fabs(d)) / fs.voxelSize;
    r.maxAbs = std::max(r.maxAbs, std::fabs(err));
    r.meanAbs += std::fabs(err);
    r.meanExcess += err;
    if (d > margin && !(f > 0.0f)) ++r.wrongSignOutside;
    if (d < -margin && !(f < 0.0f)) ++r.wrongSignInside;
    // The frame's upper bound c^ (refine.comp): anything below it came from rays or the closest point.
    const float bound = upsampleCoarse(coarse, cs, fs, v) + beta + 0.8660254f * float(cs.voxelSize);
    const double af = std::fabs(double(f));
    if (af < double(bound) * (1.0 - 1e-6) && af < std::fabs(d) - floatTol) ++r.rayUnder;
    if (af < std::fabs(d) - std::sqrt(3.0) * cs.voxelSize - floatTol) ++r.boundUnder;
  }
  if (r.masked) { r.meanAbs /= double(r.masked); r.meanExcess /= double(r.masked); }
  // Outside the mask: every other voxel along each axis (the reference is a brute force).
  for (int z = 0; z < fs.dims.z; z += 2)
    for (int y = 0; y < fs.dims.y; y += 2)
      for (int x = 0; x < fs.dims.x; x += 2) {
        const std::uint64_t i = fs.linear(x, y, z);
        if (masked[i]) continue;
        const double d = exact(fs.indexToWorld(glm::dvec3(x, y, z)));
        if (d > margin && !(fine[i] > 0.0f)) ++r.wrongSignOutside;
        if (fine[i] < -beta * (1.0f + 1e-5f)) ++r.belowCoarseShell;
      }
  return r;
}

/// Assertions every refined field satisfies. @a signInside: the mask's inside voxels must be negative.
void expectSane(const Report& r, bool signInside, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_EQ(r.nonFinite, 0u);
  EXPECT_EQ(r.wrongSignOutside, 0u);
  if (signInside) EXPECT_EQ(r.wrongSignInside, 0u);
  EXPECT_EQ(r.belowCoarseShell, 0u);
  EXPECT_EQ(r.rayUnder, 0u);
  EXPECT_EQ(r.boundUnder, 0u);
}

std::string describe(const Report& r) {
  return fmt::format("{} masked of {}; |err| mean {:.2e} max {:.2e} voxels, excess {:.3f}; wrong sign out {} in {}",
                     r.masked, r.voxels, r.meanAbs, r.maxAbs, r.meanExcess, r.wrongSignOutside, r.wrongSignInside);
}

PipelineSettings small(RefineMode mode, int rays = 8) {
  PipelineSettings s = test::formerPipelineDefaults();
  s.coarseRes = 16;
  s.fineRes = 32;
  s.rays = rays;
  s.mode = mode;
  return s;
}

/// Float tolerance of a distance in a scene of size @a size whose coordinates reach @a magnitude.
double floatTol(double size, double magnitude) { return 1e-5 * size + 8.0 * magnitude * 1.2e-7; }

Mesh sphere(float r = 0.8f, int n = 2) { return makeSphereMesh(r, n, "sphere"); }

} // namespace

// ---------------------------------------------------------------------------------------------- resolution

TEST_F(Stability, ResolutionOneVoxelWorksInBothModes) {
  const Mesh m = sphere();
  const Scene scene = makeScene({{m, Transform{}}});
  const ConvexReference ref(m, Transform{});
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest})
    for (auto [coarse, fine] : {std::pair{1, 1}, std::pair{1, 2}, std::pair{1, 16}}) {
      PipelineSettings s = small(mode);
      s.coarseRes = coarse;
      s.fineRes = fine;
      SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
      EXPECT_GE(pipe.coarseSpec().dims.x, 1);
      for (int f = 0; f < 2; ++f) pipe.runFrame(0.0);
      const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
      expectSane(r, true, fmt::format("{} coarse {} fine {}: {}", toString(mode), coarse, fine, describe(r)));
      // The bake path: the fine field as a level set.
      const auto grid = denseToLevelSet(pipe.fineField(), pipe.fineSpec(), float(s.band));
      for (auto it = grid->cbeginValueOn(); it; ++it) ASSERT_TRUE(std::isfinite(*it));
      EXPECT_TRUE(std::isfinite(grid->background()));
    }
  // The exact reference on a one-voxel grid.
  const GridSpec one = GridSpec::fromBounds(boundsOf(scene), 1, 0.0);
  ExactSdfOptions opt;
  opt.band = INFINITY;
  opt.progress = false;
  const auto exact = exactSignedDistance(buildSceneGeometry(scene), one, opt);
  EXPECT_EQ(exact->activeVoxelCount(), one.voxelCount());
  for (auto it = exact->cbeginValueOn(); it; ++it) EXPECT_NEAR(*it, ref(one.indexToWorld(glm::dvec3(it.getCoord().x(), it.getCoord().y(), it.getCoord().z()))), 1e-5);
}

// The estimate finds the largest fine resolution this device and host can hold (coarse = fine / 2); one
// step beyond is refused with the numbers and the setting to lower, and the constructor refuses it before
// creating any Vulkan object.
TEST_F(Stability, ResolutionLargestThatFitsAndAClearErrorBeyond) {
  const Scene scene = makeScene({{sphere(), Transform{}}});
  const Bounds bounds = boundsOf(scene);
  const MemoryLimits limits = memoryLimits(sCtx->info());
  auto settingsFor = [](int fine) {
    PipelineSettings s = test::formerPipelineDefaults();
    s.fineRes = fine;
    s.coarseRes = std::max(1, fine / 2);
    return s;
  };
  auto fits = [&](int fine, std::string* why = nullptr) {
    try {
      checkPipelineMemory(estimatePipelineMemory(bounds, settingsFor(fine), {320, 320, 1}), limits);
      return true;
    } catch (const Error& e) {
      if (why) *why = e.what();
      return false;
    }
  };
  ASSERT_TRUE(fits(1));
  int lo = 1, hi = 1025; // fits(lo), !fits(hi): resolutions past 1024 are out of range
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    (fits(mid) ? lo : hi) = mid;
  }
  const PipelineMemory atMax = estimatePipelineMemory(bounds, settingsFor(lo), {320, 320, 1});
  std::string why;
  EXPECT_FALSE(fits(lo + 1, &why));
  std::printf("largest fine resolution on %s: %d (%s)\n  beyond: %s\n", sCtx->info().name.c_str(), lo,
              atMax.describe().c_str(), why.c_str());
  EXPECT_GE(lo, 64);
  EXPECT_LE(atMax.largestBuffer, limits.maxStorageBufferRange);
  EXPECT_NE(why.find("fine resolution"), std::string::npos) << why;
  if (lo < 1024) {
    EXPECT_NE(why.find("MiB"), std::string::npos) << why;
    // The constructor refuses before allocating anything.
    const std::int64_t live = sCtx->liveObjects();
    try {
      SdfPipeline pipe(*sCtx, scene, bounds, settingsFor(lo + 1));
      ADD_FAILURE() << "a pipeline beyond the memory estimate was created";
    } catch (const SettingError& e) {
      EXPECT_EQ(e.setting(), "fine resolution") << e.what();
      EXPECT_NE(std::string(e.what()).find("lower the fine resolution"), std::string::npos) << e.what();
    }
    EXPECT_EQ(sCtx->liveObjects(), live);
  }
  // Each limit names itself.
  const PipelineMemory need = estimatePipelineMemory(bounds, settingsFor(64), {320, 320, 1});
  MemoryLimits tiny = limits;
  tiny.maxStorageBufferRange = need.largestBuffer - 1;
  EXPECT_THROW(checkPipelineMemory(need, tiny), Error);
  tiny = limits;
  tiny.deviceBytes = need.deviceBytes - 1;
  try { checkPipelineMemory(need, tiny); ADD_FAILURE(); } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("heap"), std::string::npos) << e.what();
  }
  tiny = limits;
  tiny.hostBytes = need.hostBytes - 1;
  tiny.unifiedMemory = false;
  try { checkPipelineMemory(need, tiny); ADD_FAILURE(); } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("host memory"), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------------------------------------- band d

// The mask grows with d (never shrinks); d = 0 refines nothing (the fine field is the upsampled coarse one);
// d beyond the scene refines every voxel, and then every far voxel has the exact sign.
TEST_F(Stability, BandFromZeroToBeyondTheScene) {
  const Mesh m = sphere();
  const Scene scene = makeScene({{m, Transform{}}});
  const ConvexReference ref(m, Transform{});
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    std::uint64_t lastCoarse = 0, lastFine = 0;
    for (double d : {0.0, 1e-6, 0.05, 0.1, 0.3, 1.0, 100.0}) {
      PipelineSettings s = small(mode);
      s.band = d;
      SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
      const FrameStats st = pipe.runFrame(0.0);
      const std::string what = fmt::format("{} d = {}", toString(mode), d);
      SCOPED_TRACE(what);
      if (d <= 0.3) { // the grid itself grows with d up to a quarter of the scene: compare on one grid size
        EXPECT_GE(st.maskCoarseVoxels, lastCoarse);
        EXPECT_GE(st.maskFineVoxels, lastFine);
      }
      lastCoarse = st.maskCoarseVoxels;
      lastFine = st.maskFineVoxels;
      if (d == 0.0) {
        EXPECT_EQ(st.maskFineVoxels, 0u);
        const std::vector<float> fine = pipe.fineField();
        const GridSpec& fs = pipe.fineSpec();
        const std::vector<float> coarse = pipe.coarseField(); // read back once: each call downloads it
        for (int z = 0; z < fs.dims.z; z += 3)
          for (int y = 0; y < fs.dims.y; y += 3)
            for (int x = 0; x < fs.dims.x; x += 3)
              ASSERT_NEAR(fine[fs.linear(x, y, z)], upsampleCoarse(coarse, pipe.coarseSpec(), fs, {x, y, z}),
                          1e-5f);
      }
      if (d >= 100.0) EXPECT_EQ(st.maskFineVoxels, pipe.fineSpec().voxelCount());
      const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
      expectSane(r, true, what + ": " + describe(r));
      // The bake path writes a level set of half-width d (three fine voxels at d = 0).
      const auto grid = denseToLevelSet(pipe.fineField(), pipe.fineSpec(),
                                        float(d > 0.0 ? d : 3.0 * pipe.fineSpec().voxelSize));
      for (auto it = grid->cbeginValueOn(); it; ++it) ASSERT_TRUE(std::isfinite(*it));
    }
  }
}

// -------------------------------------------------------------------------------------------------- rays x

// x from 0 to 64: with x = 0 the fine field is the coarse upper bound (positive: no votes); more rays only
// lower the excess; a ray never reports less than the exact distance (beyond float rounding).
TEST_F(Stability, RaysFromZeroTo64) {
  const Mesh m = sphere();
  const Scene scene = makeScene({{m, Transform{}}});
  const ConvexReference ref(m, Transform{});
  std::map<int, Report> reports;
  for (int x : {0, 1, 4, 16, 64}) {
    PipelineSettings s = small(RefineMode::Rays, x);
    SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
    pipe.runFrame(0.0);
    const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
    std::printf("x = %d: %s\n", x, describe(r).c_str());
    expectSane(r, x >= 16, fmt::format("x = {}: {}", x, describe(r)));
    reports[x] = r;
  }
  EXPECT_LE(reports[64].meanExcess, reports[1].meanExcess);
  EXPECT_LE(reports[16].meanExcess, reports[1].meanExcess);
  EXPECT_LE(reports[1].meanExcess, reports[0].meanExcess);
  EXPECT_GT(reports[0].meanExcess, 0.0);
  // Closest mode at both ends of x: exact distances either way.
  for (int x : {0, 64}) {
    PipelineSettings s = small(RefineMode::Closest, x);
    SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
    pipe.runFrame(0.0);
    const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
    expectSane(r, true, fmt::format("closest x = {}: {}", x, describe(r)));
    EXPECT_LT(r.maxAbs, 1e-3);
  }
}

// --------------------------------------------------------------------------------------------- alpha 0, 1

// alpha = 1: f_t = min(f_{t-1}, r_t): |f| never grows from one frame to the next. alpha = 0: no history.
TEST_F(Stability, AlphaZeroAndOne) {
  const Mesh m = sphere();
  const Scene scene = makeScene({{m, Transform{}}});
  const ConvexReference ref(m, Transform{});
  for (double alpha : {0.0, 1.0}) {
    PipelineSettings s = small(RefineMode::Rays, 4);
    s.alpha = alpha;
    SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
    pipe.runFrame(0.0);
    std::vector<float> last = pipe.fineField();
    const RayMask mask = buildRayMask(pipe.coarseField(), pipe.coarseSpec(), pipe.fineSpec(), s.band);
    Report first = inspect(pipe, ref, floatTol(2.0, 1.0)), r;
    for (int f = 1; f < 4; ++f) {
      pipe.runFrame(0.0);
      const std::vector<float> now = pipe.fineField();
      std::uint64_t grew = 0;
      for (std::uint32_t p : mask.fineVoxels) {
        const glm::ivec3 v = unpack(p);
        const std::uint64_t i = pipe.fineSpec().linear(v.x, v.y, v.z);
        grew += std::fabs(now[i]) > std::fabs(last[i]);
      }
      if (alpha == 1.0) EXPECT_EQ(grew, 0u) << "frame " << f + 1;
      last = now;
      r = inspect(pipe, ref, floatTol(2.0, 1.0));
      expectSane(r, true, fmt::format("alpha = {} frame {}: {}", alpha, f + 1, describe(r)));
    }
    std::printf("alpha = %g: frame 1 %s\n           frame 4 %s\n", alpha, describe(first).c_str(), describe(r).c_str());
    if (alpha == 1.0) EXPECT_LT(r.meanExcess, first.meanExcess);
  }
}

// ------------------------------------------------------------------------------------- scale and position

// The same sphere at scale 1e-4, 1 and 1e4, and 1e5 units from the origin: in voxels, the fields agree with
// the unit scene's (same random directions: the grids are identical up to scale and translation).
TEST_F(Stability, ScaleAndPositionInvariance) {
  struct Case { const char* name; double scale; glm::dvec3 offset; };
  const std::vector<Case> cases{{"unit", 1.0, glm::dvec3(0.0)},
                                {"scale 1e-4", 1e-4, glm::dvec3(0.0)},
                                {"scale 1e4", 1e4, glm::dvec3(0.0)},
                                {"1e5 from the origin", 1.0, glm::dvec3(1e5, -1e5, 1e5)}};
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    std::vector<float> unitField;
    Report unit;
    for (const Case& c : cases) {
      SCOPED_TRACE(fmt::format("{} {}", toString(mode), c.name));
      const Mesh m = sphere(float(0.8 * c.scale));
      const Transform xf = at(c.offset);
      const Scene scene = makeScene({{m, xf}});
      const ConvexReference ref(m, xf);
      PipelineSettings s = small(mode, 8);
      // d an exact fraction of the bounds: the padded grid is then 20 voxels across at every scale (a band of
      // 0.1 * scale against float bounds would round the voxel count differently).
      s.band = 0.125 * boundsOf(scene).maxExtent();
      SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
      for (int f = 0; f < 2; ++f) pipe.runFrame(0.0);
      const double size = 1.6 * c.scale;
      const Report r = inspect(pipe, ref, floatTol(size, glm::length(c.offset) + size));
      std::printf("%s %s: %s\n", toString(mode), c.name, describe(r).c_str());
      expectSane(r, true, describe(r));
      const std::vector<float> field = pipe.fineField();
      const double h = pipe.fineSpec().voxelSize;
      if (c.scale == 1.0 && c.offset == glm::dvec3(0.0)) {
        unit = r;
        unitField = field;
        for (float& v : unitField) v = float(v / h);
        continue;
      }
      // The GPU passes and the BVH's top level work in the fine grid's frame (SdfPipeline::frameOrigin()), into
      // which the geometry moves in double, and the bounds that place the grid are double too: 1e5 from the
      // origin the field is the origin's, voxel for voxel.
      ASSERT_EQ(field.size(), unitField.size());
      // Per voxel, in voxels: the same field. Rays grazing an edge may hit in one scene and miss in the other
      // (float rounding differs): a few voxels may differ by more.
      std::size_t differ = 0;
      double maxDiff = 0.0;
      for (std::size_t i = 0; i < field.size(); ++i) {
        const double diff = std::fabs(field[i] / h - unitField[i]);
        maxDiff = std::max(maxDiff, diff);
        differ += diff > 0.05;
      }
      std::printf("  per-voxel difference to the unit scene: max %.3g voxels, %zu of %zu over 0.05\n", maxDiff, differ,
                  field.size());
      EXPECT_LE(differ, field.size() / 200);
      EXPECT_LE(r.maxAbs, unit.maxAbs + 0.05);
      EXPECT_NEAR(r.meanExcess, unit.meanExcess, 0.02);
    }
  }
  // A scene 1.6e-4 across, 1e5 from the origin, is below float resolution there (1/128): refused clearly.
  {
    const Scene lost = makeScene({{sphere(0.8e-4f), at(glm::dvec3(1e5, -1e5, 1e5))}});
    try {
      buildSceneGeometry(lost);
      ADD_FAILURE() << "a scene below float resolution was accepted";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("non-zero area"), std::string::npos) << e.what();
    }
  }
  // The exact reference at the extremes, in voxels of its own grid.
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const Mesh m = sphere(float(0.8 * c.scale));
    const Transform xf = at(c.offset);
    const Scene scene = makeScene({{m, xf}});
    const ConvexReference ref(m, xf);
    GridSpec spec = GridSpec::fromBounds(boundsOf(scene), 24, 0.1 * c.scale);
    if (spec.voxelSize < minVdbVoxelSize()) {
      // OpenVDB refuses voxels this small: a clear error, then the finest grid it accepts.
      ExactSdfOptions o;
      o.progress = false;
      try {
        exactSignedDistance(buildSceneGeometry(scene), spec, o);
        ADD_FAILURE() << "voxels below OpenVDB's smallest were accepted";
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("OpenVDB"), std::string::npos) << e.what();
      }
      spec = GridSpec::fromBounds(boundsOf(scene), 8, 0.1 * c.scale);
      ASSERT_GE(spec.voxelSize, minVdbVoxelSize());
    }
    ExactSdfOptions opt;
    opt.band = 0.2 * c.scale;
    opt.progress = false;
    const auto grid = exactSignedDistance(buildSceneGeometry(scene), spec, opt);
    double maxErr = 0.0;
    for (auto it = grid->cbeginValueOn(); it; ++it) {
      ASSERT_TRUE(std::isfinite(*it));
      const openvdb::Coord q = it.getCoord();
      maxErr = std::max(maxErr, std::fabs(*it - ref(spec.indexToWorld(glm::dvec3(q.x(), q.y(), q.z())))) / spec.voxelSize);
    }
    std::printf("exact reference %s: max error %.3g voxels\n", c.name, maxErr);
    // Float coordinates: 4 ulps of the largest coordinate, in voxels (0.47 voxels 1e5 from the origin).
    double coord = 0.0;
    for (int a = 0; a < 3; ++a) coord = std::max(coord, std::fabs(c.offset[a]) + 1.6 * c.scale);
    EXPECT_LT(maxErr, std::max(1e-3, 4.0 * std::ldexp(1.0, std::ilogb(coord) - 23) / spec.voxelSize));
  }
}

// ------------------------------------------------------------------------------------ degenerate triangles

// Degenerate triangles are dropped by validation (counted); slivers down to 1e-18 units thin stay and must
// give finite, exact (closest mode) and never under-estimated (rays) distances.
TEST_F(Stability, DegenerateAndSliverTriangles) {
  Mesh slivers;
  slivers.name = slivers.source = "slivers";
  // Thin offsets from a zero coordinate: float keeps them (0.4 + 1e-9 would round to 0.4, a degenerate).
  const double heights[] = {1e-2, 1e-4, 1e-6, 1e-9, 1e-14, 1e-18, 1e-20, 1e-30};
  for (int k = 0; k < 8; ++k) {
    const float z = -0.5f + 0.14f * float(k), hk = float(heights[k]);
    const unsigned b = unsigned(slivers.positions.size());
    slivers.positions.push_back({0.7f, 0.0f, z});
    slivers.positions.push_back({1.4f, 0.0f, z});
    slivers.positions.push_back({1.0f, hk, z});
    slivers.triangles.push_back({b, b + 1, b + 2});
    // A needle in another plane: long along y, thin along z.
    const float x = 0.6f + 0.1f * float(k);
    slivers.positions.push_back({x, -0.3f, 0.0f});
    slivers.positions.push_back({x, 0.6f, 0.0f});
    slivers.positions.push_back({x, 0.2f, hk});
    slivers.triangles.push_back({b + 3, b + 4, b + 5});
  }
  // Degenerate: a repeated index, three collinear points, three coincident points.
  const unsigned b = unsigned(slivers.positions.size());
  slivers.positions.insert(slivers.positions.end(),
                           {{0.7f, 0.5f, 0.0f}, {0.9f, 0.5f, 0.0f}, {1.1f, 0.5f, 0.0f}, {0.7f, 0.7f, 0.0f}});
  slivers.triangles.push_back({b, b, b + 1});
  slivers.triangles.push_back({b, b + 1, b + 2});
  slivers.triangles.push_back({b + 3, b + 3, b + 3});
  const Mesh box = makeBoxMesh(glm::vec3(1.0f));
  Scene scene = makeScene({{box, Transform{}}, {slivers, Transform{}}});
  // Three degenerates, and the slivers and needles 1e-20 and 1e-30 thin (their float normal is not a normal
  // number: hasFloatArea).
  EXPECT_EQ(scene.meshReports[1].degenerateDropped, 7u);
  const SceneGeometry geo = buildSceneGeometry(scene);
  const ExactDistanceField exact(geo);
  // Unsigned: the slivers are an open surface. Brute force in double: float barycentrics of a sliver are
  // cancellation.
  const Reference unsignedExact = bruteUnsigned(geo);
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    PipelineSettings s = small(mode, 16);
    SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
    for (int f = 0; f < 2; ++f) pipe.runFrame(0.0);
    const Report r = inspect(pipe, unsignedExact, floatTol(2.0, 1.5));
    std::printf("slivers %s: %s\n", toString(mode), describe(r).c_str());
    SCOPED_TRACE(describe(r));
    EXPECT_EQ(r.nonFinite, 0u);
    EXPECT_EQ(r.rayUnder, 0u);
    EXPECT_EQ(r.boundUnder, 0u);
    if (mode == RefineMode::Closest) EXPECT_LT(r.maxAbs, 1e-3);
  }
  // The exact reference (Embree closest points) near the slivers.
  double refErr = 0.0;
  for (float x = 0.5f; x <= 1.6f; x += 0.05f)
    for (float y = -0.2f; y <= 0.3f; y += 0.05f)
      for (float z = -0.6f; z <= 0.6f; z += 0.05f) {
        const float e = exact.signedDistance({x, y, z});
        ASSERT_TRUE(std::isfinite(e));
        refErr = std::max(refErr, std::fabs(std::fabs(double(e)) - unsignedExact(glm::dvec3(x, y, z))));
      }
  std::printf("exact reference near the slivers: max |error| %.3g\n", refErr);
  EXPECT_LT(refErr, 1e-5);
  // A scene that is one needle: its grid is one voxel thick along two axes.
  Mesh needle;
  needle.name = needle.source = "needle";
  needle.positions = {{0.0f, 0.0f, 0.0f}, {1.0f, 0.0f, 0.0f}, {0.5f, 1e-6f, 0.0f}};
  needle.triangles = {{0, 1, 2}};
  const Scene one = makeScene({{needle, Transform{}}});
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    PipelineSettings s = small(mode, 16);
    SdfPipeline pipe(*sCtx, one, boundsOf(one), s);
    pipe.runFrame(0.0);
    for (float v : pipe.fineField()) ASSERT_TRUE(std::isfinite(v));
  }
}

// ----------------------------------------------------------------------------------- coincident surfaces

// The same closed surface twice: as two instances in the same place, and as one mesh holding every triangle
// twice. Distances and signs are those of the single surface.
TEST_F(Stability, CoincidentDuplicateSurfaces) {
  const Mesh m = sphere();
  const ConvexReference ref(m, Transform{});
  Mesh doubled = m;
  for (const glm::uvec3& t : m.triangles) doubled.triangles.push_back(t);
  const Scene twoInstances = makeScene({{m, Transform{}}, {m, Transform{}}});
  const Scene oneMesh = makeScene({{doubled, Transform{}}});
  EXPECT_FALSE(oneMesh.meshReports[0].watertight());
  for (const Scene* scene : {&twoInstances, &oneMesh})
    for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
      PipelineSettings s = small(mode, 16);
      SdfPipeline pipe(*sCtx, *scene, boundsOf(*scene), s);
      for (int f = 0; f < 2; ++f) pipe.runFrame(0.0);
      const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
      const std::string what = fmt::format("{} {}: {}", scene == &oneMesh ? "one mesh" : "two instances",
                                           toString(mode), describe(r));
      std::printf("%s\n", what.c_str());
      expectSane(r, true, what);
      if (mode == RefineMode::Closest) EXPECT_LT(r.maxAbs, 1e-3) << what;
    }
  // The exact reference signs the doubled (non-manifold) mesh by winding number: twice inside is inside.
  const SceneGeometry doubledGeo = buildSceneGeometry(oneMesh); // the field keeps a reference to it
  const ExactDistanceField exact(doubledGeo);
  for (float x = -1.0f; x <= 1.0f; x += 0.1f) {
    const double d = ref(glm::dvec3(x, 0.05, 0.02));
    if (std::fabs(d) > 0.05) EXPECT_EQ(exact.signedDistance({x, 0.05f, 0.02f}) < 0.0f, d < 0.0) << x;
  }
}

// ---------------------------------------------------------------------------------------- sub-voxel mesh

// A sphere of radius 0.004 in a grid of 0.125-unit coarse voxels: the conservative voxelization still seeds
// it, the mask surrounds it, and the fine field is the exact distance (closest) or never below it (rays).
TEST_F(Stability, MeshSmallerThanAVoxel) {
  const Mesh m = sphere(0.004f, 1);
  const Transform xf = at(glm::dvec3(0.31, 0.17, -0.23));
  const Scene scene = makeScene({{m, xf}});
  const ConvexReference ref(m, xf);
  const Bounds big{glm::dvec3(-1.0), glm::dvec3(1.0)};
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    PipelineSettings s = small(mode, 16);
    SdfPipeline pipe(*sCtx, scene, big, s);
    const FrameStats st = pipe.runFrame(0.0);
    EXPECT_GT(st.maskCoarseVoxels, 0u);
    const auto& c = pipe.coarseField();
    EXPECT_LT(*std::min_element(c.begin(), c.end()), pipe.coarseSpec().voxelSize); // a seed was found
    const Report r = inspect(pipe, ref, floatTol(2.0, 1.0));
    std::printf("sub-voxel sphere %s: %s\n", toString(mode), describe(r).c_str());
    expectSane(r, true, describe(r));
    if (mode == RefineMode::Closest) EXPECT_LT(r.maxAbs, 1e-3);
  }
  // The same mesh on its own bounds (the grid is a few voxels of its own size).
  for (RefineMode mode : {RefineMode::Rays, RefineMode::Closest}) {
    PipelineSettings s = small(mode, 16);
    s.coarseRes = 4;
    s.fineRes = 8;
    s.band = 0.002;
    SdfPipeline pipe(*sCtx, scene, boundsOf(scene), s);
    pipe.runFrame(0.0);
    const Report r = inspect(pipe, ref, floatTol(0.008, 0.5));
    expectSane(r, true, describe(r));
  }
}
