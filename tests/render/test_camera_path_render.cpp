// A scene camera given as keyframes: the renderer's frames and the ray-traced truth look through the camera at the
// frame's time, until the viewer sets a camera of its own.
#include "GpuFixture.h"
#include "TestUtil.h"
#include "render/Renderer.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <gtest/gtest.h>

using namespace rtsdf;

namespace {

struct PathTag : test::NoSuiteObjects {};
using RenderCameraPath = test::VulkanSuite<PathTag>;

/// A floor and a plate, the camera moving from the +z side to the +x side in one second.
Scene movingCamera() {
  return parseScene(R"({"meshes": {"floor": {"box": [2, 0.02, 2]}, "plate": {"box": [1, 0.02, 2]}},
      "instances": [{"mesh": "floor", "translate": [0, -0.01, 0]}, {"mesh": "plate", "translate": [-0.5, 0.5, 0]}],
      "lights": [{"type": "directional", "direction": [0, -1, 0]}],
      "camera": {"fov_deg": 60, "keyframes": [
        {"time": 0, "position": [0, 0.3, 2.6], "look_at": [0, 0.05, 0]},
        {"time": 1, "position": [2.6, 0.3, 0], "look_at": [0, 0.05, 0], "fov_deg": 40}]}})",
                    "path.json");
}

RenderSettings tiny() {
  RenderSettings r;
  r.width = 32;
  r.height = 18;
  r.technique = ShadowTechnique::ShadowMap;
  r.taa.enabled = false;
  return r;
}

glm::dvec3 cameraPosition(const Renderer& r) {
  return glm::dvec3(glm::vec3(r.cameraParams().position)) + r.frameOrigin();
}

} // namespace

TEST_F(RenderCameraPath, FramesLookThroughTheCameraAtTheirTime) {
  const Scene scene = movingCamera();
  Renderer r(*sCtx, scene, buildSceneGeometry(scene).bounds, tiny());
  r.renderFrame(0.0, false);
  EXPECT_LT(glm::length(cameraPosition(r) - glm::dvec3(0, 0.3, 2.6)), 1e-5);
  r.renderFrame(0.5, false);
  EXPECT_LT(glm::length(cameraPosition(r) - glm::dvec3(1.3, 0.3, 1.3)), 1e-5);
  r.renderFrame(1.0, false);
  EXPECT_LT(glm::length(cameraPosition(r) - glm::dvec3(2.6, 0.3, 0)), 1e-5);
  // A camera of the viewer's own stays until it is changed.
  Camera own;
  own.position = {0, 2, 0.5};
  own.target = {0, 0, 0};
  r.setCamera(own);
  r.renderFrame(0.25, false);
  EXPECT_LT(glm::length(cameraPosition(r) - own.position), 1e-5);
}

TEST(RenderCameraPathTruth, TheRayTracedTruthLooksThroughTheCameraAtItsTime) {
  const Scene path = movingCamera();
  Scene fixed = path;
  fixed.cameraPath.clear();
  fixed.camera = path.cameraAt(0.75);
  const RenderedFrame a = renderRayTraced(path, 0.75, tiny());
  const RenderedFrame b = renderRayTraced(fixed, 0.75, tiny());
  ASSERT_EQ(a.gbuffer.position.size(), b.gbuffer.position.size());
  EXPECT_EQ(a.gbuffer.position, b.gbuffer.position);
  const RenderedFrame start = renderRayTraced(path, 0.0, tiny());
  EXPECT_NE(start.gbuffer.position, a.gbuffer.position);
}
