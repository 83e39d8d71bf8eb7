// The renderer on lavapipe: every GPU pass against its CPU reference on real scenes, the SDF penumbra
// against the closed form and the ray-traced truth, moving shadows, files and the extremes.
#include "GpuFixture.h"
#include "RenderTestUtil.h"
#include "TestUtil.h"
#include "image/ImageIO.h"
#include "render/AnalyticPenumbra.h"
#include "render/RenderPasses.h"
#include "render/RayTracedShadows.h"
#include "render/compose/ComposeCpu.h"
#include "render/contactshadow/ContactShadowCpu.h"
#include "render/sdfshadow/SdfShadowCpu.h"
#include "render/shadowmap/ShadowMapCpu.h"
#include "render/taa/TaaCpu.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstring>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <random>

using namespace rtsdf;
namespace sh = rtsdf::gpu::shared;

namespace {

struct RenderTag : test::NoSuiteObjects {};
using Render = test::VulkanSuite<RenderTag>;

using test::defaultScene;
Scene analyticScene() { return loadScene(test::dataPath("scenes/analytic.json")); }
/// A floor half covered by a plate (x in [-1, 0], 0.5 above it) under a sun straight down, seen from below the plate.
Scene plateScene() {
  return parseScene(R"({"meshes": {"floor": {"box": [2, 0.02, 2]}, "plate": {"box": [1, 0.02, 2]}},
      "instances": [{"mesh": "floor", "translate": [0, -0.01, 0]}, {"mesh": "plate", "translate": [-0.5, 0.5, 0]}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}],
      "camera": {"position": [0, 0.3, 2.6], "look_at": [0, 0.05, 0], "fov_deg": 60}})",
                    "plate.json");
}
using test::boundsOf;

RenderSettings small(ShadowTechnique t, int w = 160, int h = 90) {
  RenderSettings r;
  r.width = w;
  r.height = h;
  r.technique = t;
  r.pipeline.coarseRes = 64;
  r.pipeline.fineRes = 128;
  r.pipeline.mode = RefineMode::Closest;
  r.pipeline.rays = 4;
  r.pipeline.band = 0.1;   // the former defaults, which these tests were written for
  r.sdf.maxStep = 0.05;
  r.taa.enabled = false;
  r.sdf.jitter = false;
  r.sdf.contactRays = 0; // the march alone; the tests of the contact rays turn them on
  return r;
}

using test::countAbove;

void expectAllFinite(const RenderedFrame& f) {
  for (const auto& v : f.visibility)
    for (float x : v) {
      ASSERT_TRUE(std::isfinite(x));
      ASSERT_GE(x, 0.0f);
      ASSERT_LE(x, 1.0f);
    }
}

} // namespace

// GBufferPass traverses the GPU BVH; the reference is Embree's rtcIntersect1 through the same camera rays.
// Rays that graze an edge between two triangles may pick either: both must agree on at least 99.8% of the
// pixels, and where they agree the hit points match to float rounding.
TEST_F(Render, GBufferPassEqualsEmbreePrimaryHits) {
  const Scene scene = defaultScene();
  Renderer r(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::ShadowMap, 320, 180));
  const RenderedFrame f = r.renderFrame(0.0);
  const GBuffer cpu = traceGBuffer(buildSceneGeometry(scene, 0.0), makeCameraParams(scene.camera, 320, 180));
  std::size_t differ = 0, hits = 0;
  for (std::size_t i = 0; i < cpu.pixelCount(); ++i) {
    if (f.gbuffer.hit(i) != cpu.hit(i) || f.gbuffer.normal[i].w != cpu.normal[i].w) {
      ++differ;
      continue;
    }
    if (!cpu.hit(i)) continue;
    ++hits;
    EXPECT_LT(glm::length(f.gbuffer.worldPosition(i) - cpu.worldPosition(i)), 1e-4);
    EXPECT_GT(glm::dot(glm::vec3(f.gbuffer.normal[i]), glm::vec3(cpu.normal[i])), 0.9999f);
  }
  EXPECT_GT(hits, cpu.pixelCount() / 2);
  EXPECT_LT(differ, cpu.pixelCount() / 500) << differ << " pixels differ";
}

// SdfShadowPass (buffer sampling) against the same march on the CPU over the same field and G-buffer.
// Trilinear sampling and the march are marked 'precise' on the GPU and compiled without FMA contraction on
// the CPU; a march whose sample lands within rounding of epsilon may still end one step apart, so 0.1% of the
// pixels may differ by more than 1e-4.
TEST_F(Render, SdfShadowPassEqualsTheCpuMarch) {
  const Scene scene = defaultScene();
  for (PenumbraEstimate p : {PenumbraEstimate::Classic, PenumbraEstimate::Improved, PenumbraEstimate::Centered,
                            PenumbraEstimate::Umbra}) {
    RenderSettings s = small(ShadowTechnique::Sdf);
    s.sdf.penumbra = p;
    s.sdf.jitter = true;
    s.sdf.sampling = SdfSampling::Buffer;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    const RenderedFrame f = r.renderFrame(0.0);
    const LightVisibility cpu = sdfShadowsCpu(f.gbuffer, r.sdfPipeline()->fineField(), r.gpuLights(),
                                              r.sdfShadowParams());
    const std::size_t n = countAbove(f.visibility[0], cpu[0], 1e-4f);
    std::size_t shadowed = 0;
    for (float v : cpu[0]) shadowed += v < 0.5f;
    EXPECT_GT(shadowed, 100u) << toString(p);
    EXPECT_LE(n, f.gbuffer.pixelCount() / 1000) << toString(p) << ": " << n << " pixels differ";
  }
}

// ContactShadowPass after SdfShadowPass against their CPU references (the same marks, Embree's rays) on the default
// scene: the pass must trace a real share of the pixels (its contacts, creases and the gaps under the walls) and
// agree with Embree except for rays that graze an edge, on at most 0.2% of the pixels. The pixels it changed must be
// the marked ones only.
TEST_F(Render, ContactShadowPassEqualsEmbreeRaysWhereTheMarchMarkedContacts) {
  const Scene scene = defaultScene();
  RenderSettings s = small(ShadowTechnique::Sdf, 320, 180);
  s.sdf.contactRays = 4;
  s.sdf.jitter = true;
  s.sdf.sampling = SdfSampling::Buffer;
  Renderer r(*sCtx, scene, boundsOf(scene), s);
  r.renderFrame(0.0);
  const RenderedFrame f = r.renderFrame(0.0); // frame 2: the rays turned by the jitter
  ASSERT_GT(r.contactShadowParams().rays, 0u);
  ASSERT_GT(r.sdfShadowParams().contactReach, 0.0f);
  EXPECT_GT(f.passTotal(ContactShadowPass::kName), 0.0) << "the pass is profiled";
  LightVisibility cpu = sdfShadowsCpu(f.gbuffer, r.sdfPipeline()->fineField(), r.gpuLights(), r.sdfShadowParams());
  std::size_t marked = 0;
  for (float v : cpu[0]) marked += v >= sh::kContactPending;
  const LightVisibility march = cpu;
  contactShadowsCpu(buildSceneGeometry(scene, 0.0, r.frameOrigin()), f.gbuffer, r.gpuLights(),
                    r.contactShadowParams(), cpu);
  std::size_t darkened = 0, differMarked = 0, differOther = 0;
  for (std::size_t i = 0; i < cpu[0].size(); ++i) {
    ASSERT_LE(cpu[0][i], 1.0f);
    const bool isMarked = march[0][i] >= sh::kContactPending;
    if (!isMarked) EXPECT_EQ(cpu[0][i], march[0][i]) << "pixel " << i << " was not marked";
    else darkened += cpu[0][i] < march[0][i] - sh::kContactPending;
    (isMarked ? differMarked : differOther) += std::fabs(f.visibility[0][i] - cpu[0][i]) > 1e-4f;
  }
  std::cout << marked << " of " << f.gbuffer.pixelCount() << " pixels marked, " << darkened << " darkened by the "
            << "rays; " << differMarked << " marked and " << differOther << " other pixels differ from the CPU\n";
  EXPECT_GT(marked, f.gbuffer.pixelCount() / 200);
  EXPECT_LT(marked, f.gbuffer.pixelCount() / 4) << "the marks are to spare the open surfaces";
  EXPECT_GT(darkened, 10u);
  // The march may end a step apart on 0.1% of the pixels (SdfShadowPassEqualsTheCpuMarch); a marked pixel's rays
  // may graze an edge, on at most 1% of them: fewer than the pixels the rays darken, so a pass that darkened
  // nothing (or left a mark on) fails here.
  EXPECT_LE(differOther, f.gbuffer.pixelCount() / 1000);
  EXPECT_LE(differMarked, marked / 100) << differMarked << " marked pixels differ";
}

