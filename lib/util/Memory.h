#pragma once
/// @file Memory.h
/// @brief The machine's and the process's memory (Linux sysconf and /proc): what can be allocated before a
///        large grid is, and peak memory per benchmark point.
#include <cstdint>

namespace rtsdf {

/// @brief Physical memory of this machine in bytes (0 when unknown).
std::uint64_t physicalMemoryBytes();

/// @brief Host memory available now (MemAvailable of /proc/meminfo, else physical memory; 0 when unknown).
std::uint64_t availableHostMemory();

/// @brief Peak resident set size in bytes since the process started or since the last
///        resetPeakResidentMemory() (VmHWM); 0 where /proc is unavailable.
std::uint64_t peakResidentMemory();

/// @brief Current resident set size in bytes (VmRSS); 0 where /proc is unavailable.
std::uint64_t currentResidentMemory();

/// @brief Start a new peak: the next peakResidentMemory() counts from the current resident size.
/// @return false when the kernel does not allow it (then the peak stays the process's lifetime peak).
bool resetPeakResidentMemory();

} // namespace rtsdf
