#pragma once
/// @file Viewer.h
/// @brief The `view` job: a window showing the scene with its soft shadows as the instances animate, an orbit
///        camera, keys to switch shadows (SDF / shadow map / ray-traced truth), to show a slice of the fine SDF or
///        the ray mask, and to change x, d and alpha; a line of text with the pass times and the frame rate.
#include "render/Renderer.h"
#include "scene/MeshIO.h"
#include "util/JobControl.h"
#include "util/Knobs.h"
#include "view/OrbitCamera.h"

#include <string>

namespace rtsdf {

/// @brief What the picture shows.
enum class ViewMode {
  Shaded, ///< the lit scene
  Slice,  ///< the fine SDF on a horizontal plane (blue outside, orange inside, contour lines)
  Mask,   ///< the ray mask (coarse voxels with |c| <= d) on a horizontal plane
  Levels  ///< the lit scene tinted by the cascade level the march samples at each point (with --cascades)
};
template <> struct EnumNames<ViewMode> {
  static constexpr const char* kSetting = "view";
  static constexpr std::pair<const char*, ViewMode> kValues[] = {
      {"shaded", ViewMode::Shaded}, {"slice", ViewMode::Slice}, {"mask", ViewMode::Mask}, {"levels", ViewMode::Levels}};
};

/// @brief Everything the viewer needs.
struct ViewOptions {
  std::string scene;  ///< scene (.json) with a camera and lights
  MeshLoadOptions meshLoad; ///< whether the scene's mesh paths and meshes' references may leave their folder
  std::string device; ///< Vulkan device by index or name; empty: the best one
  /// > 0: render this many frames at fixed steps of 1 / fps ending at @a time (the frames `render` renders, so a
  /// screenshot equals its picture), then close; 0: until the window is closed, the wall clock driving time.
  int frames = 0;
  double fps = 30.0;
  double time = 0.0;      ///< scene time of the last frame when frames > 0
  std::string screenshot; ///< where to write the last frame's picture (.png); empty: nowhere
  ViewMode view = ViewMode::Shaded;
  double sliceHeight = std::numeric_limits<double>::quiet_NaN(); ///< world y of the slice; NaN: the scene's middle
  bool overlay = true;    ///< the line of text at the top
  /// Key presses replayed one per frame before the user's (scripts and tests): a letter or digit presses its key
  /// (an upper-case letter with Shift), '+' / '-' move the slice up / down, '<' / '>' turn the camera.
  std::string keys;
  RenderSettings render = defaultRenderSettings();
  /// @brief The render job's defaults at 960x540.
  static RenderSettings defaultRenderSettings();
  /// @throw SettingError naming the setting that is out of range.
  void validate() const;
};

/// @brief The viewer's own knobs (the picture's: RenderSettings and its parts); docs/settings.md.
template <> struct KnobTable<ViewOptions> {
  using S = ViewOptions;
  static constexpr auto kKnobs = std::make_tuple(
      knob("frames", &S::frames, "--frames", KnobRange::closed(0, 1000000),
           "Show this many frames at fixed steps of 1/fps ending at the time (the frames render renders), then "
           "close; 0: until the window is closed"),
      knob("fps", &S::fps, "--fps", KnobRange::above(0), "Frames per second of scene time with frames > 0"),
      knob("time", &S::time, "-t,--time", KnobRange::finite(), "Scene time of the last frame with frames > 0"),
      knob("screenshot", &S::screenshot, "--screenshot", KnobRange::any(), "Write the last frame's picture to this .png"),
      enumKnob(&S::view, "--view",
               "What the picture shows first: the shaded scene, a horizontal slice of the fine SDF, the ray mask "
               "on that slice, or (with --cascades) the shaded scene tinted by the level that shades each point"),
      knob("slice height", &S::sliceHeight, "--slice-height", KnobRange::finite().orNaN("the scene's middle"),
           "World height (y) of the slice"),
      flagKnob("overlay", &S::overlay, "!--no-overlay",
               "A line of text (settings, pass times, frame rate) at the top; the flag hides it"),
      knob("keys", &S::keys, "--keys", KnobRange::any(),
           "Key presses replayed one per frame (a letter presses its key, upper case with Shift; + - move the "
           "slice, < > turn the camera)"),
      knob("device", &S::device, "--device", KnobRange::any(), "Vulkan device by index or name (see 'rtsdf info')"));
};

/// @brief What the viewer can change while it runs.
struct ViewState {
  ShadowTechnique technique = ShadowTechnique::Sdf;
  ViewMode view = ViewMode::Shaded;
  double sliceHeight = 0.0;   ///< world y
  double sliceStep = 0.01;    ///< per key press (a fiftieth of the scene's height)
  PipelineSettings pipeline;  ///< x (rays), d (band), alpha, refinement mode
  OrbitCamera orbit;
  bool orbiting = false;      ///< the camera left the scene's (which is drawn as it is until then)
  bool paused = false;
  bool quit = false;
};

/// @brief What a key press changed.
enum class KeyEffect { None, Camera, Technique, Pipeline, View, Pause, Quit };

/// @brief Apply GLFW key @a key (Shift held: @a shift) to @a state: 1 / 2 / 3 SDF / shadow map / ray-traced
///        shadows; V the view (shaded, slice, mask, and levels with cascades); Up / Down the slice; X / Shift+X rays per voxel +1 / -1;
///        D / Shift+D the band x1.25 / /1.25; A / Shift+A alpha +0.01 / -0.01; M closest / rays refinement;
///        Left / Right turn the camera; R the scene's camera again; Space pause; Escape or Q quit.
/// @note Settings stay in range (x >= 1 in rays mode, alpha in [0, 1]); the caller rebuilds what changed.
KeyEffect applyViewKey(ViewState& state, const Camera& sceneCamera, int key, bool shift);

/// @brief The GLFW key (and Shift) a character of ViewOptions::keys presses.
/// @throw SettingError for a character that names no key.
std::pair<int, bool> keyOfChar(char c);

/// @brief A finished view.
struct ViewResult {
  int frames = 0;
  double meanFrameMs = 0.0; ///< wall time per frame, the first left out
  std::string lastLine;     ///< the text line of the last frame
  PassTimes passMs;         ///< the last frame's pass times (GPU, or CPU for ray tracing)
};

/// @brief Open a window on @a options.scene and show it until it is closed (or options.frames have been shown).
/// @throw SettingError, Error ("no window system ..." without a display; no camera or light; bad input; no Vulkan
///        device or one that cannot present to the window); Interrupted when @a control asks to stop.
/// @note The screenshot is written (atomically) only after the last frame: an error leaves no file.
ViewResult runViewer(const ViewOptions& options, const JobControl& control = {});

} // namespace rtsdf