// SdfShadowPass sampling the sparse fine state (the brick pool and the coarse SDF) against sampling the dense
// resolve: the same fetched values in the same filter, so the same visibility bit for bit, for every estimate
// (the umbra's several marches included) and over two frames of the orbiting teapot.
TEST_F(Render, SdfShadowPassFromBricksEqualsTheDenseBuffer) {
  const Scene scene = defaultScene();
  for (PenumbraEstimate p : {PenumbraEstimate::Centered, PenumbraEstimate::Umbra}) {
    SCOPED_TRACE(toString(p));
    RenderSettings s = small(ShadowTechnique::Sdf);
    s.sdf.penumbra = p;
    s.sdf.jitter = true;
    s.pipeline.band = 0.05;
    s.pipeline.rays = 0;
    s.pipeline.coarseRes = 40;
    s.pipeline.fineRes = 80;
    Bounds bounds;
    for (int f = 0; f < 2; ++f) bounds.add(boundsOf(scene, 0.4 * f));
    s.sdf.sampling = SdfSampling::Buffer;
    Renderer dense(*sCtx, scene, bounds, s);
    s.sdf.sampling = SdfSampling::Bricks;
    Renderer sparse(*sCtx, scene, bounds, s);
    EXPECT_EQ(sparse.sdfPipeline()->settings().fineStorage, FineStorage::Sparse);
    for (int f = 0; f < 2; ++f) {
      SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
      const RenderedFrame a = dense.renderFrame(0.4 * f), b = sparse.renderFrame(0.4 * f);
      EXPECT_EQ(a.passMs.empty(), false);
      std::size_t differ = 0, shadowed = 0;
      for (std::size_t i = 0; i < a.visibility[0].size(); ++i) {
        differ += std::memcmp(&a.visibility[0][i], &b.visibility[0][i], 4) != 0;
        shadowed += a.visibility[0][i] < 0.5f;
      }
      EXPECT_EQ(differ, 0u);
      EXPECT_GT(shadowed, 100u);
      EXPECT_EQ(dense.sdfPipeline()->fineField(), sparse.sdfPipeline()->fineField());
    }
  }
}

// A flat receiver's own surface in the march: with the default start offset (the bias) the biased plane is
// exactly the receiver's horizon, so a sun at elevation e above it gets r = sin(e) / tan(radius) for every
// sample, the centred estimate's disc cut by the horizon. The field is the plane y = 0 (linear, so trilinear
// sampling is exact) in the renderer's own parameters. The former default offset (bias + epsilon) lifted
// the start a voxel: the sun at the horizon came out brighter than 0.5 by far, which the last check shows.
TEST_F(Render, AFlatReceiverSeesTheSunCutByItsOwnHorizon) {
  const Scene scene = analyticScene();
  RenderSettings s = small(ShadowTechnique::Sdf);
  Renderer r(*sCtx, scene, boundsOf(scene), s);
  sh::SdfShadowParams p = r.sdfShadowParams();
  EXPECT_FLOAT_EQ(p.normalOffset, p.bias);
  EXPECT_GT(p.bias, 0.0f);
  ASSERT_EQ(p.penumbra, sh::kPenumbraCentered);
  const float h = p.gridOriginH.w;
  const int n = 64;
  p.gridOriginH = glm::vec4(-0.5f * n * h, -0.5f * n * h, -0.5f * n * h, h);
  p.gridDims = glm::ivec4(n, n, n, 1);
  std::vector<float> plane(std::size_t(n) * n * n);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) plane[(std::size_t(z) * n + y) * n + x] = p.gridOriginH.y + (y + 0.5f) * h;
  const double radius = 2.5 * glm::pi<double>() / 180.0;
  const std::vector<double> elevations = {0.0, 0.3 * radius, 0.7 * radius, 1.5 * radius};
  GBuffer g;
  g.width = int(elevations.size());
  g.height = 1;
  for (std::size_t i = 0; i < elevations.size(); ++i) {
    g.position.emplace_back(0.01f * float(i), 0.0f, 0.0f, 1.0f);
    g.normal.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
  }
  for (std::size_t i = 0; i < elevations.size(); ++i) {
    Light sun;
    sun.type = Light::Type::Directional;
    sun.direction = -glm::dvec3(std::cos(elevations[i]), std::sin(elevations[i]), 0.0);
    sun.angularRadius = radius;
    const LightVisibility v = sdfShadowsCpu(g, plane, makeGpuLights({sun}), p);
    const double rr = std::min(std::sin(elevations[i]) / std::tan(radius), 1.0);
    const double expected = 0.25 * (1.0 + rr) * (1.0 + rr) * (2.0 - rr);
    EXPECT_NEAR(v[0][i], expected, 2e-3) << "elevation " << elevations[i] / radius << " radii";
    if (i == 0) {
      sh::SdfShadowParams lifted = p;
      lifted.normalOffset = p.bias + p.epsilon;
      const float old = sdfShadowsCpu(g, plane, makeGpuLights({sun}), lifted)[0][0];
      std::printf("sun at the horizon: %.4f (start offset = bias), %.4f (bias + epsilon)\n", v[0][0], old);
      EXPECT_GT(old, expected + 0.2);
    }
  }
}

// The SDF march with the renderer's default parameters (centred estimate) through the exact field of a sphere,
// against the closed-form visible fraction of the sun past that sphere (AnalyticPenumbra.h) on floor points
// across its penumbra: the march, not the field, is under test. The estimate treats the silhouette as a
// straight edge and the bias widens the sphere by 0.15 voxels. Measured: RMSE 0.0667
// over the penumbra (1044 points), max |error| 0.125.
TEST_F(Render, SdfMarchThroughAnExactSphereFieldMatchesTheClosedFormPenumbra) {
  const Scene scene = analyticScene();
  Renderer r(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::Sdf));
  sh::SdfShadowParams p = r.sdfShadowParams();
  ASSERT_EQ(p.penumbra, sh::kPenumbraCentered);
  const float h = p.gridOriginH.w;
  const int n = int(std::ceil(2.0f / h));
  p.gridOriginH = glm::vec4(-1.0f, -0.5f, -1.0f, h); // x, z in [-1, 1], y in [-0.5, 1.5]
  p.gridDims = glm::ivec4(n, n, n, 1);
  const glm::dvec3 centre(0.0, 0.5, 0.0); // the analytic scene's sphere
  const double radius = 0.25;
  std::vector<float> field(std::size_t(n) * n * n);
  for (int z = 0; z < n; ++z)
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        field[(std::size_t(z) * n + y) * n + x] =
            float(glm::length(glm::dvec3(glm::vec3(p.gridOriginH)) + (glm::dvec3(x, y, z) + 0.5) * double(h) - centre) -
                  radius);
  const Light& sun = scene.lights[0];
  const glm::dvec3 toLight = -glm::normalize(sun.direction);
  const glm::dvec3 shadow = centre - toLight * (centre.y / toLight.y); // the shadow's centre on the floor
  GBuffer g;
  g.width = g.height = 81;
  for (int j = 0; j < g.height; ++j)
    for (int i = 0; i < g.width; ++i) {
      g.position.emplace_back(glm::vec3(shadow + 0.01 * glm::dvec3(i - 40, 0.0, j - 40)), 1.0f);
      g.normal.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
    }
  const LightVisibility v = sdfShadowsCpu(g, field, makeGpuLights({sun}), p);
  double sq = 0.0, worst = 0.0;
  std::size_t penumbra = 0;
  for (std::size_t i = 0; i < g.pixelCount(); ++i) {
    const double exact = sunVisibilityPastSphere(glm::dvec3(glm::vec3(g.position[i])), toLight, sun.angularRadius,
                                                 centre, radius);
    const double e = v[0][i] - exact;
    worst = std::max(worst, std::fabs(e));
    if (exact > 0.02 && exact < 0.98) sq += e * e, ++penumbra;
  }
  const double rmse = std::sqrt(sq / double(std::max<std::size_t>(penumbra, 1)));
  std::printf("SDF march past an exact sphere: penumbra RMSE %.4f over %zu points, max |error| %.4f\n", rmse,
              penumbra, worst);
  EXPECT_GT(penumbra, 500u);
  EXPECT_LT(rmse, 0.1);
  EXPECT_LT(worst, 0.2);
}

