// The renderer on lavapipe: every GPU pass against its CPU reference on real scenes, the SDF penumbra
// against the closed form and the ray-traced truth, moving shadows, files and the extremes.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "image/ImageIO.h"
#include "reference/AnalyticPenumbra.h"
#include "reference/RayTracedShadows.h"
#include "render/RenderReference.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace rtsdf;
namespace sh = rtsdf::gpu::shared;

namespace {

struct RenderTag : test::NoSuiteObjects {};
using Render = test::VulkanSuite<RenderTag>;

Scene defaultScene() { return loadScene(test::dataPath("scenes/default.json")); }
Scene analyticScene() { return loadScene(test::dataPath("scenes/analytic.json")); }
Bounds boundsOf(const Scene& s, double t = 0.0) { return buildSceneGeometry(s, t).bounds; }

RenderSettings small(ShadowTechnique t, int w = 160, int h = 90) {
  RenderSettings r;
  r.width = w;
  r.height = h;
  r.technique = t;
  r.pipeline.coarseRes = 64;
  r.pipeline.fineRes = 128;
  r.pipeline.mode = RefineMode::Closest;
  r.pipeline.rays = 4;
  r.taa.enabled = false;
  r.sdf.jitter = false;
  return r;
}

std::size_t countAbove(const std::vector<float>& a, const std::vector<float>& b, float tol) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += std::fabs(a[i] - b[i]) > tol;
  return n;
}

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
    EXPECT_LT(glm::length(glm::vec3(f.gbuffer.position[i]) - glm::vec3(cpu.position[i])), 1e-4f);
    EXPECT_GT(glm::dot(glm::vec3(f.gbuffer.normal[i]), glm::vec3(cpu.normal[i])), 0.9999f);
  }
  EXPECT_GT(hits, cpu.pixelCount() / 2);
  EXPECT_LT(differ, cpu.pixelCount() / 500) << differ << " pixels differ";
}

// SdfShadowPass against the same march on the CPU over the same field and G-buffer. Trilinear sampling
// and the march are marked 'precise' on the GPU and compiled without FMA contraction on the CPU; a march
// whose sample lands within rounding of epsilon may still end one step apart, so 0.1% of the pixels may
// differ by more than 1e-4.
TEST_F(Render, SdfShadowPassEqualsTheCpuMarch) {
  const Scene scene = defaultScene();
  for (PenumbraEstimate p : {PenumbraEstimate::Classic, PenumbraEstimate::Improved, PenumbraEstimate::Centered}) {
    RenderSettings s = small(ShadowTechnique::Sdf);
    s.sdf.penumbra = p;
    s.sdf.jitter = true;
    Renderer r(*sCtx, scene, boundsOf(scene), s);
    const RenderedFrame f = r.renderFrame(0.0);
    const LightVisibility cpu = sdfShadowsCpu(f.gbuffer, r.sdfPipeline()->fineField(), makeGpuLights(scene.lights),
                                              r.sdfShadowParams());
    const std::size_t n = countAbove(f.visibility[0], cpu[0], 1e-4f);
    std::size_t shadowed = 0;
    for (float v : cpu[0]) shadowed += v < 0.5f;
    EXPECT_GT(shadowed, 100u) << toString(p);
    EXPECT_LE(n, f.gbuffer.pixelCount() / 1000) << toString(p) << ": " << n << " pixels differ";
  }
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
  const auto lights = makeGpuLights(scene.lights);
  const std::vector<float> cpuDepth = shadowMapDepthsCpu(buildSceneGeometry(scene, 0.0), lights, r.shadowMapParams());
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
