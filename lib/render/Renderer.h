#pragma once
/// @file Renderer.h
/// @brief Soft shadows of a scene's lights, per frame: SDF sphere tracing (the technique), shadow maps (what
///        games otherwise use) and distributed ray tracing (the truth), with TAA over frames.
#include "image/Image.h"
#include "render/RayTracedShadows.h"
#include "render/RenderPasses.h"
#include "render/RenderTypes.h"
#include "render/sdfshadow/SdfShadowCpu.h"
#include "sdf/SdfPipeline.h"
#include "sdf/cascade/CascadeSet.h"
#include "util/Knobs.h"

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rtsdf {

/// @brief Which shadows to render.
enum class ShadowTechnique {
  Sdf,       ///< sphere tracing of the fine SDF refined every frame (RTSDF)
  ShadowMap, ///< a depth map per light with PCF filtering
  RayTraced  ///< distributed ray tracing with Embree on the CPU: the ground truth
};
template <> struct EnumNames<ShadowTechnique> {
  static constexpr const char* kSetting = "shadow technique";
  static constexpr std::pair<const char*, ShadowTechnique> kValues[] = {
      {"sdf", ShadowTechnique::Sdf},
      {"shadowmap", ShadowTechnique::ShadowMap},
      {"raytraced", ShadowTechnique::RayTraced}};
};

/// @brief How the SDF march turns distances into visibility (gpu/shared/Render.h has the formulas).
enum class PenumbraEstimate {
  Classic,  ///< min over samples of k h / t with k = 1 / tan(light half-angle)
  Improved, ///< the triangulated estimate between consecutive samples (less banding)
  Centered, ///< marches on through occluders (signed h): the penumbra straddles the geometric boundary
  Umbra     ///< the SDF-simulated umbra: several centred marches towards jittered points of the light, each
            ///< over its share of the cone, averaged (TAA integrates the jitter)
};
template <> struct EnumNames<PenumbraEstimate> {
  static constexpr const char* kSetting = "penumbra estimate";
  static constexpr std::pair<const char*, PenumbraEstimate> kValues[] = {{"classic", PenumbraEstimate::Classic},
                                                                         {"improved", PenumbraEstimate::Improved},
                                                                         {"centered", PenumbraEstimate::Centered},
                                                                         {"umbra", PenumbraEstimate::Umbra}};
};

/// @brief How the SDF march reads the fine SDF.
enum class SdfSampling {
  Texture, ///< a 3D texture with hardware trilinear filtering: one fetch per step (the fine buffer is copied
           ///< into it each frame); falls back to Buffer where the device cannot filter R32_SFLOAT
  Buffer,  ///< the dense buffer, filtered in the shader exactly as the CPU reference does: eight fetches per step
  Bricks   ///< no dense fine SDF at all: the pipeline keeps it sparse (FineStorage::Sparse) and the march fetches
           ///< the brick pool through the brick slots under the band, the coarse SDF upsampled elsewhere (the same
           ///< values as Buffer, bit for bit); eight fetches per step, each up to six loads under the band, nine
           ///< elsewhere
};
template <> struct EnumNames<SdfSampling> {
  static constexpr const char* kSetting = "SDF sampling";
  static constexpr std::pair<const char*, SdfSampling> kValues[] = {
      {"texture", SdfSampling::Texture}, {"buffer", SdfSampling::Buffer}, {"bricks", SdfSampling::Bricks}};
};

/// @brief SDF shadow settings (lengths in scene units unless stated).
struct SdfShadowSettings {
  PenumbraEstimate penumbra = PenumbraEstimate::Centered;
  double epsilonVoxels = 1.0; ///< hit threshold and march start in fine voxels (at least one: the field is no finer)
  /// Subtracted from every SDF sample, in fine voxels: against light leaking through thin surfaces, and
  /// against trilinear filtering's overestimate of the distance at convex edges (docs/design.md).
  double biasVoxels = 0.15;
  double minStepVoxels = 0.5; ///< shortest march step in fine voxels: samples the closest approach to an edge
  Length maxStep = Length::voxels(4); ///< longest march step, against banding (scene units or fine voxels)
  int maxSteps = 256;         ///< march steps at most
  bool jitter = true;         ///< jitter the start (over [0.25, 1.25] epsilon), the probes' and umbra samples' turn
                              ///< per pixel and frame (TAA averages the noise away)
  /// March start off the surface along its normal (scene units or fine voxels); < 0: the bias, so that a flat
  /// receiver's own plane, biased, is exactly its geometric horizon (docs/design.md).
  Length normalOffset = -1.0;
  /// Centred estimate: SDF samples around the light's cone where the march came closest to an occluder, so
  /// that a plate thinner than the cone does not pass for an edge and leak light (docs/design.md); 0: off
  /// (the centre's signed distance alone, as before).
  int lateralProbes = 8;
  int lightSamples = 4; ///< umbra estimate: marches per pixel, light and frame
  /// Contact rays (ContactShadowPass): short rays per pixel and light through the scene's BVH over the first
  /// contactVoxels fine voxels off the surface, where the SDF is too coarse to see (gaps, creases, contacts);
  /// the visibility is the smaller of the march's and theirs (docs/design.md). 0: off.
  int contactRays = 4;
  double contactVoxels = 4.0; ///< how far the contact rays reach, in fine voxels
  SdfSampling sampling = SdfSampling::Texture;
};

/// @brief Shadow-map baseline settings.
struct ShadowMapSettings {
  int resolution = 1024;        ///< texels per side (per cube face for sphere lights)
  int pcfRadius = 2;            ///< PCF kernel: (2r + 1)^2 texels
  double depthBiasTexels = 1.5; ///< depth bias in texel widths
};

/// @brief Temporal anti-aliasing of the visibility.
struct TaaSettings {
  bool enabled = true;
  double blend = 0.1;      ///< weight of the newest frame once the history is established
  bool clampHistory = true; ///< clamp the history into the current 3x3 neighbourhood (no ghosting)
};

/// @brief Everything a render needs.
struct RenderSettings {
  int width = 640, height = 360;
  ShadowTechnique technique = ShadowTechnique::Sdf;
  SdfShadowSettings sdf;
  ShadowMapSettings shadowMap;
  TaaSettings taa;
  PipelineSettings pipeline;        ///< the SDF generation (Sdf technique)
  RayTracedShadowSettings rayTraced; ///< the ground truth (RayTraced technique)
  /// @throw SettingError naming the setting when one is out of range.
  void validate() const;
};

/// @brief The SDF march's knobs (docs/settings.md).
template <> struct KnobTable<SdfShadowSettings> {
  using S = SdfShadowSettings;
  static constexpr auto kKnobs = std::make_tuple(
      enumKnob(&S::penumbra, "--penumbra",
               "SDF penumbra estimate: classic (k h / t), improved (triangulated between samples), centered (marches "
               "through occluders: penumbra centred on the shadow boundary), umbra (light-samples centered marches "
               "towards jittered points of the light, averaged: the SDF-simulated umbra)"),
      enumKnob(&S::sampling, "--sdf-sampling",
               "How the SDF march reads the fine SDF: texture (a 3D texture, hardware trilinear filtering, one fetch "
               "per step), buffer (filtered in the shader like the CPU reference, eight fetches) or bricks (no dense "
               "fine SDF: the brick pool and the coarse SDF, eight fetches)"),
      knob("epsilon", &S::epsilonVoxels, "--epsilon", KnobRange::closed(1, 64).in(" fine voxels"),
           "SDF hit threshold and march start in fine voxels [epsilon]"),
      knob("bias", &S::biasVoxels, "--bias", KnobRange::closed(0, 64).in(" fine voxels"),
           "Subtracted from SDF samples, in fine voxels: against leaks through thin surfaces and the filtered "
           "field's overestimate at convex edges"),
      knob("min step", &S::minStepVoxels, "--min-step", KnobRange::closed(0.05, 64).in(" fine voxels"),
           "Shortest SDF march step in fine voxels: how densely the march samples near occluders"),
      knob("max step", &S::maxStep, "--max-step", KnobRange::above(0),
           "Longest SDF march step, against banding"),
      knob("max steps", &S::maxSteps, "--max-steps", KnobRange::closed(1, 4096), "SDF march steps at most"),
      knob("normal offset", &S::normalOffset, "--normal-offset", KnobRange::atLeast(0).orNegative("the bias"),
           "SDF march start off the surface along its normal"),
      knob("lateral probes", &S::lateralProbes, "--lateral-probes", KnobRange::closed(0, 64),
           "Centered estimate: SDF samples around the light's cone where the march came closest to an occluder, so "
           "that thin plates hold their umbra (0: off)"),
      knob("light samples", &S::lightSamples, "--light-samples", KnobRange::closed(1, 64),
           "Umbra estimate: marches per pixel, light and frame, each over its share of the light"),
      knob("contact rays", &S::contactRays, "--contact-rays", KnobRange::closed(0, 64),
           "Short rays per pixel and light through the scene's BVH near the surface, where the SDF is too coarse to "
           "see (contacts, creases, gaps thinner than a voxel); traced only where the SDF shows something near the "
           "receiver (0: off)"),
      knob("contact distance", &S::contactVoxels, "--contact-distance", KnobRange::closed(0, 64).in(" fine voxels"),
           "How far the contact rays reach, in fine voxels"),
      flagKnob("jitter", &S::jitter, "!--no-jitter",
               "Jitter the SDF march's start per pixel and frame (and the lateral probes', umbra samples' and contact "
               "rays' turn); the flag turns it off"));
};

/// @brief The shadow maps' knobs.
template <> struct KnobTable<ShadowMapSettings> {
  using S = ShadowMapSettings;
  static constexpr auto kKnobs = std::make_tuple(
      knob("shadow map resolution", &S::resolution, "--shadow-map-res", KnobRange::closed(1, 8192),
           "Shadow map texels per side (per cube face)"),
      knob("PCF radius", &S::pcfRadius, "--pcf-radius", KnobRange::closed(0, 16), "PCF kernel radius in texels"),
      knob("shadow bias", &S::depthBiasTexels, "--shadow-bias", KnobRange::atLeast(0),
           "Shadow map depth bias in texels"));
};

/// @brief Temporal anti-aliasing's knobs.
template <> struct KnobTable<TaaSettings> {
  using S = TaaSettings;
  static constexpr auto kKnobs = std::make_tuple(
      flagKnob("TAA", &S::enabled, "!--no-taa", "Temporal accumulation of the visibility; the flag turns it off"),
      knob("TAA blend", &S::blend, "--taa-blend", KnobRange::halfOpen(0, 1), "TAA weight of the newest frame"),
      flagKnob("TAA history clamp", &S::clampHistory, "",
               "Clamp the history into the current 3x3 neighbourhood (no ghosting)"));
};

/// @brief The ray-traced truth's knobs (its seed follows the pipeline's on the command line).
template <> struct KnobTable<RayTracedShadowSettings> {
  using S = RayTracedShadowSettings;
  static constexpr auto kKnobs = std::make_tuple(knob("samples", &S::samples, "--samples", KnobRange::closed(1, 65536),
                                                      "Ray-traced shadows: samples per pixel and light"));
};

/// @brief The picture's own knobs; its parts (sdf, shadowMap, taa, rayTraced, pipeline) have tables of their own.
template <> struct KnobTable<RenderSettings> {
  using S = RenderSettings;
  static constexpr auto kKnobs = std::make_tuple(
      enumKnob(&S::technique, "--shadows",
               "sdf: sphere tracing of the RTSDF fine SDF; shadowmap: depth maps with PCF; raytraced: distributed "
               "ray tracing on the CPU (the truth)"),
      knob("image width", &S::width, "--width", KnobRange::closed(1, 16384), "Image width in pixels"),
      knob("image height", &S::height, "--height", KnobRange::closed(1, 16384), "Image height in pixels"));
};

/// @brief One rendered frame.
struct RenderedFrame {
  double time = 0.0;
  GBuffer gbuffer;
  LightVisibility visibility; ///< after TAA (the raw frame when TAA is off or for ray tracing)
  PassTimes passMs;           ///< GPU (or CPU, for ray tracing) time per pass
  FrameStats sdf;             ///< the SDF generation's statistics (Sdf technique; with cascades summed over levels)
  std::vector<FrameStats> levels; ///< with cascades: each level's, finest first
  CascadeMove cascadeMove;        ///< with cascades: the levels that moved with the camera this frame
  double passTotal(const std::string& pass) const { return rtsdf::passTotal(passMs, pass); }
};

/// @brief The band at a cascade level's border over which the march fades it into the next coarser level, in the
///        level's fine voxels (CascadeSamplerCpu's blendVoxels).
constexpr double kCascadeBlendVoxels = 4.0;
/// @brief How far ahead of the camera along the view the cascade levels below the outermost are centred, in each
///        level's side (CascadeLayout::around clamps it to CascadeShape::maxLookAhead so that the levels nest): along
///        a view down an axis they reach 0.9 of their side ahead of the camera and 0.1 behind it, so that level 0's
///        voxel holds what the view shows near the camera, not the air behind it; the outermost stays on the camera
///        and holds the scene around it.
constexpr double kCascadeLookAhead = 0.4;
/// @brief Level 0's offset from @a eye's position along its view: kCascadeLookAhead of its side @a levelZeroExtent
///        (zero when the eye has no view direction). The renderer's, and the cascade suite's.
glm::dvec3 cascadeLookAhead(const Camera& eye, double levelZeroExtent);

/// @brief Renders frames of a scene's camera with the GPU techniques (Sdf, ShadowMap). With
///        PipelineSettings::cascades > 1 the SDF is K camera-centred levels (CascadeSet) that follow the camera, and
///        the march samples them blended (sdf_shadow_cascade.comp).
class Renderer {
public:
  /// @param sdfBounds the SDF grids' bounds (the union over the animation, so the grids stay fixed).
  /// @param firstFrameTime the scene time of the first frame: cascade levels are built around the camera of that
  ///        moment (built around another, the first frame would move and rebuild them at once).
  /// @throw Error when the scene has no camera or no light, or on bad settings.
  Renderer(const gpu::VulkanContext& ctx, const Scene& scene, const Bounds& sdfBounds, const RenderSettings& settings,
           double firstFrameTime = 0.0);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// @brief Render the frame at @a time seconds (the frames of one Renderer form the TAA sequence), from the scene
  ///        camera at that time (Scene::cameraAt) until setCamera() is called.
  /// @param readBack download the G-buffer and visibility (off for benchmarks of the GPU time alone).
  RenderedFrame renderFrame(double time, bool readBack = true);

  /// @brief The one box's pipeline (Sdf technique, cascades 1), else null.
  const SdfPipeline* sdfPipeline() const { return mSdf.get(); }
  /// @brief The camera-centred levels (Sdf technique, cascades > 1), else null.
  const CascadeSet* cascades() const { return mCascades.get(); }
  /// @brief The cascade levels as the last frame's march sampled them, read back (for the CPU reference).
  /// @throw Error when the renderer has no cascades.
  CascadeFieldCpu cascadeField() const;
  /// @brief The cascade levels' grids as the last frame's march sampled them (frame-relative; empty without cascades).
  const std::vector<gpu::shared::CascadeFieldLevel>& cascadeLevels() const { return mCascadeLevels; }
  /// @brief Render the next frames from @a camera (an orbiting viewer's) instead of the scene camera's path; the TAA
  ///        history is kept.
  /// @throw Error when the camera is degenerate.
  void setCamera(const Camera& camera);
  /// @brief The camera as the GPU passes see it (relative to frameOrigin()).
  const gpu::shared::CameraParams& cameraParams() const { return mCamera; }
  /// @brief The last frame on the GPU, for passes that follow it (ComposePass): the G-buffer, the visibility
  ///        shown (after TAA when it is on; light-major) and the lights (in the frame of frameOrigin()).
  const GpuGBuffer& gpuGBuffer() const;
  const gpu::Buffer& gpuVisibility() const;
  const gpu::Buffer& gpuLightBuffer() const;
  /// @brief The world point the GPU passes measure from (the SDF's frameOrigin(), or the corner of the bounds
  ///        with shadow maps): G-buffer positions, lights and every pass parameter are relative to it.
  const glm::dvec3& frameOrigin() const { return mFrameOrigin; }
  /// @brief The lights as uploaded (in the frame of frameOrigin()), for the CPU references of the passes.
  const std::vector<gpu::shared::GpuLight>& gpuLights() const { return mLights; }
  /// @brief How the SDF march samples the fine SDF in this renderer (Texture may have fallen back to Buffer; cascades
  ///        sample each level's buffer).
  SdfSampling sdfSampling() const { return mSampling; }
  /// @brief The SDF shadow parameters of the last frame (for the CPU reference).
  const gpu::shared::SdfShadowParams& sdfShadowParams() const { return mSdfParams; }
  /// @brief The contact rays' parameters of the last frame (for the CPU reference; rays == 0: the pass is off).
  const gpu::shared::ContactShadowParams& contactShadowParams() const { return mContactParams; }
  /// @brief The shadow maps' parameters (one per light) and their depths (after a ShadowMap frame).
  const std::vector<gpu::shared::ShadowMapParams>& shadowMapParams() const { return mMapParams; }
  std::vector<float> shadowMapDepths() const;
  /// @brief The raw (pre-TAA) visibility of the last frame.
  LightVisibility rawVisibility() const;

private:
  struct Gpu;
  /// The levels' grids as the march samples them (mCascadeLevels), uploaded.
  void uploadCascadeLevels();
  const gpu::VulkanContext& mCtx;
  const Scene& mScene;
  RenderSettings mSettings;
  Bounds mBounds;
  glm::dvec3 mFrameOrigin{0.0};
  gpu::shared::CameraParams mCamera{};
  bool mFollowsSceneCamera = true; ///< the camera moves along the scene's path; false after setCamera()
  std::vector<gpu::shared::GpuLight> mLights;
  gpu::shared::SdfShadowParams mSdfParams{};
  gpu::shared::ContactShadowParams mContactParams{};
  std::vector<gpu::shared::ShadowMapParams> mMapParams;
  std::unique_ptr<SdfPipeline> mSdf;
  std::unique_ptr<CascadeSet> mCascades;
  std::vector<gpu::shared::CascadeFieldLevel> mCascadeLevels; ///< as uploaded for the last frame
  Camera mEye; ///< the camera in world units (the cascades' centre and view)
  SdfSampling mSampling = SdfSampling::Buffer;
  std::unique_ptr<GpuSceneBvh> mBvh; // ShadowMap technique and cascades (one box's Sdf uses the pipeline's)
  std::unique_ptr<Gpu> mGpu;
  int mFrame = 0;
};

/// @brief The ground truth frame: Embree primary hits and distributed shadow rays (CPU, TBB).
/// @param control progress and stop requests of the shadow rays (rayTracedVisibility); null: neither.
/// @throw Interrupted when @a control asks to stop.
RenderedFrame renderRayTraced(const Scene& scene, double time, const RenderSettings& settings,
                              const JobControl* control = nullptr);

/// @brief The shadow maps' parameters for @a lights over @a bounds.
std::vector<gpu::shared::ShadowMapParams> makeShadowMapParams(const std::vector<gpu::shared::GpuLight>& lights,
                                                              const Bounds& bounds, const ShadowMapSettings& s,
                                                              int width, int height);

/// @brief A light's name for channel names: its name, or "light<i>" when it has none.
std::string lightChannelName(const Scene& scene, std::size_t light);

/// @brief The picture: Lambertian surfaces (a colour per instance) lit by every light times its visibility,
///        plus a little ambient light. Channels: R, G, B (linear) and "<light>.V" (visibility) per light.
Image composeImage(const Scene& scene, const RenderedFrame& frame);

/// @brief The picture for a display: R, G, B through the exposure curve 1 - exp(-x) (highlights roll off
///        instead of clipping), for writePng.
Image displayImage(const Image& linear);

/// @brief Pixels whose surface faces light @a light (n . L > 0 at the light's centre): where its shadows show.
std::vector<std::uint8_t> litSideMask(const Scene& scene, const GBuffer& gbuffer, std::size_t light);

/// @brief Image error of a frame against the ground truth of the same moment.
struct ShadowImageError {
  double visibilityRmse = 0.0;      ///< over lit-side pixels of every light where both frames see the same instance
  double visibilityMeanAbs = 0.0;
  double penumbraRmse = 0.0;        ///< over the truth's penumbra pixels (0.02 < visibility < 0.98)
  /// Mean |test - truth| over the truth's umbra pixels (visibility < 0.02): light leaking where none arrives.
  double umbraMeanAbs = 0.0;
  double flip = 0.0;                ///< mean LDR-FLIP of the sRGB pictures
  std::size_t pixels = 0, penumbraPixels = 0, umbraPixels = 0;
};
/// @brief Compare @a test with @a truth (same camera and size).
/// @throw Error when the sizes differ or no pixel is comparable.
ShadowImageError compareWithTruth(const Scene& scene, const RenderedFrame& test, const RenderedFrame& truth);

} // namespace rtsdf