namespace {
/// Exact signed distance of an axis-aligned box (centre c, half extents e) at point x.
float boxDistance(const glm::dvec3& x, const glm::dvec3& c, const glm::dvec3& e) {
  const glm::dvec3 q = glm::abs(x - c) - e;
  return float(glm::length(glm::max(q, 0.0)) + std::min(std::max(q.x, std::max(q.y, q.z)), 0.0));
}

struct PlateShadowError {
  double umbraMax = 0.0, umbraMean = 0.0, penumbraRmse = 0.0;
  std::size_t umbra = 0, penumbra = 0;
};

/// The CPU march (params p, its grid replaced by one of voxel size h around the plate) through the exact field of
/// a 0.5 x thickness x 0.5 plate whose mid-plane lies offset voxels above a voxel centre plane, for floor points
/// under it, against the ray-traced truth of the same plate (Embree, 1024 rays per point) for each light.
PlateShadowError plateShadowError(sh::SdfShadowParams p, const std::vector<Light>& lights, double thicknessVoxels,
                                  double offsetVoxels) {
  const double h = p.gridOriginH.w;
  const glm::dvec3 lo(-0.6, -0.1, -0.6);
  const glm::ivec3 n = glm::ivec3(glm::ceil((glm::dvec3(0.6, 0.45, 0.6) - lo) / h));
  p.gridOriginH = glm::vec4(glm::vec3(lo), float(h));
  p.gridDims = glm::ivec4(n, int(lights.size()));
  const glm::dvec3 centre(0.0, lo.y + (std::floor((0.25 - lo.y) / h) + 0.5 + offsetVoxels) * h, 0.0);
  const glm::dvec3 half(0.25, 0.5 * thicknessVoxels * h, 0.25);
  std::vector<float> field(std::size_t(n.x) * n.y * n.z);
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x)
        field[(std::size_t(z) * n.y + y) * n.x + x] = boxDistance(lo + (glm::dvec3(x, y, z) + 0.5) * h, centre, half);
  const Scene plate = parseScene(fmt::format(R"({{"meshes": {{"plate": {{"box": [0.5, {}, 0.5]}}}},
      "instances": [{{"mesh": "plate", "translate": [0, {}, 0]}}]}})",
                                             2.0 * half.y, centre.y),
                                 "thin_plate.json");
  const SceneGeometry geometry = buildSceneGeometry(plate, 0.0);
  PlateShadowError err;
  double umbraSum = 0.0, sq = 0.0;
  for (const Light& light : lights) {
    const glm::dvec3 toLight = -glm::normalize(light.direction);
    const glm::dvec3 shadow = centre - toLight * (centre.y / toLight.y);
    GBuffer g;
    g.width = g.height = 64;
    for (int j = 0; j < g.height; ++j)
      for (int i = 0; i < g.width; ++i) {
        g.position.emplace_back(glm::vec3(shadow + glm::dvec3(0.1 + 0.3 * i / 63.0, 0.0, 0.2 * (j / 31.5 - 1.0))), 1.0f);
        g.normal.emplace_back(0.0f, 1.0f, 0.0f, 0.0f);
      }
    const std::vector<float> v = sdfShadowsCpu(g, field, makeGpuLights({light}), p)[0];
    RayTracedShadowSettings rt;
    rt.samples = 1024;
    const std::vector<float> truth = rayTracedVisibility(geometry, {light}, g, rt)[0];
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (truth[i] < 0.02f) {
        err.umbraMax = std::max(err.umbraMax, double(v[i]));
        umbraSum += v[i], ++err.umbra;
      } else if (truth[i] < 0.98f) {
        sq += double(v[i] - truth[i]) * double(v[i] - truth[i]), ++err.penumbra;
      }
    }
  }
  err.umbraMean = umbraSum / double(std::max<std::size_t>(err.umbra, 1));
  err.penumbraRmse = std::sqrt(sq / double(std::max<std::size_t>(err.penumbra, 1)));
  return err;
}
} // namespace

// A plate thinner than the light's cone is never deeper than half its thickness, so the centred estimate alone
// calls its crossing a narrow edge and lets light through the umbra; the lateral probes (the default) see the
// plate all around the cone. Plates 0.5, 1 and 2 fine voxels thick, their mid-plane on, a quarter and half a
// voxel off the voxel centres, 0.25 above the floor (the cone's radius is about 1.5 voxels there), under the
// default scene's sun (tilted: the probes follow the plate's plane) and a sun straight down; floor points
// across the plate's edge against the ray-traced truth. Measured with the probes: umbra (truth < 0.02) max
// 0.0091, penumbra RMSE 0.086-0.107; without: umbra max 0.05-0.50, penumbra RMSE 0.081-0.178. The umbra must
// stay below 0.02 everywhere with the probes and leak without them (plates under 2 voxels); the penumbra must
// stay within 0.12 and, for plates under 2 voxels, beat the centre-only estimate.
TEST_F(Render, ThinPlatesHoldTheirUmbra) {
  const Scene scene = defaultScene();
  Renderer r(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::Sdf));
  sh::SdfShadowParams p = r.sdfShadowParams();
  ASSERT_EQ(p.penumbra, sh::kPenumbraCentered);
  ASSERT_GT(p.lateralProbes, 0u);
  const float h = 1.0f / 128.0f;
  p.gridOriginH.w = h;
  Light down = scene.lights[0];
  down.direction = glm::dvec3(0.0, -1.0, 0.0);
  const std::vector<Light> lights = {scene.lights[0], down};
  for (double thickness : {0.5, 1.0, 2.0})
    for (double offset : {0.0, 0.25, 0.5}) {
      const PlateShadowError with = plateShadowError(p, lights, thickness, offset);
      sh::SdfShadowParams off = p;
      off.lateralProbes = 0;
      const PlateShadowError without = plateShadowError(off, lights, thickness, offset);
      std::printf("plate %.1f voxels, offset %.2f: umbra (%zu points) max %.4f mean %.4f, penumbra (%zu) RMSE %.4f; "
                  "without probes: umbra max %.4f mean %.4f, penumbra RMSE %.4f\n",
                  thickness, offset, with.umbra, with.umbraMax, with.umbraMean, with.penumbra, with.penumbraRmse,
                  without.umbraMax, without.umbraMean, without.penumbraRmse);
      EXPECT_GT(with.umbra, 1000u);
      EXPECT_GT(with.penumbra, 200u);
      EXPECT_LT(with.umbraMax, 0.02) << thickness << " voxels, offset " << offset;
      EXPECT_LT(with.penumbraRmse, 0.12) << thickness << " voxels, offset " << offset;
      if (thickness < 2.0) {
        EXPECT_GT(without.umbraMax, 0.1) << "the plate did not leak without the probes";
        EXPECT_LT(with.penumbraRmse, without.penumbraRmse) << thickness << " voxels, offset " << offset;
      }
    }
}

// SdfShadowPass with the fine SDF in a 3D texture (hardware trilinear filtering) against the CPU march over
// the same field. The texture unit filters with limited sub-texel precision (Vulkan guarantees 4 bits; the
// device reports its own), so a sample may differ from the exact trilinear value by up to about
// h / 2^bits; the visibility then differs a little along penumbrae and, rarely, a march ends one step apart.
TEST_F(Render, SdfShadowPassFromA3dTextureMatchesTheCpuMarch) {
  if (!gpu::SampledVolume::supported(*sCtx)) GTEST_FAIL() << sCtx->info().name << " cannot filter R32_SFLOAT 3D textures";
  const Scene scene = defaultScene();
  for (PenumbraEstimate p : {PenumbraEstimate::Improved, PenumbraEstimate::Centered}) {
    RenderSettings s = small(ShadowTechnique::Sdf);
    s.sdf.penumbra = p;
    s.sdf.jitter = true;
    s.sdf.sampling = SdfSampling::Texture;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    ASSERT_EQ(r.sdfSampling(), SdfSampling::Texture);
    const RenderedFrame f = r.renderFrame(0.0);
    EXPECT_GT(f.passTotal(SdfShadowPass::kCopyName), 0.0) << "the copy into the texture is profiled";
    const LightVisibility cpu = sdfShadowsCpu(f.gbuffer, r.sdfPipeline()->fineField(), r.gpuLights(),
                                              r.sdfShadowParams());
    double sum = 0.0;
    for (std::size_t i = 0; i < cpu[0].size(); ++i) sum += std::fabs(f.visibility[0][i] - cpu[0][i]);
    const double mean = sum / double(cpu[0].size());
    const std::size_t far = countAbove(f.visibility[0], cpu[0], 0.05f);
    std::size_t shadowed = 0;
    for (float v : f.visibility[0]) shadowed += v < 0.5f;
    std::cout << toString(p) << ": texture vs CPU mean |diff| " << mean << ", " << far << " of "
              << f.gbuffer.pixelCount() << " pixels differ by > 0.05\n";
    EXPECT_GT(shadowed, 100u) << toString(p);
    EXPECT_LT(mean, 2e-3) << toString(p);
    EXPECT_LE(far, f.gbuffer.pixelCount() / 200) << toString(p) << ": " << far << " pixels differ by > 0.05";
  }
  // A pipeline refuses a resource of the wrong kind at a binding (a buffer where the texture belongs).
  gpu::ComputePipeline texturePass(*sCtx, "sdf_shadow.comp",
                                   {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                    VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                    VK_DESCRIPTOR_TYPE_STORAGE_BUFFER},
                                   sizeof(gpu::shared::SdfShadowParams));
  gpu::Buffer b(*sCtx, 64, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "b");
  gpu::CommandBuffer cmd(*sCtx);
  gpu::shared::SdfShadowParams params{};
  EXPECT_THROW(texturePass.dispatch(cmd.handle(), {&b, &b, &b, &b, &b}, &params, {1, 1, 1}), Error);
  cmd.submitAndWait();
}

