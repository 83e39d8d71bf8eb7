#pragma once
/// @file PeakMemory.h
/// @brief The process's resident memory (Linux /proc), for peak memory per benchmark point.
#include <cstdint>

namespace rtsdf {

/// @brief Peak resident set size in bytes since the process started or since the last
///        resetPeakResidentMemory() (VmHWM); 0 where /proc is unavailable.
std::uint64_t peakResidentMemory();

/// @brief Current resident set size in bytes (VmRSS); 0 where /proc is unavailable.
std::uint64_t currentResidentMemory();

/// @brief Start a new peak: the next peakResidentMemory() counts from the current resident size.
/// @return false when the kernel does not allow it (then the peak stays the process's lifetime peak).
bool resetPeakResidentMemory();

} // namespace rtsdf
