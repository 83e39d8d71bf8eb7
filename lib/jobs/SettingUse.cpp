#include "jobs/SettingUse.h"

#include "util/EnumNames.h"

#include <fmt/format.h>

namespace rtsdf {
namespace {

/// Whether @a setting names a row of S's knob table.
template <class S> bool isKnobOf(const std::string& setting) {
  bool found = false;
  forEachKnob<S>([&](const auto& k) { found = found || setting == k.setting; });
  return found;
}

std::string techniqueIgnores(ShadowTechnique t, const std::string& setting, const char* what, const char* readers) {
  return fmt::format("does not apply to {} shadows (it sets the {}{}, which only {} read): leave it out or choose "
                     "that technique", toString(t), what, setting, readers);
}

/// The SDF march's own knobs that one penumbra estimate or the contact rays' other knob leaves unread.
std::string sdfMarchIgnores(const SdfShadowSettings& s, const std::string& setting) {
  if (setting == "light samples" && s.penumbra != PenumbraEstimate::Umbra)
    return fmt::format("does not apply to the {} penumbra estimate (the light samples are the umbra estimate's "
                       "marches): leave it out or choose that estimate", toString(s.penumbra));
  if (setting == "lateral probes" &&
      (s.penumbra == PenumbraEstimate::Classic || s.penumbra == PenumbraEstimate::Improved))
    return fmt::format("does not apply to the {} penumbra estimate (only the centered and umbra estimates probe "
                       "around the light's cone): leave it out or choose one of them", toString(s.penumbra));
  if (setting == "contact distance" && s.contactRays == 0)
    return "does not apply with 0 contact rays (it is how far they reach): leave it out or cast contact rays";
  if (setting == "contact rays" && s.contactRays > 0 && !(s.contactVoxels > 0.0))
    return "does not apply with a contact distance of 0 (no ray is cast that reaches nowhere): leave it out or "
           "give the rays a distance";
  return {};
}

} // namespace

std::string oneFrameIgnores(int frames, const std::string& setting) {
  if (frames == 1 && (setting == "alpha" || setting == "settle frames" || setting == "refresh period" ||
                      setting == "full recompute"))
    return "does not apply to one refinement frame (it acts on the voxels' history, from the second frame on): "
           "leave it out or run more frames";
  return {};
}

std::string pipelineIgnores(const PipelineSettings& s, const std::string& setting, bool seedElsewhere) {
  if (setting == "closest search" && s.mode == RefineMode::Rays)
    return "does not apply to the rays refinement (only the closest refinement searches closest points): leave it "
           "out or choose that refinement";
  if (setting == "seed" && !seedElsewhere && s.mode == RefineMode::Closest && s.rays == 0)
    return "does not apply to the closest refinement with 0 rays (it seeds the random rays, and none is cast): "
           "leave it out or cast rays";
  if ((setting == "settle frames" || setting == "refresh period") && s.fullRecompute)
    return "does not apply with a full recompute (every masked voxel is refined every frame: none settles): "
           "leave one of them out";
  if (setting == "cascade extent" && s.cascades <= 1)
    return "does not apply to one box (it sizes cascade level 0 when there are 2 cascades or more): leave it out "
           "or give the cascades";
  if (setting == "cascade view margin" && s.cascades <= 1)
    return "does not apply to one box (it limits cascade levels above 0 to the view when there are 2 cascades or "
           "more): leave it out or give the cascades";
  return {};
}

std::string pictureIgnores(const RenderSettings& r, const std::string& setting, bool techniqueFixed,
                           bool truthTraced) {
  const ShadowTechnique t = r.technique;
  if (techniqueFixed) {
    if (t != ShadowTechnique::Sdf && isKnobOf<SdfShadowSettings>(setting))
      return techniqueIgnores(t, setting, "SDF march's ", "sdf shadows");
    if (t != ShadowTechnique::Sdf && isKnobOf<PipelineSettings>(setting) &&
        !(setting == "seed" && (t == ShadowTechnique::RayTraced || truthTraced)))
      return techniqueIgnores(t, setting, "SDF pipeline's ", "sdf shadows");
    if (t != ShadowTechnique::ShadowMap && isKnobOf<ShadowMapSettings>(setting))
      return techniqueIgnores(t, setting, "", "shadowmap shadows");
    if (t == ShadowTechnique::RayTraced && isKnobOf<TaaSettings>(setting))
      return techniqueIgnores(t, setting, "", "the GPU techniques (sdf and shadowmap shadows)");
    if (t != ShadowTechnique::RayTraced && !truthTraced && isKnobOf<RayTracedShadowSettings>(setting))
      return fmt::format("does not apply to {} shadows without the comparison (it sets the ray-traced truth's {}): "
                         "leave it out, compare or choose raytraced shadows", toString(t), setting);
  }
  if (setting == "TAA blend" && !r.taa.enabled)
    return "does not apply with TAA off (it is TAA's weight of the newest frame): leave one of them out";
  if (techniqueFixed && t != ShadowTechnique::Sdf) return {};
  if (std::string why = sdfMarchIgnores(r.sdf, setting); !why.empty()) return why;
  if (!techniqueFixed && setting == "closest search") return {}; // the viewer's M key turns closest mode on
  return pipelineIgnores(r.pipeline, setting, true);
}

std::string bakeIgnores(const BakeOptions& o, const std::string& setting) {
  if (!bakeMethodUses(o.method, setting)) {
    std::string users;
    for (const auto& [name, m] : EnumNames<BakeMethod>::kValues)
      if (bakeMethodUses(m, setting)) users += fmt::format("{}{}", users.empty() ? "" : ", ", name);
    return fmt::format("does not apply to the {} method (it sets the {}, which only {} read{}): leave it out or "
                       "choose that method", toString(o.method), setting, users,
                       users.find(',') == std::string::npos ? "s" : "");
  }
  if (o.method != BakeMethod::Rtsdf) return {};
  if (std::string why = oneFrameIgnores(bakeFrames(o), setting); !why.empty()) return why;
  return pipelineIgnores(o.pipeline, setting);
}

std::string animateIgnores(const AnimateOptions& o, const std::string& setting) {
  if (setting == "fps" && o.frames == 1)
    return "does not apply to one frame (it spaces the frames in time): leave it out or run more frames";
  if (setting == "focus" && !o.measureError)
    return "does not apply without the error measured (it is where the error is measured): leave one of them out";
  if (setting == EnumNames<UpAxis>::kSetting && o.vdbDir.empty())
    return "does not apply without .vdb files (it turns the frames written into the vdb folder): leave it out or "
           "write them";
  if (!isKnobOf<PipelineSettings>(setting)) return {};
  if (std::string why = oneFrameIgnores(o.frames, setting); !why.empty()) return why;
  return pipelineIgnores(o.pipeline, setting);
}

std::string renderIgnores(const RenderJobOptions& o, const std::string& setting) {
  const bool rayTraced = o.render.technique == ShadowTechnique::RayTraced;
  if (rayTraced && (setting == "frames" || setting == "fps" || setting == "device"))
    return fmt::format("does not apply to raytraced shadows (it sets the {}; the CPU ray tracer draws the one "
                       "frame at the time): leave it out or choose a GPU technique", setting);
  if (setting == "fps" && o.frames == 1)
    return "does not apply to one frame (it spaces the frames in time): leave it out or render more frames";
  if (std::string why = pictureIgnores(o.render, setting, true, o.compare); !why.empty()) return why;
  return rayTraced ? std::string() : oneFrameIgnores(o.frames, setting);
}

} // namespace rtsdf