// VolumeFillPass: the 3D texture holds the dense field bit for bit by either method (a copy command, or the compute
// shader a GPU uses by default), each into a texture of its own; a field smaller than the texture is refused.
TEST_F(Render, VolumeFillPassCopiesTheFieldBitForBitEitherWay) {
  ASSERT_TRUE(gpu::SampledVolume::storageSupported(*sCtx)) << sCtx->info().name << " cannot store to R32F 3D textures";
  const glm::uvec3 dims(37, 5, 23); // not a multiple of the 64-wide work groups along x
  std::vector<float> field(std::size_t(dims.x) * dims.y * dims.z);
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> value(-2.0f, 2.0f);
  for (float& v : field) v = value(rng);
  gpu::Buffer src, back;
  gpu::reserveAndUpload(*sCtx, src, field.data(), field.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "field");
  gpu::reserve(*sCtx, back, field.size() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "back");
  const VolumeFillPass fill(*sCtx);
  for (VolumeFillPass::Method m : {VolumeFillPass::Method::Compute, VolumeFillPass::Method::Transfer}) {
    SCOPED_TRACE(m == VolumeFillPass::Method::Compute ? "compute" : "transfer");
    const gpu::SampledVolume texture(*sCtx, dims, "texture");
    gpu::CommandBuffer cmd(*sCtx);
    vkCmdFillBuffer(cmd.handle(), back.handle(), 0, VK_WHOLE_SIZE, 0u);
    gpu::computeBarrier(cmd.handle());
    fill.execute(cmd.handle(), nullptr, {src}, {texture}, m);
    texture.copyTo(cmd.handle(), back);
    cmd.submitAndWait();
    std::vector<float> out(field.size());
    gpu::download(*sCtx, back, out.data(), out.size() * 4);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < field.size(); ++i) differ += std::memcmp(&out[i], &field[i], 4) != 0;
    EXPECT_EQ(differ, 0u);
  }
  const gpu::SampledVolume larger(*sCtx, dims + glm::uvec3(1), "larger");
  gpu::CommandBuffer cmd(*sCtx);
  EXPECT_THROW(fill.execute(cmd.handle(), nullptr, {src}, {larger}, VolumeFillPass::Method::Compute), Error);
  cmd.submitAndWait();
}

// ShadowMapPass: the depth maps against Embree rays along the same texel rays (a sun and a sphere light's
// cube map), then the PCF lookups against the CPU lookups of the GPU's depths (exact: the same code).
TEST_F(Render, ShadowMapPassEqualsEmbreeDepthsAndTheCpuLookup) {
  Scene scene = defaultScene();
  Light lamp;
  lamp.name = "lamp";
  lamp.type = Light::Type::Sphere;
  lamp.position = glm::dvec3(-0.3, 0.8, 0.2);
  lamp.radius = 0.05;
  scene.lights.push_back(lamp);
  RenderSettings s = small(ShadowTechnique::ShadowMap);
  s.shadowMap.resolution = 128;
  Renderer r(*sCtx, scene, boundsOf(scene), s);
  const RenderedFrame f = r.renderFrame(0.0);
  const std::vector<float> gpuDepth = r.shadowMapDepths();
  // The CPU reference works in the renderer's frame, as the passes do.
  const auto& lights = r.gpuLights();
  const std::vector<float> cpuDepth =
      shadowMapDepthsCpu(buildSceneGeometry(scene, 0.0, r.frameOrigin()), lights, r.shadowMapParams());
  ASSERT_EQ(gpuDepth.size(), cpuDepth.size());
  std::size_t used = 0, differ = 0, hits = 0;
  for (std::size_t l = 0; l < lights.size(); ++l) {
    const std::size_t n = 128, faces = l == 0 ? 1 : 6;
    for (std::size_t k = l * 6 * n * n; k < l * 6 * n * n + faces * n * n; ++k) {
      ++used;
      const float a = gpuDepth[k], b = cpuDepth[k];
      if (b < 1e30f) ++hits;
      if (!(std::fabs(a - b) <= 1e-4f * std::max(1.0f, b)) && !(a >= 1e30f && b >= 1e30f)) ++differ;
    }
  }
  EXPECT_GT(hits, used / 3); // the room is open above and in front: many cube-map texels see the sky
  EXPECT_LE(differ, used / 500) << differ << " of " << used << " texels differ";
  const LightVisibility cpuVis = shadowMapLookupCpu(f.gbuffer, gpuDepth, lights, r.shadowMapParams());
  for (std::size_t l = 0; l < lights.size(); ++l) {
    EXPECT_EQ(countAbove(f.visibility[l], cpuVis[l], 1e-6f), 0u) << "light " << l;
    std::size_t shadowed = 0;
    for (float v : cpuVis[l]) shadowed += v < 0.5f;
    EXPECT_GT(shadowed, 50u) << "light " << l;
  }
}

// TaaPass over a moving scene against the CPU step applied to the same raw frames.
TEST_F(Render, TaaPassEqualsTheCpuAccumulation) {
  const Scene scene = defaultScene();
  RenderSettings s = small(ShadowTechnique::ShadowMap);
  s.shadowMap.resolution = 256;
  s.taa.enabled = true;
  s.taa.blend = 0.3;
  Renderer r(*sCtx, scene, boundsOf(scene), s);
  LightVisibility history;
  RenderedFrame f;
  for (int k = 1; k <= 4; ++k) {
    f = r.renderFrame(0.25 * k);
    const LightVisibility raw = r.rawVisibility();
    if (history.empty()) history = raw;
    sh::TaaParams p{};
    p.image = glm::ivec4(s.width, s.height, 1, k);
    p.blend = 0.3f;
    p.clampHistory = 1u;
    taaCpu(raw, history, p);
  }
  EXPECT_EQ(countAbove(f.visibility[0], history[0], 1e-6f), 0u);
}

/// A TaaPass over a small image of one constant value: step() runs one frame on the history it holds and
/// returns the value it leaves (every pixel must agree).
class TaaRig {
public:
  explicit TaaRig(gpu::VulkanContext& ctx) : mCtx(ctx), mPass(ctx) {}
  void setHistory(float value) { gpu::upload(mCtx, mHistory, std::vector<float>(kPixels, value).data(), kBytes); }
  double step(int frame, float blend, float input, bool clamp = false) {
    gpu::upload(mCtx, mCurrent, std::vector<float>(kPixels, input).data(), kBytes);
    sh::TaaParams p{};
    p.image = glm::ivec4(kWidth, kHeight, 1, frame);
    p.blend = blend;
    p.clampHistory = clamp ? 1u : 0u;
    gpu::CommandBuffer cmd(mCtx);
    mPass.execute(cmd.handle(), nullptr, {mCurrent}, {mHistory}, p);
    cmd.submitAndWait();
    std::vector<float> out(kPixels);
    gpu::download(mCtx, mHistory, out.data(), kBytes);
    for (float v : out) EXPECT_EQ(v, out[0]);
    return double(out[0]);
  }

private:
  static constexpr int kWidth = 8, kHeight = 4;
  static constexpr std::size_t kPixels = std::size_t(kWidth) * kHeight, kBytes = kPixels * sizeof(float);
  gpu::VulkanContext& mCtx;
  const gpu::Buffer mCurrent{mCtx, kBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "current"};
  const gpu::Buffer mHistory{mCtx, kBytes, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, gpu::Buffer::Memory::Device, "history"};
  const TaaPass mPass;
};

// TaaPass against its closed form, independent of the shared taaResolve: with history h and a constant current
// frame c, the result is c on the first frame, h + (c - h) max(blend, 1 / frame) later, and c again when the
// history is clamped into the (constant) neighbourhood of the current frame.
TEST_F(Render, TaaPassFollowsTheClosedFormBlendAndClamp) {
  TaaRig taa(*sCtx);
  struct Case { int frame; bool clamp; float blend; float expected; };
  for (const Case& c : {Case{1, false, 0.1f, 0.8f}, Case{5, false, 0.1f, 0.2f + 0.6f * 0.2f},
                        Case{20, false, 0.1f, 0.2f + 0.6f * 0.1f}, Case{20, false, 0.5f, 0.5f},
                        Case{5, true, 0.1f, 0.8f}}) {
    taa.setHistory(0.2f);
    EXPECT_NEAR(taa.step(c.frame, c.blend, 0.8f, c.clamp), c.expected, 1e-6) << "frame " << c.frame << " clamp "
                                                                              << c.clamp;
  }
  EXPECT_EQ(sCtx->validationErrors(), 0u);
}

