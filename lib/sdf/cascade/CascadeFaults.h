#pragma once
/// @file CascadeFaults.h
/// @brief Failures injected into a CascadeSet's moves, for tests of what the set does after one.
#include "sdf/cascade/CascadeSet.h"
#include "sdf/pipeline/PipelineProbe.h"

namespace rtsdf {

/// @brief Failures injected into one CascadeSet. The set must outlive it.
class CascadeFaults {
public:
  explicit CascadeFaults(CascadeSet& set) : mSet(set) {}
  /// @brief Level @a level's next scroll throws Error after recording its shifts, nothing submitted
  ///        (PipelineFaults::failNextScroll).
  void failNextScroll(int level) { PipelineFaults(*mSet.mLevels.at(std::size_t(level)).pipeline).failNextScroll(); }
  /// @brief The next level built by a move, or built again after a failed one, throws Error instead.
  void failNextBuild() { mSet.mFailNextBuild = true; }

private:
  CascadeSet& mSet;
};

} // namespace rtsdf
