// Shading across cascade levels: the march's level sampling (shared with the GPU) against CascadeSamplerCpu, the GPU
// march over the levels against its CPU copy, the levels following the camera path, and a room's shadows inside a
// town of rooms against the ray-traced truth.
#include "GpuFixture.h"
#include "RenderTestUtil.h"
#include "TestUtil.h"
#include "TownOfRooms.h"
#include "render/Renderer.h"
#include "render/sdfshadow/SdfShadowCpu.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "sdf/cascade/CascadeSamplerCpu.h"
#include "util/Error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <random>

using namespace rtsdf;
namespace sh = rtsdf::gpu::shared;

namespace {

struct CascadeRenderTag : test::NoSuiteObjects {};
using CascadeRender = test::VulkanSuite<CascadeRenderTag>;

using test::defaultScene;
using test::boundsOf;

/// The levels of @a layout as the march samples them, in the frame of @a origin, with fields from @a f(world point).
template <class F>
CascadeFieldCpu closedFormLevels(const CascadeLayout& layout, const glm::dvec3& origin, double blendVoxels, F f) {
  CascadeFieldCpu out;
  for (const CascadeLevel& level : layout.levels) {
    const GridSpec g = level.fine;
    sh::CascadeFieldLevel l{};
    l.originH = glm::vec4(glm::vec3(g.origin - origin), float(g.voxelSize));
    l.dims = glm::ivec4(g.dims, 0);
    l.blend.x = float(blendVoxels * g.voxelSize);
    out.levels.push_back(l);
    std::vector<float> values(g.voxelCount());
    for (int z = 0; z < g.dims.z; ++z)
      for (int y = 0; y < g.dims.y; ++y)
        for (int x = 0; x < g.dims.x; ++x) values[g.linear(x, y, z)] = float(f(g.indexToWorld(glm::dvec3(x, y, z))));
    out.fields.push_back(std::move(values));
  }
  return out;
}

RenderSettings cascadeSettings(int w, int h) {
  RenderSettings r;
  r.width = w;
  r.height = h;
  r.technique = ShadowTechnique::Sdf;
  r.pipeline.coarseRes = 32;
  r.pipeline.fineRes = 64;
  r.pipeline.mode = RefineMode::Closest;
  r.pipeline.cascades = 2;
  r.taa.enabled = false;
  r.sdf.jitter = true;
  r.sdf.contactRays = 0; // the march alone
  return r;
}

using test::countAbove;

} // namespace

// The level sampling the march runs (sampleCascade in SdfShadowMarch.h, in float, frame-relative: what the GPU runs)
// against CascadeSamplerCpu (its own code, in double) on a closed-form sphere whose level fields are exact distances,
// at points everywhere: deep in level 0, in every blend band, and beyond the outermost level. A hard switch at the
// borders (no blend band) must differ, so the comparison sees the blend.
TEST(CascadeShading, TheMarchSamplesTheLevelsAsCascadeSamplerCpuDoes) {
  CascadeShape shape;
  shape.levels = 3;
  shape.coarseRes = 8;
  shape.fineRes = 16;
  shape.levelZeroExtent = 1.0;
  const glm::dvec3 camera(0.13, -0.07, 0.21), centre = camera + glm::dvec3(0.3, 0.1, -0.2);
  const CascadeLayout layout = CascadeLayout::around(camera, shape);
  const glm::dvec3 origin = layout.levels.back().box().min;
  auto sphere = [&](const glm::dvec3& p) { return glm::length(p - centre) - 0.45; };
  constexpr double kBlend = 4.0;
  const CascadeFieldCpu levels = closedFormLevels(layout, origin, kBlend, sphere);
  const CascadeFieldCpu hard = closedFormLevels(layout, origin, 0.0, sphere);
  const CascadeSamplerCpu reference(layout, levels.fields, kBlend);
  sh::SdfShadowParams p{};
  p.cascadeLevels = 3;
  p.gridOriginH = levels.levels[0].originH;
  p.gridDims = levels.levels[0].dims;
  std::mt19937 rng(7);
  const Bounds outer = layout.levels.back().box();
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  double worst = 0.0, hardWorst = 0.0;
  int perLevel[4] = {0, 0, 0, 0};
  for (int k = 0; k < 20000; ++k) {
    // Half the points near level 0 and 1 (their blend bands), half over the outermost level and beyond.
    const Bounds box = k % 2 ? outer : layout.levels[std::size_t(k % 4 == 0 ? 0 : 1)].box();
    const glm::dvec3 w(u(rng), u(rng), u(rng));
    const glm::dvec3 q = box.min + w * (box.max - box.min);
    const glm::vec3 rel(q - origin);
    const double want = reference.sample(glm::dvec3(rel) + origin);
    worst = std::max(worst, std::fabs(double(sampleCascadeFieldCpu(levels, p, rel)) - want));
    hardWorst = std::max(hardWorst, std::fabs(double(sampleCascadeFieldCpu(hard, p, rel)) - want));
    const int at = layout.finestHolding(q, shape.fineVoxel(std::max(0, layout.finestHolding(q))));
    ++perLevel[at < 0 ? 3 : at];
  }
  std::cout << "points per finest level " << perLevel[0] << ", " << perLevel[1] << ", " << perLevel[2]
            << ", outside " << perLevel[3] << "; worst difference " << worst << ", hard switch " << hardWorst << "\n";
  for (int n : perLevel) EXPECT_GT(n, 500);
  EXPECT_LT(worst, 2e-5) << "the shared sampler is CascadeSamplerCpu's rule";
  EXPECT_GT(hardWorst, 1e-3) << "the blend bands are sampled";
  EXPECT_THROW(sampleCascadeFieldCpu(levels, sh::SdfShadowParams{}, glm::vec3(0.0f)), Error) << "0 levels asked for";
}