// TaaPass over many frames against closed forms of the accumulation: while 1 / frame >= blend every frame
// weighs the same (the running mean), and inputs alternating 1, 0 settle at the fixed point of
// x = blend + (1 - blend) y, y = (1 - blend) x: x = 1 / (2 - blend) after a 1, y = (1 - blend) / (2 - blend) after a 0.
TEST_F(Render, TaaPassAccumulatesTheRunningMeanThenTheExponentialAverage) {
  TaaRig taa(*sCtx);
  const float inputs[] = {0.3f, 0.9f, 0.0f, 0.5f, 1.0f, 0.2f, 0.7f, 0.4f, 0.8f, 0.1f};
  double sum = 0.0;
  for (int k = 1; k <= 10; ++k) {
    sum += inputs[k - 1];
    EXPECT_NEAR(taa.step(k, 0.1f, inputs[k - 1]), sum / k, 1e-6) << "frame " << k;
  }
  const double b = 0.3;
  double afterOne = 0.0, afterZero = 0.0;
  for (int k = 1; k <= 60; ++k) (k % 2 ? afterOne : afterZero) = taa.step(k, float(b), float(k % 2));
  // 28 alternations after the running mean leave 0.49^28 ~ 2e-9 of the start.
  EXPECT_NEAR(afterOne, 1.0 / (2.0 - b), 1e-6);
  EXPECT_NEAR(afterZero, (1.0 - b) / (2.0 - b), 1e-6);
  EXPECT_EQ(sCtx->validationErrors(), 0u);
}

/// Shadow maps of @a mapRes texels per side for a square picture of @a pixels.
RenderSettings plateShadowMaps(int pixels, int mapRes) {
  RenderSettings s = small(ShadowTechnique::ShadowMap, pixels, pixels);
  s.shadowMap.resolution = mapRes;
  return s;
}

// Shadow maps with PCF against the geometric truth, independent of the shared lookup code: a sun straight
// down over a floor half covered by a plate, seen from below the plate's height. Away from the plate's edge
// (more than the PCF kernel and the bias), the floor is exactly shadowed under the plate and exactly lit
// beside it.
TEST_F(Render, ShadowMapsAreExactAwayFromShadowEdges) {
  const Scene scene = plateScene();
  Renderer r(*sCtx, scene, boundsOf(scene), plateShadowMaps(120, 512));
  const RenderedFrame f = r.renderFrame(0.0);
  std::size_t shadowed = 0, lit = 0;
  for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
    const glm::dvec3 q = f.gbuffer.worldPosition(i);
    if (!f.gbuffer.hit(i) || std::fabs(q.y) > 0.05f) continue; // the floor only
    const float v = f.visibility[0][i];
    if (q.x < -0.08f && q.x > -0.92f && std::fabs(q.z) < 0.92f) {
      ASSERT_EQ(v, 0.0f) << "under the plate at " << q.x << ", " << q.z;
      ++shadowed;
    } else if (q.x > 0.08f) {
      ASSERT_EQ(v, 1.0f) << "beside the plate at " << q.x << ", " << q.z;
      ++lit;
    }
  }
  EXPECT_GT(shadowed, 300u);
  EXPECT_GT(lit, 300u);
}

// PCF across the plate's straight edge against the fraction of the kernel's texels whose centre the plate
// covers, counted from the geometry (not from the depth map, nor with the shared lookup): with the sun straight
// down each texel's centre lies right above the floor point it shadows. Coarse texels make the ramp wide.
TEST_F(Render, PcfAtAStraightEdgeIsTheFractionOfCoveredTexels) {
  const Scene scene = plateScene();
  Renderer r(*sCtx, scene, boundsOf(scene), plateShadowMaps(240, 64));
  const RenderedFrame f = r.renderFrame(0.0);
  const sh::ShadowMapParams m = r.shadowMapParams()[0];
  const int res = m.info.x, rad = m.image.z;
  const glm::dvec3 c(glm::vec3(m.center)), right(glm::vec3(m.right)), up(glm::vec3(m.up));
  const double half = m.center.w;
  auto texels = [&](const glm::dvec3& q, const glm::dvec3& axis) { // map coordinate in texels
    return (glm::dot(q - c, axis) / half + 1.0) * 0.5 * res;
  };
  auto centreX = [&](int i, int j) { // world x of texel (i, j)'s centre
    auto at = [&](int k) { return 2.0 * (std::clamp(k, 0, res - 1) + 0.5) / res - 1.0; };
    return (c + (at(i) * right + at(j) * up) * half + r.frameOrigin()).x;
  };
  std::size_t checked = 0, ramp = 0;
  for (std::size_t i = 0; i < f.gbuffer.pixelCount(); ++i) {
    const glm::dvec3 q(glm::vec3(f.gbuffer.position[i])), w = f.gbuffer.worldPosition(i);
    if (!f.gbuffer.hit(i) || std::fabs(w.y) > 0.05 || std::fabs(w.x) > 0.5 || std::fabs(w.z) > 0.8) continue;
    const double u = texels(q, right), v = texels(q, up);
    if (std::fabs(u - std::round(u)) < 1e-3 || std::fabs(v - std::round(v)) < 1e-3) continue; // on a texel border
    int covered = 0;
    bool onEdge = false;
    for (int dy = -rad; dy <= rad; ++dy)
      for (int dx = -rad; dx <= rad; ++dx) {
        const double x = centreX(int(std::floor(u)) + dx, int(std::floor(v)) + dy);
        covered += x < 0.0;
        onEdge |= std::fabs(x) < 1e-4;
      }
    if (onEdge) continue;
    const double expected = 1.0 - covered / double((2 * rad + 1) * (2 * rad + 1));
    ASSERT_NEAR(f.visibility[0][i], expected, 1e-6) << "floor at " << w.x << ", " << w.z;
    ++checked;
    ramp += expected > 0.0 && expected < 1.0;
  }
  std::printf("PCF edge: %zu floor pixels checked, %zu on the ramp\n", checked, ramp);
  EXPECT_GT(checked, 1000u);
  EXPECT_GT(ramp, 150u) << "pixels on the PCF ramp"; // 1374 and 248 at 240x240
}

namespace {
RenderedFrame truthOf(const Scene& scene, double t, int w, int h, int samples = 256) {
  RenderSettings s = small(ShadowTechnique::RayTraced, w, h);
  s.rayTraced.samples = samples;
  return renderRayTraced(scene, t, s);
}
} // namespace

// The analytic scene: a sphere over a floor under a 4-degree sun; the ray tracer matches the closed form
// there (test_shadow_reference). The SDF penumbra (centred estimate, fine 128) must match the truth
// within an RMSE of 0.08 over the penumbra (measured 0.059 at 160x90; 0.030 with no bias, which the default
// scene's box edges need) and beat the shadow map (measured
// 0.19: a fixed PCF kernel cannot widen with the distance to the occluder). The paper's classic estimate
// shrinks the penumbra to its outer half: it must be worse than the centred one. The SDF-simulated umbra (16
// centred marches over sixteenths of the sun's disc, no jitter) must beat the centred estimate (measured
// 0.048 vs 0.059) and keep the sphere's umbra dark.
TEST_F(Render, AnalyticPenumbraMatchesTheTruth) {
  const Scene scene = analyticScene();
  const int w = 160, h = 90;
  const RenderedFrame truth = truthOf(scene, 0.0, w, h);
  // The truth itself against the closed form, per floor pixel.
  std::size_t floorPixels = 0;
  double maxDiff = 0.0;
  const glm::dvec3 toLight = -glm::normalize(scene.lights[0].direction);
  for (std::size_t i = 0; i < truth.gbuffer.pixelCount(); ++i) {
    if (!truth.gbuffer.hit(i) || std::fabs(truth.gbuffer.position[i].y) > 1e-3f) continue;
    ++floorPixels;
    const double exact = sunVisibilityPastSphere(glm::dvec3(glm::vec3(truth.gbuffer.position[i])), toLight,
                                                 scene.lights[0].angularRadius, glm::dvec3(0.0, 0.5, 0.0), 0.25);
    maxDiff = std::max(maxDiff, std::fabs(exact - truth.visibility[0][i]));
  }
  EXPECT_GT(floorPixels, truth.gbuffer.pixelCount() / 2);
  EXPECT_LT(maxDiff, 0.08);

  auto sdfError = [&](PenumbraEstimate p) {
    RenderSettings s = small(ShadowTechnique::Sdf, w, h);
    s.sdf.penumbra = p;
    s.sdf.lightSamples = 16;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    const RenderedFrame f = r.renderFrame(0.0);
    expectAllFinite(f);
    return compareWithTruth(scene, f, truth);
  };
  const ShadowImageError centred = sdfError(PenumbraEstimate::Centered);
  const ShadowImageError classic = sdfError(PenumbraEstimate::Classic);
  const ShadowImageError umbra = sdfError(PenumbraEstimate::Umbra);
  RenderSettings sm = small(ShadowTechnique::ShadowMap, w, h);
  Renderer smr(*sCtx, scene, boundsOf(scene), sm);
  const ShadowImageError map = compareWithTruth(scene, smr.renderFrame(0.0), truth);
  std::printf("analytic penumbra RMSE: centred %.4f, umbra (16 samples) %.4f, classic %.4f, shadow map %.4f (%zu "
              "pixels)\n",
              centred.penumbraRmse, umbra.penumbraRmse, classic.penumbraRmse, map.penumbraRmse, centred.penumbraPixels);
  EXPECT_GT(centred.penumbraPixels, std::size_t(w * h / 5));
  EXPECT_LT(centred.penumbraRmse, 0.08);
  EXPECT_LT(centred.penumbraRmse, map.penumbraRmse);
  EXPECT_LT(centred.penumbraRmse, classic.penumbraRmse);
  EXPECT_LT(umbra.penumbraRmse, centred.penumbraRmse);
  EXPECT_LT(umbra.umbraMeanAbs, 0.01);
}

