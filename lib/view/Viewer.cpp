#include "view/Viewer.h"

#include "gpu/VulkanContext.h"
#include "image/ImageIO.h"
#include "jobs/JobSupport.h"
#include "jobs/RenderJob.h"
#include "render/RenderPasses.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"
#include "util/AtomicFile.h"
#include "util/Error.h"
#include "view/TextOverlay.h"
#include "view/Window.h"

#include <GLFW/glfw3.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>

namespace rtsdf {
namespace sh = gpu::shared;
using gpu::Buffer;

RenderSettings ViewOptions::defaultRenderSettings() {
  RenderSettings r = RenderJobOptions::defaultRenderSettings();
  r.width = 960;
  r.height = 540;
  return r;
}

void ViewOptions::validate() const {
  validateKnobs(*this);
  for (char c : keys) keyOfChar(c);
  render.validate();
  if (render.sdf.sampling == SdfSampling::Bricks)
    throw SettingError("SDF sampling", "SDF sampling 'bricks': the viewer's slice view reads the dense fine SDF; "
                                       "sample it as 'texture' or 'buffer'");
}

std::pair<int, bool> keyOfChar(char c) {
  if (c >= 'a' && c <= 'z') return {GLFW_KEY_A + (c - 'a'), false};
  if (c >= 'A' && c <= 'Z') return {GLFW_KEY_A + (c - 'A'), true};
  if (c >= '0' && c <= '9') return {GLFW_KEY_0 + (c - '0'), false};
  switch (c) {
  case '+': return {GLFW_KEY_UP, false};
  case '-': return {GLFW_KEY_DOWN, false};
  case '<': return {GLFW_KEY_LEFT, false};
  case '>': return {GLFW_KEY_RIGHT, false};
  case ' ': return {GLFW_KEY_SPACE, false};
  default: break;
  }
  throw SettingError("keys", fmt::format("key '{}' is none the viewer knows (letters, digits, + - < > and space)", c));
}

KeyEffect applyViewKey(ViewState& s, const Camera& sceneCamera, int key, bool shift) {
  auto turn = [&](double yaw) {
    if (!s.orbiting) s.orbit = OrbitCamera::from(sceneCamera);
    s.orbiting = true;
    s.orbit.rotate(yaw, 0.0);
    return KeyEffect::Camera;
  };
  switch (key) {
  case GLFW_KEY_1: s.technique = ShadowTechnique::Sdf; return KeyEffect::Technique;
  case GLFW_KEY_2: s.technique = ShadowTechnique::ShadowMap; return KeyEffect::Technique;
  case GLFW_KEY_3: s.technique = ShadowTechnique::RayTraced; return KeyEffect::Technique;
  case GLFW_KEY_V: s.view = ViewMode((int(s.view) + 1) % (s.pipeline.cascades > 1 ? 4 : 3)); return KeyEffect::View;
  case GLFW_KEY_UP: s.sliceHeight += s.sliceStep; return KeyEffect::View;
  case GLFW_KEY_DOWN: s.sliceHeight -= s.sliceStep; return KeyEffect::View;
  case GLFW_KEY_X: s.pipeline.rays = std::clamp(s.pipeline.rays + (shift ? -1 : 1), 1, 1024); return KeyEffect::Pipeline;
  case GLFW_KEY_D: s.pipeline.band.value *= shift ? 1.0 / 1.25 : 1.25; return KeyEffect::Pipeline; // either unit
  case GLFW_KEY_A:
    s.pipeline.alpha = std::clamp(std::round((s.pipeline.alpha + (shift ? -0.01 : 0.01)) * 100.0) / 100.0, 0.0, 1.0);
    return KeyEffect::Pipeline;
  case GLFW_KEY_M:
    s.pipeline.mode = s.pipeline.mode == RefineMode::Closest ? RefineMode::Rays : RefineMode::Closest;
    if (s.pipeline.mode == RefineMode::Rays) s.pipeline.rays = std::max(s.pipeline.rays, 1); // x = 0 refines nothing
    return KeyEffect::Pipeline;
  case GLFW_KEY_LEFT: return turn(-0.1);
  case GLFW_KEY_RIGHT: return turn(0.1);
  case GLFW_KEY_R: s.orbiting = false; return KeyEffect::Camera;
  case GLFW_KEY_SPACE: s.paused = !s.paused; return KeyEffect::Pause;
  case GLFW_KEY_ESCAPE:
  case GLFW_KEY_Q: s.quit = true; return KeyEffect::Quit;
  default: return KeyEffect::None;
  }
}

namespace {
/// The live view loops over this much of the animation: the SDF's grids cover the instances over it.
constexpr double kLoopSeconds = 20.0;

/// The frame's picture inputs on the GPU when the CPU rendered it (ray-traced truth).
struct UploadedFrame {
  GpuGBuffer gbuffer;
  Buffer visibility, lights;
};

/// One open window on one scene, and everything that draws into it.
class ViewSession {
public:
  ViewSession(const ViewOptions& o, Scene scene);
  ~ViewSession() {
    if (mSwapchain) mSwapchain->waitIdle(); // the last frame reads buffers the members below own
  }
  ViewSession(const ViewSession&) = delete;
  ViewSession& operator=(const ViewSession&) = delete;
  /// Render and show the frame at @a time (@a wallMs: the previous frame's wall time, for the text line).
  void showFrame(double time, double wallMs);
  /// Apply the keys pressed and the mouse moved since the last frame.
  void handleInput(const WindowInput& input);
  bool quit() const { return mState.quit || mWindow.closeRequested(); }
  bool paused() const { return mState.paused; }
  Window& window() { return mWindow; }
  /// The last frame's picture, read back from the GPU.
  PngPixels screenshot();
  /// Destroy every GPU object, then the device, and throw (throwOnValidationErrors) when validation reported an
  /// error, those at the device's destruction (objects left alive) included, as runOnDevice does for the jobs.
  void close();
  const std::string& lastLine() const { return mLine; }
  const PassTimes& lastPassMs() const { return mPassMs; }

private:
  void rebuild();
  RenderSettings settings() const;
  /// The orbit's camera, or the scene camera at the time shown (it follows the scene's camera path).
  Camera camera() const { return mState.orbiting ? mState.orbit.camera() : mScene.cameraAt(mTime); }
  void recordCompose(VkCommandBuffer cmd, const sh::ComposeParams& params);
  sh::ComposeParams composeParams() const;
  /// The pipeline whose fields the slice and mask views show: the one box's, or cascade level 0's; null without one.
  const SdfPipeline* shownPipeline() const;
  std::string statusLine(double wallMs) const;

