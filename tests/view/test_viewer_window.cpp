// The viewer in a window (ctest runs this binary under xvfb-run: an X server without a screen, lavapipe
// presenting into it): its screenshot equals `render`'s picture of the same frames, and the keys switch
// shadows, views and settings without a validation error.
#include "TestUtil.h"
#include "image/ImageIO.h"
#include "jobs/RenderJob.h"
#include "view/Viewer.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

using namespace rtsdf;
namespace fs = std::filesystem;

namespace {
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "rtsdf_viewer_window";
  fs::create_directories(dir);
  return dir / name;
}

ViewOptions smallView(const std::string& scene, const fs::path& shot) {
  ViewOptions o;
  o.scene = test::dataPath(scene);
  o.render = RenderJobOptions::defaultRenderSettings();
  o.render.width = 320;
  o.render.height = 180;
  o.render.pipeline.coarseRes = 32; // small grids: the test is about the window, not the SDF
  o.render.pipeline.fineRes = 128;
  o.render.pipeline.band = 0.1; // the former default, which these tests were written for
  o.screenshot = shot.string();
  return o;
}
} // namespace

TEST(ViewerWindow, RunsWhereADisplayIs) { ASSERT_NE(std::getenv("DISPLAY"), nullptr) << "run under xvfb-run"; }

// The same frames as `render --frames 3 --time 0.5`: the window shows the picture render writes (ComposePass's
// exp and pow may round one step of 255 differently from the CPU's).
TEST(ViewerWindow, ScreenshotEqualsTheRenderJobsPicture) {
  const fs::path shot = scratch("view.png");
  fs::remove(shot);
  ViewOptions o = smallView("scenes/default.json", shot);
  o.frames = 3;
  o.time = 0.5;
  o.overlay = false;
  const ViewResult v = runViewer(o);
  EXPECT_EQ(v.frames, 3);
  ASSERT_TRUE(fs::exists(shot));

  RenderJobOptions r;
  r.scene = o.scene;
  r.frames = 3;
  r.time = 0.5;
  r.render = o.render;
  const RenderOutputs out = RenderOutputs::forExr(scratch("render.exr"));
  writeRender(renderScene(r), out);
  const PngPixels a = readPng(shot), b = readPng(out.png);
  ASSERT_EQ(a.width, 320);
  ASSERT_EQ(a.height, 180);
  ASSERT_EQ(a.rgb.size(), b.rgb.size());
  int worst = 0;
  std::size_t differ = 0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    worst = std::max(worst, std::abs(int(a.rgb[i]) - int(b.rgb[i])));
    differ += a.rgb[i] != b.rgb[i];
  }
  EXPECT_LE(worst, 1);
  EXPECT_LT(double(differ), 0.02 * double(a.rgb.size()));
}

// Replayed keys: slice view, shadow maps, mask view, the ray-traced truth, SDF again, x + 1 in rays mode (the
// pipeline rebuilt), alpha + 0.01, the camera turned; the text strip on.
TEST(ViewerWindow, KeysSwitchShadowsViewsAndSettings) {
  const fs::path shot = scratch("keys.png");
  fs::remove(shot);
  ViewOptions o = smallView("scenes/default.json", shot);
  o.render.rayTraced.samples = 4;
  o.frames = 9;
  o.keys = "v2v31mxa<";
  const ViewResult v = runViewer(o);
  EXPECT_EQ(v.frames, 9);
  EXPECT_NE(v.lastLine.find("sdf | rays"), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find("x=2"), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find("alpha=0.96"), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find("| mask |"), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find("SdfShadow"), std::string::npos) << v.lastLine;
  const PngPixels p = readPng(shot);
  EXPECT_EQ(p.width, 320);
  // The strip of text: white glyph pixels over a darkened band at the top.
  std::size_t white = 0;
  for (int y = 0; y < 12; ++y)
    for (int x = 0; x < p.width; ++x) {
      const std::size_t i = 3 * std::size_t(y * p.width + x);
      white += p.rgb[i] == 255 && p.rgb[i + 1] == 255 && p.rgb[i + 2] == 255;
    }
  EXPECT_GT(white, 100u);
}