// The image error keeps the truth's umbra (V < 0.02) apart from its penumbra: light added only in the umbra
// shows in the umbra's mean |diff| (exactly what was added) and the whole picture's, never in the penumbra's.
TEST_F(Render, ImageErrorReportsLightLeakingIntoTheUmbra) {
  const Scene scene = analyticScene();
  const RenderedFrame truth = truthOf(scene, 0.0, 80, 45, 64);
  RenderedFrame leak = truth;
  for (float& v : leak.visibility[0])
    if (v < 0.02f) v += 0.25f;
  const ShadowImageError e = compareWithTruth(scene, leak, truth);
  EXPECT_GT(e.umbraPixels, 100u);
  EXPECT_GT(e.penumbraPixels, 100u);
  EXPECT_NEAR(e.umbraMeanAbs, 0.25, 1e-6);
  EXPECT_EQ(e.penumbraRmse, 0.0);
  EXPECT_NEAR(e.visibilityMeanAbs, 0.25 * double(e.umbraPixels) / double(e.pixels), 1e-6);
  const ShadowImageError same = compareWithTruth(scene, truth, truth);
  EXPECT_EQ(same.umbraMeanAbs, 0.0);
  EXPECT_EQ(same.umbraPixels, e.umbraPixels);
}

// The default scene at 320x180 against the ray-traced truth, SDF at fine 256 (the size `render` uses; the
// sun's penumbrae are one or two voxels wide at 128) with the default march settings, and the 1024^2 shadow
// map with PCF. Measured: penumbra RMSE (truth in (0.02, 0.98)) 0.0995 vs 0.153 over 244 pixels, mean
// |error| over lit surfaces 0.0008 vs 0.0066, FLIP 0.0018 vs 0.0086, umbra mean |diff| 0.0167 vs 0.0424
// (0.126, 0.0023, 0.0049 and about twice the shadow map's umbra error before the lateral probes). The SDF
// must be closer on all four.
TEST_F(Render, SdfShadowsAreCloserToTheTruthThanShadowMapsOnTheDefaultScene) {
  const Scene scene = defaultScene();
  const int w = 320, h = 180;
  const RenderedFrame truth = truthOf(scene, 0.0, w, h, 256);
  RenderSettings s = small(ShadowTechnique::Sdf, w, h);
  s.pipeline.fineRes = 256;
  Renderer sdf(*sCtx, scene, boundsOf(scene), s);
  const ShadowImageError es = compareWithTruth(scene, sdf.renderFrame(0.0), truth);
  Renderer map(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::ShadowMap, w, h));
  const ShadowImageError em = compareWithTruth(scene, map.renderFrame(0.0), truth);
  std::printf("default scene: SDF mean |err| %.4f FLIP %.4f penumbra RMSE %.4f umbra mean |diff| %.4f; shadow map "
              "%.4f, %.4f, %.4f, %.4f\n",
              es.visibilityMeanAbs, es.flip, es.penumbraRmse, es.umbraMeanAbs, em.visibilityMeanAbs, em.flip,
              em.penumbraRmse, em.umbraMeanAbs);
  EXPECT_GT(es.penumbraPixels, 200u);
  EXPECT_LT(es.penumbraRmse, em.penumbraRmse);
  EXPECT_LT(es.visibilityMeanAbs, em.visibilityMeanAbs);
  EXPECT_LT(es.flip, em.flip);
  EXPECT_GT(es.umbraPixels, 200u);
  EXPECT_LT(es.umbraMeanAbs, em.umbraMeanAbs);
}

// What the contact rays are for: the default scene's light in the umbra comes mostly from receivers within a voxel
// of another surface (the floor seen through the 0.002 gap under the walls, the creases of the couch), which the
// 256^3 SDF cannot resolve. Against the ray-traced truth, at fine 256 as `render` runs, the umbra error must at
// least halve and the penumbra error must not grow.
TEST_F(Render, ContactRaysDarkenTheUmbraTheSdfCannotResolve) {
  const Scene scene = defaultScene();
  const int w = 320, h = 180;
  const RenderedFrame truth = truthOf(scene, 0.0, w, h, 256);
  ShadowImageError e[2];
  for (int rays : {0, 4}) {
    RenderSettings s = small(ShadowTechnique::Sdf, w, h);
    s.pipeline.fineRes = 256;
    s.sdf.contactRays = rays;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    e[rays > 0] = compareWithTruth(scene, r.renderFrame(0.0), truth);
  }
  std::printf("default scene, contact rays 0 / 4: penumbra RMSE %.4f / %.4f, umbra mean |diff| %.4f / %.4f\n",
              e[0].penumbraRmse, e[1].penumbraRmse, e[0].umbraMeanAbs, e[1].umbraMeanAbs);
  ASSERT_GT(e[0].umbraPixels, 200u);
  EXPECT_LT(e[1].umbraMeanAbs, 0.5 * e[0].umbraMeanAbs);
  EXPECT_LE(e[1].penumbraRmse, e[0].penumbraRmse + 1e-3);
}

// The orbiting teapot at 4 frames per second of scene time (it moves about 10 cm a frame). After 8 frames
// with TAA, where the truth had its shadow 4 frames ago and has none now, the TAA frame may be darker than
// a frame rendered afresh at the same moment (no history) by at most 0.1 on average. Without the
// neighbourhood clamp the history keeps the stale shadow: that case must be worse.
TEST_F(Render, ShadowsFollowTheOrbitingTeapot) {
  const Scene scene = defaultScene();
  const int w = 320, h = 180;
  const double fps = 4.0, tEnd = 7.0 / fps;
  const RenderedFrame now = truthOf(scene, tEnd, w, h, 32), before = truthOf(scene, tEnd - 4.0 / fps, w, h, 32);
  Bounds bounds;
  for (int f = 0; f < 8; ++f) bounds.add(boundsOf(scene, f / fps));
  RenderSettings s = small(ShadowTechnique::Sdf, w, h);
  s.pipeline.coarseRes = 48;
  s.pipeline.fineRes = 96;
  s.pipeline.rays = 0; // closest mode signed by the closest triangle: no decayed sign votes to lag behind
  s.taa.blend = 0.1;
  Renderer freshRenderer(*sCtx, scene, bounds, s);
  const RenderedFrame fresh = freshRenderer.renderFrame(tEnd);
  auto staleDarkness = [&](bool clamp) {
    s.taa.enabled = true;
    s.taa.clampHistory = clamp;
    Renderer r(*sCtx, scene, bounds, s);
    RenderedFrame f;
    for (int k = 0; k < 8; ++k) f = r.renderFrame(k / fps, k == 7);
    double deficit = 0.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < now.gbuffer.pixelCount(); ++i) {
      if (!(before.visibility[0][i] < 0.5f && now.visibility[0][i] > 0.9f)) continue;
      deficit += fresh.visibility[0][i] - f.visibility[0][i];
      ++n;
    }
    EXPECT_GT(n, 40u);
    return n ? deficit / double(n) : 1.0;
  };
  const double clamped = staleDarkness(true), unclamped = staleDarkness(false);
  std::printf("stale shadow darkness: clamped %.4f, unclamped %.4f\n", clamped, unclamped);
  EXPECT_LT(clamped, 0.1);
  EXPECT_GT(unclamped, clamped + 0.05);
}