// SdfShadowPass over two cascade levels (sdf_shadow_cascade4.comp and its umbra variant) against the same march on
// the CPU over the levels read back, on the default scene seen from inside the room: a real share of the pixels in
// shadow and received in each level, and at most 0.1% of the pixels apart by more than 1e-4 (as for the one box's
// buffer march).
TEST_F(CascadeRender, SdfShadowPassOverTheLevelsEqualsTheCpuMarch) {
  Scene scene = defaultScene();
  scene.camera.position = {0.7, 0.8, 0.6}; // in the room, so that level 0 holds the near half of the view
  scene.camera.target = {-0.4, 0.2, -0.4};
  for (PenumbraEstimate e : {PenumbraEstimate::Centered, PenumbraEstimate::Umbra}) {
    RenderSettings s = cascadeSettings(128, 72);
    s.sdf.penumbra = e;
    s.pipeline.cascadeExtent = 2.0;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    ASSERT_EQ(r.sdfPipeline(), nullptr);
    ASSERT_NE(r.cascades(), nullptr);
    const RenderedFrame f = r.renderFrame(0.0);
    const CascadeFieldCpu levels = r.cascadeField();
    ASSERT_EQ(levels.levels.size(), 2u);
    const LightVisibility cpu = sdfShadowsCpu(f.gbuffer, levels, r.gpuLights(), r.sdfShadowParams());
    std::size_t shadowed = 0, inLevel[2] = {0, 0};
    for (std::size_t i = 0; i < cpu[0].size(); ++i) {
      if (!f.gbuffer.hit(i)) continue;
      shadowed += cpu[0][i] < 0.5f;
      const int at = r.cascades()->layout().finestHolding(f.gbuffer.worldPosition(i));
      if (at >= 0) ++inLevel[at];
    }
    EXPECT_GT(shadowed, 100u);
    EXPECT_GT(inLevel[0], 300u) << "receivers in level 0";
    EXPECT_GT(inLevel[1], 300u) << "receivers in level 1 only";
    const std::size_t n = countAbove(f.visibility[0], cpu[0], 1e-4f);
    EXPECT_LE(n, f.gbuffer.pixelCount() / 1000) << n << " pixels differ";
  }
}

// The levels follow the scene camera's path: each frame centres them on the camera at its time (a move rebuilds the
// levels whose box moved), and the march over the moved levels still equals its CPU copy; 5 levels, so the shader
// variant for more than 4 levels runs (the test above runs the one for up to 4).
TEST_F(CascadeRender, TheLevelsFollowTheCameraPath) {
  Scene scene = defaultScene();
  scene.cameraPath = {{0.0, {1.6, 1.3, 1.8}, {0.0, 0.25, 0.0}, 0.785398},
                      {1.0, {-1.4, 1.1, 1.7}, {0.0, 0.25, 0.0}, 0.785398}};
  RenderSettings s = cascadeSettings(64, 36);
  s.pipeline.cascades = 5;
  Renderer r(*sCtx, scene, boundsOf(scene), s);
  for (double t : {0.0, 1.0}) {
    const RenderedFrame f = r.renderFrame(t);
    const glm::dvec3 eye = scene.cameraAt(t).position;
    EXPECT_LT(glm::length(r.cascades()->layout().camera - eye), 1e-12) << "t = " << t;
    const LightVisibility cpu = sdfShadowsCpu(f.gbuffer, r.cascadeField(), r.gpuLights(), r.sdfShadowParams());
    EXPECT_LE(countAbove(f.visibility[0], cpu[0], 1e-4f), f.gbuffer.pixelCount() / 500) << "t = " << t;
  }
}

// Bad combinations are refused by name: the brick sampling (cascade levels are sampled from their dense buffers).
TEST_F(CascadeRender, BrickSamplingOfCascadesIsRefusedByName) {
  const Scene scene = defaultScene();
  RenderSettings s = cascadeSettings(32, 18);
  s.sdf.sampling = SdfSampling::Bricks;
  try {
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    FAIL() << "refused";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.setting(), "SDF sampling");
  }
}

