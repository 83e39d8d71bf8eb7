// The README's library snippet ("Using the library") as a program: the lines between the README-SNIPPET markers,
// each block unindented and the blocks joined by an empty line, are the README's code block word for word
// (scripts/check_readme_snippet.py checks it; ctest Docs.ReadmeLibrarySnippetRuns compiles this file against the
// built library and runs it on the default scene with the default settings). Run from the source tree's root
// (the scene path is relative to it); it writes out.vdb where it runs.
// README-SNIPPET-BEGIN
#include "jobs/Bake.h"
// README-SNIPPET-END

#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>

int main() {
  try {
    // README-SNIPPET-BEGIN
    rtsdf::BakeOptions o;                       // the defaults of every command and of Python
    o.scene = "data/scenes/default.json";
    o.method = rtsdf::BakeMethod::Rtsdf;
    rtsdf::setOutputResolution(o, 128);         // as --res: the fine grid (coarse 64); every GPU knob lives in
    o.pipeline.band = rtsdf::Length::voxels(6); // o.pipeline (band d: scene units or voxels, rays, alpha, ...)
    rtsdf::JobControl control;                  // optional: progress per stage, and a stop request
    control.progress = [](const std::string& stage, std::uint64_t done, std::uint64_t total) { /* ... */ };
    const rtsdf::BakeResult r = rtsdf::bake(o, control);   // r.grid: the openvdb::FloatGrid level set
    rtsdf::writeBake(r, "out.vdb");
    // README-SNIPPET-END
    std::printf("baked %s in %.2f s: %llu active voxels, out.vdb\n", o.scene.c_str(), r.seconds,
                static_cast<unsigned long long>(r.grid->activeVoxelCount()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
  return 0;
}