// Every EXR written is read back, with every channel finite, at the extremes: the camera inside a box, a
// sun grazing the floor, zero-radius and huge lights (sun 89 degrees, a sphere light around the room).
TEST_F(Render, ExtremesGiveFiniteImagesThatReadBack) {
  const test::TempDir dir;
  std::vector<Scene> scenes;
  Scene inside = defaultScene();
  inside.camera.position = glm::dvec3(inside.instances[3].transform.translation); // inside the couch seat
  inside.camera.target = inside.camera.position + glm::dvec3(1.0, 0.0, 0.0);
  scenes.push_back(inside);
  Scene grazing = defaultScene();
  grazing.lights[0].direction = glm::dvec3(1.0, -1e-4, 0.0);
  scenes.push_back(grazing);
  Scene point = defaultScene();
  point.lights[0].angularRadius = 0.0;
  Light bulb;
  bulb.type = Light::Type::Sphere;
  bulb.position = glm::dvec3(0.0, 0.7, 0.0);
  bulb.radius = 0.0;
  point.lights.push_back(bulb);
  scenes.push_back(point);
  Scene huge = defaultScene();
  huge.lights[0].angularRadius = glm::radians(89.0);
  Light dome = bulb;
  dome.radius = 10.0; // every surface is inside the light
  huge.lights.push_back(dome);
  scenes.push_back(huge);
  int k = 0;
  for (const Scene& scene : scenes) {
    for (ShadowTechnique t : {ShadowTechnique::Sdf, ShadowTechnique::ShadowMap, ShadowTechnique::RayTraced}) {
      RenderSettings s = small(t, 48, 27);
      s.pipeline.coarseRes = 32;
      s.pipeline.fineRes = 64;
      s.shadowMap.resolution = 128;
      s.rayTraced.samples = 16;
      s.taa.enabled = true;
      s.sdf.contactRays = 64; // and the contact rays at their extremes: every ray, the longest reach
      s.sdf.contactVoxels = 64.0;
      RenderedFrame f;
      if (t == ShadowTechnique::RayTraced) {
        f = renderRayTraced(scene, 0.0, s);
      } else {
        Renderer r(*sCtx, scene, boundsOf(scene), s);
        for (int i = 0; i < 2; ++i) f = r.renderFrame(0.1 * i);
      }
      expectAllFinite(f);
      const auto path = dir / ("frame" + std::to_string(k++) + ".exr");
      const Image img = composeImage(scene, f);
      writeExr(path, img);
      const Image back = readExr(path);
      ASSERT_EQ(back.channelNames().size(), img.channelNames().size());
      for (const std::string& c : img.channelNames()) {
        ASSERT_EQ(back.channel(c), img.channel(c)) << c;
        for (float v : back.channel(c)) ASSERT_TRUE(std::isfinite(v)) << c;
      }
    }
  }
}

TEST_F(Render, BadSettingsAndScenesAreClearErrors) {
  Scene scene = defaultScene();
  RenderSettings s = small(ShadowTechnique::Sdf);
  s.sdf.epsilonVoxels = 0.5;
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), s), Error);
  s = small(ShadowTechnique::Sdf);
  s.sdf.minStepVoxels = 0.01;
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), s), Error);
  s.sdf.minStepVoxels = std::nan("");
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), s), Error);
  s = small(ShadowTechnique::Sdf);
  s.sdf.biasVoxels = -0.1;
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), s), Error);
  s = small(ShadowTechnique::ShadowMap);
  s.taa.blend = 0.0;
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), s), Error);
  scene.hasCamera = false;
  EXPECT_THROW(Renderer(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::ShadowMap)), Error);
  scene = defaultScene();
  scene.lights.clear();
  EXPECT_THROW(renderRayTraced(scene, 0.0, small(ShadowTechnique::RayTraced)), Error);
}


namespace {
/// Byte @a c (0 R, 1 G, 2 B) of packed pixel @a p in @a order.
int channelOf(std::uint32_t p, int c, std::uint32_t order) {
  const int shift = 8 * (order == sh::kComposeBgra ? 2 - c : c);
  return int((p >> shift) & 0xFFu);
}
} // namespace

// ComposePass against composePixelsCpu on the default scene's SDF frame, in each view (the slice through the
// table and the bunny; two cascade levels for the level view), both byte orders and with a strip of text; its shaded
// picture against the bytes `render` writes (composeImage, displayImage, writePng's rounding); and the level view
// against the shaded picture tinted half way to level 0's red where a plain box test puts the point more than a
// voxel inside level 0, else to level 1's orange. GPU exp/pow may round the last bit differently: one step of 255 at
// most.
TEST_F(Render, ComposePassEqualsItsCpuReference) {
  const Scene scene = defaultScene();
  const int w = 320, h = 180;
  Renderer r(*sCtx, scene, boundsOf(scene), small(ShadowTechnique::Sdf, w, h));
  const RenderedFrame frame = r.renderFrame(0.0);
  const SdfPipeline& sdf = *r.sdfPipeline();
  const std::vector<float> fine = sdf.fineField(), coarse = sdf.coarseField();
  const GridSpec f = sdf.fineSpec().inFrame(r.frameOrigin()), c = sdf.coarseSpec().inFrame(r.frameOrigin());
  const int rows = 12;
  std::vector<std::uint8_t> text(std::size_t(w) * rows, 0);
  for (std::size_t i = 0; i < text.size(); ++i) text[i] = (i / 3 + i / std::size_t(w)) % 5 == 0;
  std::vector<std::uint32_t> packed((text.size() + 3) / 4, 0u);
  for (std::size_t i = 0; i < text.size(); ++i) packed[i / 4] |= std::uint32_t(text[i]) << (8 * (i % 4));
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  gpu::Buffer overlay(*sCtx, packed.size() * 4, storage, gpu::Buffer::Memory::Device, "overlay");
  upload(*sCtx, overlay, packed.data(), packed.size() * 4);
  gpu::Buffer pixels(*sCtx, std::size_t(w) * h * 4, storage, gpu::Buffer::Memory::Device, "pixels");
  ComposePass pass(*sCtx);
  std::vector<std::uint32_t> shaded;
  // Level 0: the fine grid's lower corner at half its voxel (an eighth of its volume); level 1: the whole grid.
  const glm::vec3 lo0(f.origin);
  const float h0 = 0.5f * float(f.voxelSize);
  const glm::vec3 hi0 = lo0 + glm::vec3(f.dims) * h0;
  for (std::uint32_t view : {sh::kViewShaded, sh::kViewSlice, sh::kViewMask, sh::kViewLevels}) {
    SCOPED_TRACE(fmt::format("view {}", view));
    sh::ComposeParams p{};
    p.camera = r.cameraParams();
    p.image = glm::ivec4(w, h, int(scene.lights.size()), int(view));
    p.fineDims = glm::ivec4(f.dims, view == sh::kViewShaded ? 0 : rows);
    p.fineOriginH = glm::vec4(glm::vec3(f.origin), float(f.voxelSize));
    p.coarseDims = glm::ivec4(c.dims, int(view == sh::kViewMask ? sh::kComposeBgra : sh::kComposeRgba));
    p.coarseOriginH = glm::vec4(glm::vec3(c.origin), float(c.voxelSize));
    const double middle = boundsOf(scene).center().y - r.frameOrigin().y; // the viewer's default slice
    p.slice = glm::vec4(float(middle), 0.1f, 0.1f, 0.0f);
    if (view == sh::kViewLevels) {
      p.cascade.x = 2;
      p.levels[0] = {glm::vec4(lo0, h0), glm::ivec4(f.dims, 0), glm::vec4(4.0f * h0, 0.0f, 0.0f, 0.0f)};
      p.levels[1] = {glm::vec4(lo0, float(f.voxelSize)), glm::ivec4(f.dims, 0), glm::vec4(0.0f)};
    }
    gpu::CommandBuffer cmd(*sCtx);
    pass.execute(cmd.handle(), nullptr,
                 {r.gpuGBuffer(), r.gpuVisibility(), r.gpuLightBuffer(), sdf.fineBuffer(), sdf.coarseBuffer(), overlay},
                 {pixels}, p);
    cmd.submitAndWait();
    std::vector<std::uint32_t> gpuPixels(std::size_t(w) * h);
    download(*sCtx, pixels, gpuPixels.data(), gpuPixels.size() * 4);
    const std::vector<std::uint32_t> cpu =
        composePixelsCpu(frame.gbuffer, frame.visibility, r.gpuLights(), fine, coarse, text, p);
    const std::uint32_t order = std::uint32_t(p.coarseDims.w);
    int worst = 0;
    std::size_t differ = 0, changed = 0;
    for (std::size_t i = 0; i < cpu.size(); ++i) {
      for (int ch = 0; ch < 3; ++ch)
        worst = std::max(worst, std::abs(channelOf(gpuPixels[i], ch, order) - channelOf(cpu[i], ch, order)));
      differ += gpuPixels[i] != cpu[i];
      ASSERT_EQ(gpuPixels[i] >> 24, 255u);
      if (!shaded.empty() && i >= std::size_t(w) * rows)
        for (int ch = 0; ch < 3; ++ch)
          changed += channelOf(gpuPixels[i], ch, order) != channelOf(shaded[i], ch, sh::kComposeRgba);
    }
    EXPECT_LE(worst, 1);
    EXPECT_LT(double(differ), 0.02 * double(cpu.size()));
    if (view == sh::kViewShaded) {
      shaded = gpuPixels;
      const Image display = displayImage(composeImage(scene, frame));
      for (std::size_t i = 0; i < cpu.size(); ++i)
        for (int ch = 0; ch < 3; ++ch) {
          const float linear = display.channel(ch == 0 ? "R" : ch == 1 ? "G" : "B")[i];
          const int written = int(std::lround(linearToSrgb(linear) * 255.0f));
          ASSERT_LE(std::abs(channelOf(gpuPixels[i], ch, order) - written), 1) << "pixel " << i;
        }
    } else {
      EXPECT_GT(changed, cpu.size() / 10) << "the slice plane covers too little of the picture";
    }
    if (view != sh::kViewLevels) continue;
    std::size_t inLevel[2] = {0, 0};
    for (std::size_t i = std::size_t(w) * rows; i < cpu.size(); ++i) {
      if (!frame.gbuffer.hit(i)) continue;
      const glm::vec3 pos(frame.gbuffer.position[i]);
      const bool level0 = glm::all(glm::greaterThan(pos, lo0 + h0)) && glm::all(glm::lessThan(pos, hi0 - h0));
      ++inLevel[level0 ? 0 : 1];
      const glm::vec3 tint = level0 ? glm::vec3(0.90f, 0.25f, 0.20f) : glm::vec3(0.95f, 0.55f, 0.15f);
      for (int ch = 0; ch < 3; ++ch) {
        const float expected = 0.5f * float(channelOf(shaded[i], ch, sh::kComposeRgba)) + 0.5f * 255.0f * tint[ch];
        ASSERT_LE(std::fabs(float(channelOf(gpuPixels[i], ch, order)) - expected), 1.5f) << "pixel " << i;
      }
    }
    EXPECT_GT(inLevel[0], 1000u);
    EXPECT_GT(inLevel[1], 1000u);
  }
}

