#pragma once
/// @file SettingUse.h
/// @brief Which settings a job reads, given the others: a front end refuses a setting given where the job would
///        ignore it ("every flag acts or is refused"). Each function returns why the job ignores the setting
///        named @a setting (SettingError::setting(), the knob tables' names), as a clause that follows the flag
///        or keyword in an error message ("does not apply to ..."), or "" when the job reads it.
#include "jobs/Animate.h"
#include "jobs/Bake.h"
#include "jobs/RenderJob.h"

#include <string>

namespace rtsdf {

/// @brief Why the GPU pipeline run with @a s ignores @a setting: a closest-point search in rays mode, the ray
///        seed in closest mode without rays, settling with a full recompute, a cascade extent with one box.
/// @param seedElsewhere the job also seeds something else with the pipeline's seed (render: the SDF march's
///        jitter and the ray-traced truth), so the seed always acts.
std::string pipelineIgnores(const PipelineSettings& s, const std::string& setting, bool seedElsewhere = false);

/// @brief Why a pipeline run for @a frames frames ignores @a setting: the history knobs (alpha, settle frames,
///        refresh period, full recompute) with one frame, where every voxel is new.
std::string oneFrameIgnores(int frames, const std::string& setting);

/// @brief Why the parts of the picture @a r draws ignore @a setting: the SDF march and pipeline without SDF
///        shadows, shadow maps without them, TAA when off, the penumbra estimate's own knobs with another
///        estimate, the contact rays with no reach.
/// @param techniqueFixed false where the technique can change later (the viewer's keys): then every technique's
///        settings act, and only what no key changes is checked.
/// @param truthTraced the ray-traced truth is drawn too (render --compare): its samples act.
std::string pictureIgnores(const RenderSettings& r, const std::string& setting, bool techniqueFixed,
                           bool truthTraced);

/// @brief Why a bake with @a o ignores @a setting: a setting of other methods only (bakeMethodUses), or one the
///        rtsdf method's pipeline would not read (oneFrameIgnores with its frames, bakeFrames; pipelineIgnores).
std::string bakeIgnores(const BakeOptions& o, const std::string& setting);

/// @brief Why animate with @a o ignores @a setting: fps with one frame, the focus without the error measured, the
///        up axis without .vdb files, and the pipeline's (oneFrameIgnores, pipelineIgnores).
std::string animateIgnores(const AnimateOptions& o, const std::string& setting);

/// @brief Why render with @a o ignores @a setting: frames, fps, TAA and the device with ray-traced shadows (one
///        frame on the CPU), fps with one frame, the picture's (pictureIgnores) and the history knobs of one
///        frame (oneFrameIgnores).
std::string renderIgnores(const RenderJobOptions& o, const std::string& setting);

} // namespace rtsdf
