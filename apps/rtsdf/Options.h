#pragma once
/// @file Options.h
/// @brief The command line's flags, bound onto the library's options structs (CLI11) from their knob tables
///        (KnobCli.h), and the flag that spells each library setting in error messages.
#include "suites/Suites.h"
#include "suites/SweepJob.h"
#include "jobs/Animate.h"
#include "jobs/Bake.h"
#include "jobs/Compare.h"
#include "jobs/MeshJob.h"
#include "jobs/RenderJob.h"
#include "view/Viewer.h"

#include "KnobCli.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <string>

namespace rtsdf::app {

struct BakeCommand {
  BakeOptions options;
  BakeOutputOptions written;
  std::filesystem::path output;
};

struct AnimateCommand {
  AnimateOptions options;
  std::filesystem::path csv; ///< per-frame statistics; empty: stdout only
};

struct RenderCommand {
  RenderJobOptions options;
  std::filesystem::path output, png; ///< .exr; .png (empty: the .exr's name with .png)
};

struct BenchCommand {
  bench::BenchOptions suite;
  std::string sweep; ///< quick, default or paper: the sweep instead of a suite (empty: a suite)
  bench::SweepJobOptions sweepOptions;
  bool announce = false; ///< say what will run and for how long first (`rtsdf bench` with no arguments)
  SettingFlags flags;    ///< bench's own flags by the settings bench::benchIgnores names
};

struct CompareCommand {
  CompareOptions options;
  CompareAnchor anchor = CompareAnchor::Exact;
  CLI::Option* againstFlag = nullptr; ///< given: options.against = anchor
};

/// @brief Every subcommand's options; @a which names the one given.
struct Commands {
  std::string which;
  BakeCommand bake;
  AnimateCommand animate;
  RenderCommand render;
  BenchCommand bench;
  CompareCommand compare;
  MeshOptions mesh;
  ViewOptions view;
  Preset preset = Preset::Default; ///< --preset of bake, animate, render and view (under the flags given)
  SettingFlags flags; ///< the flag of each setting the commands bind, for errors naming a setting
};

/// @brief Add the subcommands and global flags to @a app, bound onto @a c, @a verbosity and @a quiet.
void bindCommands(CLI::App& app, Commands& c, int& verbosity, bool& quiet);

/// @brief After parsing: the preset under the flags not given, a bake's resolution as its method's output grid
///        (--coarse and --fine override), and a refusal of every flag the command would ignore with the others
///        given (jobs/SettingUse.h: a setting of another bake method, technique, refinement or penumbra estimate).
/// @throw Error naming the flag and the method.
void finishCommands(CLI::App& app, Commands& c);

/// @brief Every settings struct's knob table as Markdown (`rtsdf help-settings --markdown`, docs/settings.md).
std::string helpSettings();

} // namespace rtsdf::app
