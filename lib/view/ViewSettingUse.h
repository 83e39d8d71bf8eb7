#pragma once
/// @file ViewSettingUse.h
/// @brief Which settings the viewer reads, given the others (as jobs/SettingUse.h for the other jobs).
#include "view/Viewer.h"

#include <string>

namespace rtsdf {

/// @brief Why the viewer with @a o ignores @a setting ("" when it reads it): fps and time without a fixed number
///        of frames (the wall clock drives time), and what no key brings into play (pictureIgnores with the
///        technique and the refinement mode left to the keys).
std::string viewIgnores(const ViewOptions& o, const std::string& setting);

} // namespace rtsdf
