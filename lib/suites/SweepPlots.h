#pragma once
/// @file SweepPlots.h
/// @brief PNG plots of a sweep through gnuplot: time vs error (the Pareto front, anchors marked), time vs work,
///        error vs frames.
#include "suites/Sweep.h"

#include <filesystem>
#include <string>
#include <vector>

namespace rtsdf::bench {

/// @brief Write the plots' data (@a dir/plots/*.tsv), the gnuplot script (@a dir/plots/sweep.gp) and run
///        gnuplot, which writes the PNGs into @a dir.
/// @param title the scene's name, for the plots' titles.
/// @return the PNG file names written (relative to @a dir).
/// @throw Error naming the script when gnuplot is missing or fails (the data and script stay for a rerun).
std::vector<std::string> writeSweepPlots(const std::filesystem::path& dir, const std::vector<SweepRecord>& records,
                                         const std::string& title);

} // namespace rtsdf::bench
