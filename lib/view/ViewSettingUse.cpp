#include "view/ViewSettingUse.h"

#include "jobs/SettingUse.h"

#include <fmt/format.h>

namespace rtsdf {

std::string viewIgnores(const ViewOptions& o, const std::string& setting) {
  if (o.frames == 0 && (setting == "fps" || setting == "time"))
    return fmt::format("does not apply without a number of frames (the wall clock drives the {} until the window "
                       "closes): leave it out or give the frames", setting == "fps" ? "frames" : "time");
  if (o.frames == 1 && setting == "fps")
    return "does not apply to one frame (it spaces the frames in time): leave it out or show more frames";
  if (setting == "view" && o.view == ViewMode::Levels && o.render.pipeline.cascades <= 1)
    return "levels shows cascade levels, and one box has none: give --cascades 2 or more, or another view";
  if (std::string why = pictureIgnores(o.render, setting, false, true); !why.empty()) return why;
  return oneFrameIgnores(o.frames, setting);
}

} // namespace rtsdf
