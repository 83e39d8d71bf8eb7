#pragma once
// Helpers shared by the test binaries: temporary folders, small files, analytic meshes.
#include "grid/GridSpec.h"
#include "scene/Mesh.h"
#include "sdf/PipelineSettings.h"

#include <glm/gtc/constants.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <unistd.h>

namespace rtsdf::test {

/// A fresh folder under the system temp dir, removed when the object dies.
class TempDir {
public:
  TempDir() {
    std::random_device rd;
    mPath = std::filesystem::temp_directory_path() /
            ("rtsdf-test-" + std::to_string(getpid()) + "-" + std::to_string(rd()));
    std::filesystem::create_directories(mPath);
  }
  ~TempDir() { std::error_code ec; std::filesystem::remove_all(mPath, ec); }
  const std::filesystem::path& path() const { return mPath; }
  std::filesystem::path operator/(const std::string& name) const { return mPath / name; }

private:
  std::filesystem::path mPath;
};

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
}

/// The pipeline's settings before the defaults became closest mode at 64/128 with a band of 6 voxels: rays mode,
/// x = 10, coarse 128 / fine 256, a band of 0.1 scene units. Tests written for those defaults start from here.
inline PipelineSettings formerPipelineDefaults() {
  PipelineSettings s;
  s.coarseRes = 128;
  s.fineRes = 256;
  s.band = 0.1;
  s.mode = RefineMode::Rays;
  s.rays = 10;
  return s;
}

inline std::string dataPath(const std::string& rel) { return std::string(RTSDF_DATA_DIR) + "/" + rel; }

/// The voxel (x, y, z) of a fine voxel index the GPU passes pack in 10 bits each (x lowest).
inline glm::ivec3 unpackVoxel(std::uint32_t packed) {
  return {int(packed & 1023u), int((packed >> 10) & 1023u), int((packed >> 20) & 1023u)};
}

/// Run a shell command; its standard output, and its wait status in @a status.
inline std::string runCommand(const std::string& cmd, int& status) {
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) { status = -1; return out; }
  char buf[4096];
  while (std::size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  status = pclose(p);
  return out;
}

/// Generate the town level of scripts/make_level.py @a size metres wide into folder @a out (seed 1); the path of its
/// level.json, or empty with the script's output in @a log when it failed.
inline std::string makeLevel(const std::string& out, int size, std::string& log) {
  int status = 0;
  log = runCommand("/usr/bin/python3 " + dataPath("../scripts/make_level.py") + " --out " + out + " --size " +
                       std::to_string(size) + " 2>&1",
                   status);
  return status == 0 ? out + "/level.json" : std::string();
}

/// A sphere's signed distance (centre @a c, radius @a r) at every voxel of @a g, GridSpec::linear order.
inline std::vector<float> sphereField(const GridSpec& g, const glm::dvec3& c, double r) {
  std::vector<float> v(g.voxelCount());
  for (int z = 0; z < g.dims.z; ++z)
    for (int y = 0; y < g.dims.y; ++y)
      for (int x = 0; x < g.dims.x; ++x)
        v[g.linear(x, y, z)] = float(glm::length(g.indexToWorld(glm::dvec3(x, y, z)) - c) - r);
  return v;
}

/// Icosphere of radius r, subdivided n times (20 * 4^n triangles), outward facing.
inline Mesh makeSphere(float r, int n) { return makeSphereMesh(r, n, "sphere"); }

/// Torus around the y axis (major radius R, minor r), nu x nv quads split in two, outward facing.
inline Mesh makeTorus(float R, float r, int nu, int nv) {
  Mesh m = makeTorusMesh(R, r, nu, nv, "torus");
  m.source = "torus";
  return m;
}

/// Signed volume (positive for a closed outward-facing mesh).
inline double signedVolume(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& t) {
  double v = 0.0;
  for (const auto& f : t) v += glm::dot(glm::dvec3(p[f.x]), glm::cross(glm::dvec3(p[f.y]), glm::dvec3(p[f.z]))) / 6.0;
  return v;
}

} // namespace rtsdf::test
