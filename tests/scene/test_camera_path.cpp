#include "scene/SceneLoader.h"
#include "util/Error.h"

#include <glm/gtc/constants.hpp>
#include <gtest/gtest.h>

#include <string>

using namespace rtsdf;

namespace {

std::string withCamera(const std::string& camera) {
  return R"({"meshes": {"b": {"box": [1, 1, 1]}}, "instances": [{"mesh": "b"}], "camera": )" + camera + "}";
}

/// The error parseScene gives for a scene with @a camera, or "" when it parses.
std::string cameraError(const std::string& camera) {
  try {
    parseScene(withCamera(camera), "path.json");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

const char* kPath = R"({"fov_deg": 60, "keyframes": [
  {"time": 1, "position": [0, 1, 10], "look_at": [0, 1, 0]},
  {"time": 3, "position": [4, 1, 10], "look_at": [4, 1, 0], "fov_deg": 30},
  {"time": 4, "position": [4, 3, 10], "look_at": [4, 1, 2]}]})";

} // namespace

TEST(CameraPath, InterpolatesLinearlyAndClampsAtTheEnds) {
  const Scene s = parseScene(withCamera(kPath), "path.json");
  ASSERT_TRUE(s.hasCamera);
  ASSERT_EQ(s.cameraPath.size(), 3u);
  const double deg = glm::pi<double>() / 180.0;
  // Before the first keyframe the first holds; the static camera is the first keyframe.
  EXPECT_EQ(s.cameraAt(-5.0).position, glm::dvec3(0, 1, 10));
  EXPECT_EQ(s.camera.position, glm::dvec3(0, 1, 10));
  EXPECT_NEAR(s.cameraAt(0.0).verticalFov, 60 * deg, 1e-12);
  // Halfway between keyframes 0 and 1: position, target and field of view halfway.
  const Camera mid = s.cameraAt(2.0);
  EXPECT_NEAR(mid.position.x, 2.0, 1e-12);
  EXPECT_NEAR(mid.target.x, 2.0, 1e-12);
  EXPECT_NEAR(mid.verticalFov, 45 * deg, 1e-12);
  // A quarter of the way from keyframe 1 to 2 (whose fov is the camera's 60 by default).
  const Camera late = s.cameraAt(3.25);
  EXPECT_NEAR(late.position.y, 1.5, 1e-12);
  EXPECT_NEAR(late.target.z, 0.5, 1e-12);
  EXPECT_NEAR(late.verticalFov, 37.5 * deg, 1e-12);
  // After the last keyframe the last holds.
  EXPECT_EQ(s.cameraAt(100.0).position, glm::dvec3(4, 3, 10));
  EXPECT_EQ(s.cameraAt(100.0).target, glm::dvec3(4, 1, 2));
}

TEST(CameraPath, AFixedCameraIsTheSameAtEveryTime) {
  const Scene s = parseScene(withCamera(R"({"position": [1, 2, 3], "look_at": [0, 0, 0]})"), "fixed.json");
  EXPECT_TRUE(s.cameraPath.empty());
  EXPECT_EQ(s.cameraAt(7.0).position, glm::dvec3(1, 2, 3));
}

TEST(CameraPath, BadKeysAndValuesNameTheKey) {
  const std::string kf = R"({"time": 0, "position": [0, 1, 5], "look_at": [0, 0, 0]})";
  const struct {
    std::string camera;
    std::string words;
  } cases[] = {
      {R"({"keyframes": []})", "camera.keyframes: must be a non-empty array"},
      {R"({"keyframes": 3})", "camera.keyframes: must be a non-empty array"},
      {R"({"keyframes": [{"time": 0, "position": [0, 1, 5]}]})", "camera.keyframes[0]: needs 'look_at'"},
      {R"({"keyframes": [{"position": [0, 1, 5], "look_at": [0, 0, 0]}]})", "camera.keyframes[0]: needs 'time'"},
      {R"({"keyframes": [{"time": 0, "position": [0, 1, 5], "look_at": [0, 0, 0], "zoom": 2}]})",
       "camera.keyframes[0]: unknown key 'zoom'"},
      {"{\"keyframes\": [" + kf + ", " + kf + "]}", "camera.keyframes[1].time: keyframe times must increase"},
      {R"({"keyframes": [{"time": 0, "position": [0, 1, 5], "look_at": [0, 0, 0], "fov_deg": 0}]})",
       "camera.keyframes[0].fov_deg: must be in (0, 180)"},
      {R"({"keyframes": [{"time": 0, "position": [0, 1, 5], "look_at": [0, 1, 5]}]})",
       "camera.keyframes[0]: position and look_at must differ"},
      {R"({"keyframes": [{"time": 0, "position": [0, 5, 0], "look_at": [0, 0, 0]}]})",
       "camera.keyframes[0]: the view direction is parallel to the camera's 'up'"},
      {R"({"keyframes": [{"time": 0, "position": [0, 0, 5], "look_at": [0, 0, 0]},
                         {"time": 1, "position": [0, 0, -5], "look_at": [0, 0, 0]}]})",
       "camera.keyframes[1]: between keyframes 0 and 1 the view direction passes through zero or along 'up'"},
      {R"({"position": [0, 1, 5], "look_at": [0, 0, 0], "keyframes": [{"time": 0, "position": [0, 1, 5],
           "look_at": [0, 0, 0]}]})",
       "camera: takes 'position' and 'look_at', or 'keyframes', not both"},
      {R"({"keyframes": [{"time": 0, "position": [0, 1, "x"], "look_at": [0, 0, 0]}]})",
       "camera.keyframes[0].position[2]: must be a number"},
  };
  for (const auto& c : cases) {
    const std::string e = cameraError(c.camera);
    EXPECT_NE(e.find("path.json: " + c.words), std::string::npos) << c.camera << "\n-> " << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  }
}