// The 3D texture the march samples is filled only in frames that wrote the fine SDF (FrameStats::fieldChanged): the
// orbiting teapot moving, still for three frames, moving again gives the same visibility bit for bit as a renderer
// whose pipeline rebuilds every pass, and the still frames after the band settled copy nothing.
// VolumeUpdatePass after every frame of an SdfPipeline (the first filled whole by VolumeFillPass) must leave the
// texture holding the dense fine SDF bit for bit, read back by a copy of the whole texture, over the orbiting teapot
// moving, standing still and moving again. Rays mode: a refinement changes its voxels' values every frame (the
// history decays towards the ray hits), so the still frames write the band without upsampling anything. Without the
// refined voxels' dispatch, or the blocks', the texture keeps stale values. (The renderer updates so on a GPU; a CPU
// device fills whole: SdfShadowPass::Inputs::fillOnly.)
TEST_F(Render, TheTextureUpdatedWhereTheFrameWroteHoldsTheFineSdf) {
  const Scene scene = defaultScene();
  PipelineSettings s;
  s.band = 0.05;
  s.coarseRes = 40;
  s.fineRes = 80;
  s.mode = RefineMode::Rays;
  s.rays = 4;
  const std::vector<double> times = {0.0, 0.1, 0.2, 0.3, 0.3, 0.3, 0.3, 0.7, 0.8};
  Bounds bounds;
  for (const double t : times) bounds.add(boundsOf(scene, t));
  SdfPipeline pipe(*sCtx, scene, bounds, s);
  const glm::uvec3 dims(pipe.fineSpec().dims);
  const gpu::SampledVolume texture(*sCtx, dims, "texture");
  gpu::Buffer back;
  gpu::reserve(*sCtx, back, pipe.fineSpec().voxelCount() * 4, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               gpu::Buffer::Memory::Device, "back");
  const VolumeFillPass fill(*sCtx);
  const VolumeUpdatePass update(*sCtx);
  ASSERT_TRUE(update.available()) << sCtx->info().name << " cannot store to R32F 3D textures";
  int updated = 0, refinedOnly = 0, withBlocks = 0;
  for (std::size_t f = 0; f < times.size(); ++f) {
    SCOPED_TRACE(::testing::Message() << "frame " << f + 1 << " at t = " << times[f]);
    const FrameStats stats = pipe.runFrame(times[f]);
    const DenseFineWrites& writes = pipe.lastFineWrites();
    EXPECT_EQ(writes.frame, f + 1);
    if (f == 0) ASSERT_EQ(writes.extent, DenseFineWrites::Extent::Whole);
    gpu::CommandBuffer cmd(*sCtx);
    if (writes.extent == DenseFineWrites::Extent::Whole) {
      fill.execute(cmd.handle(), nullptr, {pipe.fineBuffer()}, {texture}, VolumeFillPass::Method::Transfer);
    } else if (writes.extent == DenseFineWrites::Extent::Listed) {
      update.execute(cmd.handle(), nullptr, {pipe.fineBuffer(), writes}, {texture}, writes.params);
      ++updated;
      refinedOnly += writes.refineList && !writes.blockList;
      withBlocks += writes.blockList != nullptr;
      EXPECT_LT(stats.upsampledFineVoxels + stats.refinedFineVoxels, pipe.fineSpec().voxelCount())
          << "a listed frame writes part of the grid";
    }
    texture.copyTo(cmd.handle(), back);
    cmd.submitAndWait();
    std::vector<float> got(pipe.fineSpec().voxelCount());
    gpu::download(*sCtx, back, got.data(), got.size() * 4);
    const std::vector<float> field = pipe.fineField();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < field.size(); ++i) differ += std::memcmp(&got[i], &field[i], 4) != 0;
    EXPECT_EQ(differ, 0u) << "of " << field.size() << " texels";
  }
  EXPECT_GE(updated, 6) << "the frames after the first write part of the grid";
  EXPECT_GE(refinedOnly, 2) << "frames whose refinement alone wrote (the teapot still)";
  EXPECT_GE(withBlocks, 3) << "frames whose upsampling wrote listed blocks (the teapot moving)";
  gpu::CommandBuffer cmd(*sCtx);
  DenseFineWrites whole = pipe.lastFineWrites();
  whole.extent = DenseFineWrites::Extent::Whole;
  EXPECT_THROW(update.execute(cmd.handle(), nullptr, {pipe.fineBuffer(), whole}, {texture}, whole.params), Error);
  cmd.submitAndWait();
}

TEST_F(Render, TheTextureIsFilledOnlyWhenTheFieldChanged) {
  const Scene scene = defaultScene();
  RenderSettings s = small(ShadowTechnique::Sdf);
  s.sdf.sampling = SdfSampling::Texture;
  s.pipeline.band = 0.05;
  s.pipeline.rays = 0;
  s.pipeline.coarseRes = 40;
  s.pipeline.fineRes = 80;
  const std::vector<double> times = {0.0, 0.4, 0.4, 0.4, 0.4, 0.8};
  Bounds bounds;
  for (const double t : times) bounds.add(boundsOf(scene, t));
  Renderer skipping(*sCtx, scene, bounds, s);
  s.pipeline.fullRebuild = true;
  Renderer rebuilt(*sCtx, scene, bounds, s);
  ASSERT_EQ(skipping.sdfSampling(), SdfSampling::Texture);
  for (std::size_t f = 0; f < times.size(); ++f) {
    SCOPED_TRACE(::testing::Message() << "frame " << f + 1);
    const RenderedFrame a = skipping.renderFrame(times[f]), b = rebuilt.renderFrame(times[f]);
    // Frame 3 still runs the mask (frame 2 refined voxels near the teapot); 4 and 5 run nothing.
    const bool filled = f < 3 || f == 5;
    const auto copied = [](const RenderedFrame& r) { // the whole field, or on a GPU where the frame wrote it
      return std::any_of(r.passMs.begin(), r.passMs.end(), [](const auto& e) {
        return e.first == SdfShadowPass::kCopyName || e.first == VolumeUpdatePass::kName;
      });
    };
    EXPECT_EQ(copied(a), filled);
    EXPECT_TRUE(copied(b));
    EXPECT_EQ(a.sdf.fieldChanged, filled);
    std::size_t differ = 0;
    for (std::size_t i = 0; i < a.visibility[0].size(); ++i)
      differ += std::memcmp(&a.visibility[0][i], &b.visibility[0][i], 4) != 0;
    EXPECT_EQ(differ, 0u);
  }
}
