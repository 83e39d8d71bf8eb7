// The viewer's parts that need no window: keys, the orbit camera, the text strip; and the clear error of a
// machine without a window system.
#include "TestUtil.h"
#include "util/Error.h"
#include "view/OrbitCamera.h"
#include "view/TextOverlay.h"
#include "view/Viewer.h"

#include <fmt/format.h>
#include <GLFW/glfw3.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

using namespace rtsdf;

namespace {
Camera sceneCamera() {
  Camera c;
  c.position = {2.0, 1.5, 3.0};
  c.target = {0.0, 0.5, 0.0};
  c.verticalFov = 0.7;
  return c;
}
} // namespace

TEST(OrbitCamera, StartsAtTheSceneCameraAndTurnsAroundItsTarget) {
  const Camera c = sceneCamera();
  OrbitCamera o = OrbitCamera::from(c);
  const Camera back = o.camera();
  EXPECT_NEAR(glm::length(back.position - c.position), 0.0, 1e-12);
  EXPECT_EQ(back.verticalFov, c.verticalFov);
  const double r = glm::length(c.position - c.target);
  o.rotate(1.0, 0.2);
  EXPECT_NEAR(glm::length(o.camera().position - c.target), r, 1e-12); // still on the sphere
  EXPECT_GT(o.camera().position.y, c.position.y);                     // higher: the pitch grew
  o.rotate(0.0, 10.0);
  EXPECT_LT(o.pitch, 89.0 * 3.14159265358979 / 180.0 + 1e-12); // never over the pole
  o.zoom(1.0);
  EXPECT_NEAR(o.distance, 0.9 * r, 1e-12);
  o.zoom(-1e6);
  EXPECT_TRUE(std::isfinite(o.distance));
  Camera degenerate = c;
  degenerate.position = degenerate.target;
  EXPECT_THROW(OrbitCamera::from(degenerate), Error);
}

TEST(ViewKeys, EveryKeyChangesWhatItSaysAndKeepsSettingsInRange) {
  const Camera cam = sceneCamera();
  ViewState s;
  s.pipeline.band = 0.1; // the former default, which this test was written for
  s.pipeline.rays = 0;
  s.pipeline.mode = RefineMode::Closest;
  s.pipeline.alpha = 0.995;
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_2, false), KeyEffect::Technique);
  EXPECT_EQ(s.technique, ShadowTechnique::ShadowMap);
  applyViewKey(s, cam, GLFW_KEY_3, false);
  EXPECT_EQ(s.technique, ShadowTechnique::RayTraced);
  applyViewKey(s, cam, GLFW_KEY_1, false);
  EXPECT_EQ(s.technique, ShadowTechnique::Sdf);
  for (ViewMode v : {ViewMode::Slice, ViewMode::Mask, ViewMode::Shaded}) {
    EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_V, false), KeyEffect::View);
    EXPECT_EQ(s.view, v);
  }
  s.pipeline.cascades = 3; // the level view joins the cycle
  for (ViewMode v : {ViewMode::Slice, ViewMode::Mask, ViewMode::Levels, ViewMode::Shaded})
    EXPECT_EQ((applyViewKey(s, cam, GLFW_KEY_V, false), s.view), v);
  s.pipeline.cascades = 1;
  s.sliceHeight = 0.5;
  s.sliceStep = 0.1;
  applyViewKey(s, cam, GLFW_KEY_UP, false);
  EXPECT_DOUBLE_EQ(s.sliceHeight, 0.6);
  applyViewKey(s, cam, GLFW_KEY_DOWN, false);
  applyViewKey(s, cam, GLFW_KEY_DOWN, false);
  EXPECT_NEAR(s.sliceHeight, 0.4, 1e-12);
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_M, false), KeyEffect::Pipeline);
  EXPECT_EQ(s.pipeline.mode, RefineMode::Rays);
  EXPECT_EQ(s.pipeline.rays, 1); // rays mode with x = 0 would refine nothing
  applyViewKey(s, cam, GLFW_KEY_X, false);
  EXPECT_EQ(s.pipeline.rays, 2);
  for (int i = 0; i < 5; ++i) applyViewKey(s, cam, GLFW_KEY_X, true);
  EXPECT_EQ(s.pipeline.rays, 1);
  const double band = s.pipeline.band;
  applyViewKey(s, cam, GLFW_KEY_D, false);
  EXPECT_DOUBLE_EQ(s.pipeline.band, band * 1.25);
  applyViewKey(s, cam, GLFW_KEY_D, true);
  EXPECT_NEAR(s.pipeline.band, band, 1e-15);
  applyViewKey(s, cam, GLFW_KEY_A, false);
  EXPECT_DOUBLE_EQ(s.pipeline.alpha, 1.0); // at most 1
  applyViewKey(s, cam, GLFW_KEY_A, true);
  EXPECT_DOUBLE_EQ(s.pipeline.alpha, 0.99);
  EXPECT_FALSE(s.orbiting);
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_RIGHT, false), KeyEffect::Camera);
  EXPECT_TRUE(s.orbiting);
  EXPECT_GT(glm::length(s.orbit.camera().position - cam.position), 0.01);
  applyViewKey(s, cam, GLFW_KEY_R, false);
  EXPECT_FALSE(s.orbiting);
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_SPACE, false), KeyEffect::Pause);
  EXPECT_TRUE(s.paused);
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_F5, false), KeyEffect::None);
  EXPECT_EQ(applyViewKey(s, cam, GLFW_KEY_ESCAPE, false), KeyEffect::Quit);
  EXPECT_TRUE(s.quit);
}