// The level view over two cascade levels: the status line gives each level's GPU time, and the picture is tinted
// by level (level 0's red where the room's surfaces lie in it, level 1's orange beyond).
TEST(ViewerWindow, TheLevelViewTintsEachPointByItsLevelAndListsTheLevelsTimes) {
  const fs::path shot = scratch("levels.png");
  fs::remove(shot);
  ViewOptions o = smallView("scenes/default.json", shot);
  o.render.pipeline.cascades = 2;
  o.render.pipeline.fineRes = 64;
  // Level 0 3 units wide moves by 0.375 (a brick): snapped there it holds the floor and the room's near half
  // ([-0.375, 2.625] along each axis), level 1 the rest.
  o.render.pipeline.cascadeExtent = 3.0;
  o.view = ViewMode::Levels;
  o.frames = 2;
  const ViewResult v = runViewer(o);
  EXPECT_NE(v.lastLine.find("| levels |"), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find("levels (GPU ms) L0 "), std::string::npos) << v.lastLine;
  EXPECT_NE(v.lastLine.find(" L1 "), std::string::npos) << v.lastLine;
  const PngPixels p = readPng(shot);
  std::size_t reddish = 0, orange = 0;
  for (std::size_t i = 0; i < p.rgb.size(); i += 3) {
    const int r = p.rgb[i], g = p.rgb[i + 1], b = p.rgb[i + 2];
    // Half way to (0.90, 0.25, 0.20): green about as low as blue; to (0.95, 0.55, 0.15): green well above blue.
    reddish += r > g + 50 && g - b < 25;
    orange += r > b + 60 && g - b > 40;
  }
  EXPECT_GT(reddish, 500u);
  EXPECT_GT(orange, 500u);
}

// The command line's `view`: flags bound onto ViewOptions, the screenshot written, the summary printed.
TEST(ViewerWindow, CommandLineWritesTheScreenshot) {
  const fs::path shot = scratch("cli.png");
  fs::remove(shot);
  int status = -1;
  const std::string out = test::runCommand(
      fmt::format("{} -q view {} --frames 2 --width 160 --height 90 --coarse 32 --fine 64 --view mask "
                  "--screenshot {} 2>&1",
                  RTSDF_BINARY, test::dataPath("scenes/default.json"), shot.string()),
      status);
  EXPECT_EQ(status, 0) << out;
  EXPECT_NE(out.find("2 frame(s)"), std::string::npos) << out;
  EXPECT_NE(out.find("| mask |"), std::string::npos) << out;
  const PngPixels p = readPng(shot);
  EXPECT_EQ(p.width, 160);
  EXPECT_EQ(p.height, 90);
}

// A Vulkan validation error fails the view as it fails every job, one reported when the device is destroyed (an
// object left alive) included, and leaves no screenshot; the build's test hook (RTSDF_TEST_VALIDATION_ERROR)
// commits a deliberate one.
TEST(ViewerWindow, AValidationErrorFailsTheViewAndWritesNoScreenshot) {
  for (const char* kind : {"now", "leak"}) {
    SCOPED_TRACE(kind);
    const fs::path shot = scratch(fmt::format("validation-{}.png", kind));
    fs::remove(shot);
    int status = 0;
    const std::string out = test::runCommand(
        fmt::format("RTSDF_TEST_VALIDATION_ERROR={} {} -q view {} --frames 1 --width 160 --height 90 --coarse 32 "
                    "--fine 64 --screenshot {} 2>&1",
                    kind, RTSDF_BINARY, test::dataPath("scenes/default.json"), shot.string()),
        status);
    EXPECT_NE(status, 0) << out;
    const std::size_t at = out.find("Vulkan validation reported 1 error(s); last:");
    ASSERT_NE(at, std::string::npos) << out;
    EXPECT_LE(out.find('\n', at) - at, 300u) << "one readable line: " << out; // the layer's message is cut
    EXPECT_FALSE(fs::exists(shot));
  }
}