namespace {

/// The pixels both frames see on the same instance among the first @a instances (room (0, 0) of tiledRooms), on the
/// lit side of the light.
std::vector<std::uint8_t> roomPixels(const Scene& scene, const RenderedFrame& frame, const RenderedFrame& truth,
                                     std::size_t instances) {
  std::vector<std::uint8_t> mask = litSideMask(scene, truth.gbuffer, 0);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    const float id = truth.gbuffer.normal[i].w;
    if (!frame.gbuffer.hit(i) || !truth.gbuffer.hit(i) || frame.gbuffer.normal[i].w != id ||
        !(id >= 0.0f && id < float(instances)))
      mask[i] = 0;
  }
  return mask;
}

/// Visibility RMSE of @a frame against @a truth over the pixels of @a mask.
double maskedRmse(const RenderedFrame& frame, const RenderedFrame& truth, const std::vector<std::uint8_t>& mask,
                  std::size_t& pixels) {
  double sum = 0.0;
  pixels = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (!mask[i]) continue;
    const double d = double(frame.visibility[0][i]) - double(truth.visibility[0][i]);
    sum += d * d;
    ++pixels;
  }
  return pixels ? std::sqrt(sum / double(pixels)) : 1.0;
}

} // namespace

// The room keeps its shadows inside a town: the default room alone (one box at render's counts, coarse 64 / fine
// 128) and the same room as room (0, 0) of a 16 x 16 town of rooms (35 units wide) in one box and under 4 cascade
// levels (fine 256, level 0's voxel the room alone's: 4 units a side), seen by the same camera from outside the room;
// the visibility error against the ray-traced truth over the room's pixels that all three see. Level 0 reaches ahead
// of the camera (kCascadeLookAhead) and holds every one of them; centred a quarter of its side ahead, it held about
// half and the rest fell to level 1 (1.42x the room's error). One box over the town at the same counts has a voxel
// 17 times the room's.
TEST_F(CascadeRender, TheRoomKeepsItsShadowsInsideATownOfRooms) {
  const Scene room = defaultScene(), town = test::tiledRooms(16);
  RenderSettings s;
  s.width = 320;
  s.height = 180;
  s.taa.enabled = false;
  s.sdf.jitter = false;
  s.pipeline.coarseRes = 64;
  s.pipeline.fineRes = 128;
  RenderSettings truthSettings = s;
  truthSettings.technique = ShadowTechnique::RayTraced;
  truthSettings.rayTraced.samples = 256;
  const std::size_t roomInstances = room.instances.size();
  struct Shot {
    RenderedFrame frame, truth;
    double voxel = 0.0;   // the finest fine voxel
    CascadeLayout layout; // the levels (cascades)
  };
  // The town's truth is rendered once, for both of its shots (same camera, time and light).
  auto shoot = [&](const Scene& scene, const RenderSettings& settings, const RenderedFrame* truth) {
    Renderer r(*sCtx, scene, boundsOf(scene), settings);
    Shot shot{r.renderFrame(0.0), truth ? *truth : renderRayTraced(scene, 0.0, truthSettings)};
    if (r.cascades()) shot.layout = r.cascades()->layout();
    shot.voxel = r.sdfPipeline() ? r.sdfPipeline()->fineSpec().voxelSize : shot.layout.levels.front().fine.voxelSize;
    return shot;
  };
  const Shot alone = shoot(room, s, nullptr), single = shoot(town, s, nullptr);
  RenderSettings c = s;
  c.pipeline.cascades = 4;
  c.pipeline.fineRes = 256;
  c.pipeline.cascadeExtent = 256 * alone.voxel;
  const Shot cascaded = shoot(town, c, &single.truth);
  EXPECT_DOUBLE_EQ(cascaded.voxel, alone.voxel);
  // The room's pixels the town leaves in view (its neighbours hide the rest), in every frame.
  std::vector<std::uint8_t> mask = roomPixels(town, cascaded.frame, cascaded.truth, roomInstances);
  const std::vector<std::uint8_t> aloneMask = roomPixels(room, alone.frame, alone.truth, roomInstances);
  std::size_t inLevelZero = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    mask[i] = mask[i] && aloneMask[i];
    inLevelZero += mask[i] && cascaded.layout.finestHolding(cascaded.frame.gbuffer.worldPosition(i)) == 0;
  }
  std::size_t pixels = 0;
  const double eAlone = maskedRmse(alone.frame, alone.truth, mask, pixels);
  const double eSingle = maskedRmse(single.frame, single.truth, mask, pixels);
  const double eCascaded = maskedRmse(cascaded.frame, cascaded.truth, mask, pixels);
  std::cout << "visibility RMSE over the room's " << pixels << " pixels in view (" << inLevelZero
            << " in level 0): alone " << eAlone << ", town in one box " << eSingle << ", town in 4 levels "
            << eCascaded << " (" << eCascaded / eAlone << "x)\n";
  EXPECT_GT(pixels, 10000u);
  EXPECT_EQ(inLevelZero, pixels) << "level 0 holds the room's pixels in view";
  EXPECT_LT(eCascaded, 0.6 * eSingle) << "the levels hold the room better than one box over the town";
  EXPECT_LT(eCascaded, 1.1 * eAlone) << "the room's own error, within 10%";
}