  const ViewOptions& mOptions;
  Scene mScene;
  double mTime = 0.0; ///< the scene time of the frame shown
  Bounds mBounds;
  Window mWindow;
  std::unique_ptr<gpu::VulkanContext> mCtx;
  std::unique_ptr<Swapchain> mSwapchain;
  ViewState mState;
  int mWidth = 0, mHeight = 0;
  std::unique_ptr<Renderer> mRenderer; // the GPU techniques; null for the ray-traced truth
  std::unique_ptr<ComposePass> mCompose;
  std::unique_ptr<gpu::GpuProfiler> mProfiler; // ComposePass's time, read once its frame is done
  bool mComposed = false;
  UploadedFrame mUploaded;
  Buffer mPixels, mOverlay, mEmpty;
  std::string mLine;
  PassTimes mPassMs;
  std::vector<double> mLevelGpuMs; ///< with cascades: each level's GPU time in the last frame, finest first
};

gpu::ContextOptions windowContextOptions(const std::string& device) {
  gpu::ContextOptions c = deviceContextOptions(device);
  c.instanceExtensions = Window::requiredInstanceExtensions();
  c.deviceExtensions = {VK_KHR_SWAPCHAIN_EXTENSION_NAME};
  return c;
}

Bounds viewBounds(const Scene& scene, const ViewOptions& o) {
  Bounds b;
  if (o.frames > 0) { // the frames `render` renders: the same grids, so the same picture
    const double t0 = o.time - double(o.frames - 1) / o.fps;
    for (int f = 0; f < o.frames; ++f) b.add(buildSceneGeometry(scene, t0 + f / o.fps).bounds);
  } else {
    for (int f = 0; f <= int(kLoopSeconds * 10.0); ++f) b.add(buildSceneGeometry(scene, f / 10.0).bounds);
  }
  return b;
}

ViewSession::ViewSession(const ViewOptions& o, Scene scene)
    : mOptions(o), mScene(std::move(scene)), mBounds(viewBounds(mScene, o)),
      mWindow(o.render.width, o.render.height, "rtsdf view " + o.scene) {
  mCtx = std::make_unique<gpu::VulkanContext>(windowContextOptions(o.device));
  mSwapchain = std::make_unique<Swapchain>(*mCtx, mWindow);
  mWidth = mSwapchain->extent().x; // the window's pixels (a scaled display may give more than asked for)
  mHeight = mSwapchain->extent().y;
  mState.technique = o.render.technique;
  mState.view = o.view;
  mState.pipeline = withLengthsResolved(o.render.pipeline, mBounds); // the band key scales scene units
  mState.sliceHeight = std::isnan(o.sliceHeight) ? mBounds.center().y : o.sliceHeight;
  mState.sliceStep = std::max(mBounds.extent().y, 1e-6) / 50.0;
  mCompose = std::make_unique<ComposePass>(*mCtx);
  mProfiler = std::make_unique<gpu::GpuProfiler>(*mCtx);
  const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  const std::size_t pixels = std::size_t(mWidth) * std::size_t(mHeight);
  mPixels = Buffer(*mCtx, pixels * 4, storage, Buffer::Memory::Device, "viewer pixels");
  mOverlay = Buffer(*mCtx, (std::size_t(mWidth) * kTextStripRows * kTextStripMaxLines + 3) / 4 * 4, storage,
                    Buffer::Memory::Device,
                    "viewer text strip");
  mEmpty = Buffer(*mCtx, 16, storage, Buffer::Memory::Device, "no SDF");
  rebuild();
}

RenderSettings ViewSession::settings() const {
  RenderSettings r = mOptions.render;
  r.width = mWidth;
  r.height = mHeight;
  r.technique = mState.technique;
  r.pipeline = mState.pipeline;
  return r;
}

void ViewSession::rebuild() {
  mSwapchain->waitIdle(); // the last frame's picture still reads the renderer's buffers
  mRenderer.reset();      // its buffers go before the new one's are made
  if (mState.technique == ShadowTechnique::RayTraced) return;
  mRenderer = std::make_unique<Renderer>(*mCtx, mScene, mBounds, settings());
  if (const SdfPipeline* sdf = mRenderer->sdfPipeline())
    spdlog::info("SDF: coarse {}, fine {}", sdf->coarseSpec().describe(), sdf->fineSpec().describe());
  else if (const CascadeSet* levels = mRenderer->cascades())
    spdlog::info("SDF: {} cascade levels; the slice and mask views show level 0's fields", levels->levels());
}

void ViewSession::handleInput(const WindowInput& input) {
  bool rebuildNeeded = false;
  const ViewState before = mState;
  for (const auto& [key, shift] : input.keys) {
    const KeyEffect e = applyViewKey(mState, mScene.cameraAt(mTime), key, shift);
    rebuildNeeded = rebuildNeeded || e == KeyEffect::Technique || e == KeyEffect::Pipeline;
  }
  if (input.drag != glm::dvec2(0.0) || input.scroll != 0.0) {
    if (!mState.orbiting) mState.orbit = OrbitCamera::from(mScene.cameraAt(mTime));
    mState.orbiting = true;
    mState.orbit.rotate(-0.005 * input.drag.x, 0.005 * input.drag.y);
    mState.orbit.zoom(input.scroll);
  }
  if (!rebuildNeeded) return;
  try {
    rebuild();
  } catch (const SettingError& e) { // a band too wide for the grid, say: keep what worked
    spdlog::warn("{}: keeping the previous settings", e.what());
    mState.pipeline = before.pipeline;
    mState.technique = before.technique;
    rebuild();
  }
}

const SdfPipeline* ViewSession::shownPipeline() const {
  if (!mRenderer) return nullptr;
  if (const CascadeSet* levels = mRenderer->cascades()) return &levels->level(0);
  return mRenderer->sdfPipeline();
}

sh::ComposeParams ViewSession::composeParams() const {
  sh::ComposeParams p{};
  const Camera cam = camera();
  const glm::dvec3 origin = mRenderer ? mRenderer->frameOrigin() : glm::dvec3(0.0);
  p.camera = makeCameraParams(cam, mWidth, mHeight, origin);
  p.image = glm::ivec4(mWidth, mHeight, int(mScene.lights.size()), int(mState.view));
  p.coarseDims.w = int(mSwapchain->byteOrder());
  p.fineDims.w = mOptions.overlay ? std::min(kTextStripRows * lineCount(wrapText(mLine, mWidth)), mHeight) : 0;
  const SdfPipeline* sdf = shownPipeline();
  if (sdf) {
    const GridSpec f = sdf->fineSpec().inFrame(origin), c = sdf->coarseSpec().inFrame(origin);
    p.fineDims = glm::ivec4(f.dims, p.fineDims.w);
    p.fineOriginH = glm::vec4(glm::vec3(f.origin), float(f.voxelSize));
    p.coarseDims = glm::ivec4(c.dims, p.coarseDims.w);
    p.coarseOriginH = glm::vec4(glm::vec3(c.origin), float(c.voxelSize));
    p.slice = glm::vec4(float(mState.sliceHeight - origin.y), float(mState.pipeline.band),
                        float(std::max(double(mState.pipeline.band), f.voxelSize)), 0.0f);
  }
  if (mRenderer && mState.view == ViewMode::Levels) {
    const std::vector<sh::CascadeFieldLevel>& levels = mRenderer->cascadeLevels();
    p.cascade.x = int(std::min<std::size_t>(levels.size(), RTSDF_MAX_CASCADE_LEVELS));
    for (int i = 0; i < p.cascade.x; ++i) p.levels[i] = levels[std::size_t(i)];
  }
  return p;
}

void ViewSession::recordCompose(VkCommandBuffer cmd, const sh::ComposeParams& params) {
  const std::vector<std::uint32_t> text =
      packCoverage(rasterizeText(wrapText(mLine, mWidth), mWidth, std::max(params.fineDims.w, 1)));
  if (params.fineDims.w > 0) gpu::recordUpload(cmd, mOverlay, text.data(), text.size() * 4);
  const SdfPipeline* sdf = shownPipeline();
  const GpuGBuffer& g = mRenderer ? mRenderer->gpuGBuffer() : mUploaded.gbuffer;
  const Buffer& vis = mRenderer ? mRenderer->gpuVisibility() : mUploaded.visibility;
  const Buffer& lights = mRenderer ? mRenderer->gpuLightBuffer() : mUploaded.lights;
  mProfiler->reset(cmd);
  mComposed = true;
  mCompose->execute(cmd, mProfiler.get(),
                    {g, vis, lights, sdf ? sdf->fineBuffer() : mEmpty, sdf ? sdf->coarseBuffer() : mEmpty, mOverlay},
                    {mPixels}, params);
}

void ViewSession::showFrame(double time, double wallMs) {
  // One frame in flight: the renderer writes the buffers the previous picture read.
  mSwapchain->waitForFrame();
  const PassTimes composed = mComposed ? mProfiler->results() : PassTimes{};
  mTime = time;
  mLevelGpuMs.clear();
  if (mRenderer) {
    mRenderer->setCamera(camera());
    const RenderedFrame f = mRenderer->renderFrame(time, false);
    mPassMs = f.passMs;
    for (const FrameStats& level : f.levels) mLevelGpuMs.push_back(passSum(level.passMs));
  } else {
    Scene& scene = mScene; // the truth renders the scene's camera: put the orbit's there for this frame
    const Camera kept = scene.camera;
    std::vector<CameraKeyframe> keptPath = std::move(scene.cameraPath);
    scene.camera = camera();
    scene.cameraPath.clear();
    RenderSettings s = settings();
    const RenderedFrame f = renderRayTraced(scene, time, s);
    scene.camera = kept;
    scene.cameraPath = std::move(keptPath);
    mPassMs = f.passMs;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    mUploaded.gbuffer.reserve(*mCtx, mWidth, mHeight);
    upload(*mCtx, mUploaded.gbuffer.position, f.gbuffer.position.data(), f.gbuffer.position.size() * 16);
    upload(*mCtx, mUploaded.gbuffer.normal, f.gbuffer.normal.data(), f.gbuffer.normal.size() * 16);
    std::vector<float> all;
    for (const auto& v : f.visibility) all.insert(all.end(), v.begin(), v.end());
    gpu::reserveAndUpload(*mCtx, mUploaded.visibility, all.data(), all.size() * 4, storage, "truth visibility");
    const auto lights = makeGpuLights(mScene.lights, glm::dvec3(0.0));
    gpu::reserveAndUpload(*mCtx, mUploaded.lights, lights.data(), lights.size() * sizeof(sh::GpuLight), storage,
                          "truth lights");
  }
  mPassMs.insert(mPassMs.end(), composed.begin(), composed.end()); // the previous picture's: its time is known now
  mLine = statusLine(wallMs);
  const sh::ComposeParams params = composeParams();
  mSwapchain->present([&](VkCommandBuffer cmd) { recordCompose(cmd, params); }, mPixels);
}

std::string ViewSession::statusLine(double wallMs) const {
  const PipelineSettings& p = mState.pipeline;
  std::string line = fmt::format("{} | {} {} x={} d={:.3g} alpha={:.2f} | {} | {:.1f} ms {:.1f} fps |",
                                 toString(mState.technique), toString(p.mode), p.fullRecompute ? "full" : "incr.",
                                 p.rays, double(p.band), p.alpha, toString(mState.view), wallMs,
                                 wallMs > 0.0 ? 1000.0 / wallMs : 0.0);
  std::map<std::string, double> total;
  std::vector<std::string> order;
  for (const auto& [name, ms] : mPassMs) {
    if (!total.count(name)) order.push_back(name);
    total[name] += ms;
  }
  for (const std::string& name : order) {
    std::string shortName = name;
    for (const char* suffix : {"Pass", " (CPU)"})
      if (const auto at = shortName.find(suffix); at != std::string::npos) shortName.erase(at, std::strlen(suffix));
    line += fmt::format(" {} {:.2f}", shortName, total[name]);
  }
  if (!mLevelGpuMs.empty()) {
    line += " | levels (GPU ms)";
    for (std::size_t i = 0; i < mLevelGpuMs.size(); ++i) line += fmt::format(" L{} {:.2f}", i, mLevelGpuMs[i]);
  }
  return line + (mState.paused ? " | paused" : "");
}

void ViewSession::close() {
  mSwapchain->waitIdle();
  mRenderer.reset();
  mCompose.reset();
  mProfiler.reset();
  mUploaded = UploadedFrame{};
  mPixels = Buffer();
  mOverlay = Buffer();
  mEmpty = Buffer();
  mSwapchain.reset(); // its surface goes before the instance
  mCtx->close();
  throwOnValidationErrors(*mCtx);
}

PngPixels ViewSession::screenshot() {
  mSwapchain->waitIdle();
  std::vector<std::uint32_t> packed(std::size_t(mWidth) * std::size_t(mHeight));
  download(*mCtx, mPixels, packed.data(), packed.size() * 4);
  PngPixels png{mWidth, mHeight, std::vector<std::uint8_t>(packed.size() * 3)};
  const bool bgra = mSwapchain->byteOrder() == sh::kComposeBgra;
  for (std::size_t i = 0; i < packed.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const int shift = 8 * (bgra ? 2 - c : c);
      png.rgb[3 * i + std::size_t(c)] = std::uint8_t((packed[i] >> shift) & 0xFFu);
    }
  return png;
}
} // namespace

ViewResult runViewer(const ViewOptions& o, const JobControl& control) {
  o.validate();
  if (!o.screenshot.empty()) checkOutputPath(o.screenshot, ".png", {o.scene});
  Scene scene = loadScene(o.scene, o.meshLoad);
  if (!scene.hasCamera) throw Error(fmt::format("{}: the scene has no camera to render from", o.scene));
  if (scene.lights.empty()) throw Error(fmt::format("{}: the scene has no light to cast shadows", o.scene));
  ViewSession session(o, std::move(scene));
  ViewResult result;
  const double t0 = o.frames > 0 ? o.time - double(o.frames - 1) / o.fps : 0.0;
  double sceneTime = 0.0, wallSum = 0.0, lastWallMs = 0.0;
  auto last = std::chrono::steady_clock::now();
  for (int f = 0; o.frames == 0 || f < o.frames; ++f) {
    control.checkStop();
    WindowInput input = session.window().pollEvents();
    if (f < int(o.keys.size())) input.keys.insert(input.keys.begin(), keyOfChar(o.keys[std::size_t(f)]));
    session.handleInput(input);
    if (session.quit()) break;
    const double time = o.frames > 0 ? t0 + f / o.fps : std::fmod(sceneTime, kLoopSeconds);
    session.showFrame(time, lastWallMs);
    const auto now = std::chrono::steady_clock::now();
    lastWallMs = std::chrono::duration<double, std::milli>(now - last).count();
    last = now;
    if (!session.paused()) sceneTime += lastWallMs / 1000.0;
    if (f > 0) wallSum += lastWallMs;
    result.frames = f + 1;
    if (o.frames > 0) control.report("view", std::uint64_t(f + 1), std::uint64_t(o.frames));
  }
  result.meanFrameMs = result.frames > 1 ? wallSum / (result.frames - 1) : lastWallMs;
  result.lastLine = session.lastLine();
  result.passMs = session.lastPassMs();
  std::optional<PngPixels> shot;
  if (!o.screenshot.empty() && result.frames > 0) shot = session.screenshot();
  session.close(); // a validation error, at the device's destruction too, fails the view before its file
  if (shot) writePng(o.screenshot, *shot);
  return result;
}

} // namespace rtsdf
