#pragma once
/// @file RenderJob.h
/// @brief The `render` job: a scene camera's view with soft shadows (SDF, shadow maps or the ray-traced truth)
///        over several frames, the picture of the last one, and optionally its error against the truth.
#include "image/Image.h"
#include "render/Renderer.h"
#include "scene/MeshIO.h"
#include "util/JobControl.h"
#include "util/Knobs.h"

#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief Everything a render needs.
struct RenderJobOptions {
  std::string scene;          ///< scene (.json) with a camera and lights
  MeshLoadOptions meshLoad;   ///< whether the scene's mesh paths and meshes' references may leave their folder
  int frames = 8;             ///< frames rendered (SDF refinement and TAA accumulate); the last is kept
  double fps = 30.0;          ///< frames per second of scene time
  double time = 0.0;          ///< scene time of the last frame
  /// Also ray trace the truth and measure the image error. A ray-traced picture is compared with a truth of 4x
  /// its samples and another seed: its own noise, not a match with itself.
  bool compare = false;
  std::string device;         ///< Vulkan device by index or name; empty: the best one
  RenderSettings render = defaultRenderSettings();
  /// @brief The renderer's defaults, with the pipeline's own (PipelineSettings: closest-point refinement, no
  ///        ray votes, whose decayed votes lag behind moving objects), the same as every other job's.
  static RenderSettings defaultRenderSettings();
  /// @throw SettingError naming the setting that is out of range.
  void validate() const;
};

/// @brief A render's own knobs (the picture's: RenderSettings and its parts); docs/settings.md.
template <> struct KnobTable<RenderJobOptions> {
  using S = RenderJobOptions;
  static constexpr auto kKnobs = std::make_tuple(
      knob("frames", &S::frames, "--frames", KnobRange::closed(1, 100000),
           "Frames rendered (SDF refinement and TAA accumulate); the last one is written"),
      knob("fps", &S::fps, "--fps", KnobRange::above(0), "Frames per second of scene time"),
      knob("time", &S::time, "-t,--time", KnobRange::finite(), "Scene time of the written frame in seconds"),
      flagKnob("compare", &S::compare, "--compare",
               "Also ray trace the truth and print the visibility RMSE and FLIP of the picture (a ray-traced picture: "
               "against 4x its samples with another seed)"),
      knob("device", &S::device, "--device", KnobRange::any(), "Vulkan device by index or name (see 'rtsdf info')"));
};

/// @brief A finished render.
struct RenderJobResult {
  RenderedFrame frame;        ///< the last frame
  Image image;                ///< composeImage(frame): R, G, B and each light's visibility
  bool compared = false;
  ShadowImageError error;     ///< against the truth (when compared)
  Image errorImage;           ///< visibility error: red where too dark, green where too bright (when compared)
  std::string sdfGrids;       ///< the SDF pipeline's grids (Sdf technique; also logged when the render starts)
  /// @brief Per-pass times of the last frame, one line each.
  std::string passTable() const;
};

/// @brief Render @a options.scene.
/// @throw SettingError, Error (no camera, no light, bad input, no Vulkan device); Interrupted when @a control
///        asks to stop between frames.
RenderJobResult renderScene(const RenderJobOptions& options, const JobControl& control = {});

/// @brief The paths a render writes: the EXR, its PNG (default: the EXR's name with .png) and, after a
///        comparison, the error picture (the EXR's stem + "_error.png").
struct RenderOutputs {
  std::filesystem::path exr, png, errorPng;
  static RenderOutputs forExr(const std::filesystem::path& exr, const std::filesystem::path& png = {});
  /// @brief Refuse, before any work, outputs that cannot or must not be written: a missing folder, a folder, an
  ///        extension other than .exr / .png, two outputs at one path, or an output at one of @a inputs.
  /// @throw Error naming the path and the problem.
  void check(const std::vector<std::filesystem::path>& inputs = {}) const;
};

/// @brief Write the EXR (linear, every channel), the sRGB PNG and, after a comparison, the error picture.
/// @note All or nothing: when one write fails, the files this call had already written are removed.
void writeRender(const RenderJobResult& result, const RenderOutputs& outputs);

} // namespace rtsdf