TEST(ViewKeys, ReplayedCharactersNameTheirKeys) {
  EXPECT_EQ(keyOfChar('v'), std::make_pair(int(GLFW_KEY_V), false));
  EXPECT_EQ(keyOfChar('X'), std::make_pair(int(GLFW_KEY_X), true));
  EXPECT_EQ(keyOfChar('2'), std::make_pair(int(GLFW_KEY_2), false));
  EXPECT_EQ(keyOfChar('+'), std::make_pair(int(GLFW_KEY_UP), false));
  EXPECT_EQ(keyOfChar('<'), std::make_pair(int(GLFW_KEY_LEFT), false));
  try {
    keyOfChar('%');
    FAIL() << "'%' names no key";
  } catch (const SettingError& e) {
    EXPECT_EQ(e.setting(), "keys");
  }
}

TEST(TextOverlay, GlyphsCoverPixelsInsideTheStripOnly) {
  const int w = 200, rows = 12;
  const std::vector<std::uint8_t> blank = rasterizeText("", w, rows);
  EXPECT_EQ(blank.size(), std::size_t(w * rows));
  EXPECT_EQ(std::count(blank.begin(), blank.end(), 1), 0);
  const std::vector<std::uint8_t> text = rasterizeText("12.5 ms", w, rows);
  const auto covered = std::count(text.begin(), text.end(), 1);
  EXPECT_GT(covered, 40);
  int lastColumn = 0;
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < w; ++x)
      if (text[std::size_t(y * w + x)]) {
        EXPECT_GE(y, 2);
        EXPECT_LT(y, 11); // glyphs are 7 pixels high from row 2 (descenders one more)
        lastColumn = std::max(lastColumn, x);
      }
  EXPECT_LT(lastColumn, 60); // seven characters of ~6 pixels
  // Longer text than fits is cut off, not written past the strip.
  const std::vector<std::uint8_t> cut = rasterizeText(std::string(400, 'W'), 50, 5, 2);
  EXPECT_EQ(cut.size(), 250u);
  const std::vector<std::uint32_t> words = packCoverage({1, 0, 0, 1, 1});
  ASSERT_EQ(words.size(), 2u);
  EXPECT_EQ(words[0], 0x01000001u);
  EXPECT_EQ(words[1], 0x00000001u);
  EXPECT_THROW(rasterizeText("x", 0, 12), Error);
}

// Without a window system the viewer says so and leaves no screenshot behind.
TEST(ViewerWithoutDisplay, IsAClearErrorAndWritesNothing) {
  const char* display = std::getenv("DISPLAY");
  const std::string kept = display ? display : "";
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  const std::filesystem::path shot = std::filesystem::temp_directory_path() / "rtsdf_view_no_display.png";
  std::filesystem::remove(shot);
  ViewOptions o;
  o.scene = test::dataPath("scenes/analytic.json");
  o.frames = 2;
  o.screenshot = shot.string();
  try {
    runViewer(o);
    FAIL() << "a window opened without a display";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no window system"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(shot));
  if (!kept.empty()) setenv("DISPLAY", kept.c_str(), 1);
}

// The viewer's status line wraps at its " | " separators instead of being cut off at the window's edge (960
// pixels by default), and every part of it is still drawn.
TEST(TextOverlay, AStatusLineWiderThanTheWindowWraps) {
  std::string line = "sdf | closest incr. x=0 d=0.0938 alpha=0.95 | shaded | 12.0 ms 83.3 fps |";
  for (const char* pass : {"VoxelizePass", "CoarseTransformPass", "CoarseDistancePass", "RayMaskPass",
                           "ClosestRefinePass", "UpsamplePass", "GBufferPass", "SdfShadowPass", "TaaPass"})
    line += fmt::format(" {} 1.25 ms |", pass);
  const int width = 960;
  const std::string wrapped = wrapText(line, width);
  EXPECT_GT(lineCount(wrapped), 1) << wrapped;
  EXPECT_LE(lineCount(wrapped), kTextStripMaxLines);
  std::string rejoined;
  for (char c : wrapped) rejoined += c == '\n' ? ' ' : c;
  EXPECT_EQ(rejoined, line); // nothing dropped: the break replaces a separator's trailing space
  const std::vector<std::uint8_t> strip = rasterizeText(wrapped, width, kTextStripRows * lineCount(wrapped));
  bool secondLine = false;
  for (int y = kTextStripRows; y < kTextStripRows * lineCount(wrapped); ++y)
    for (int x = 0; x < width; ++x) secondLine = secondLine || strip[std::size_t(y * width + x)];
  EXPECT_TRUE(secondLine) << "the wrapped part is drawn on the next line";
  EXPECT_EQ(wrapText("short | line", width), "short | line");
}
