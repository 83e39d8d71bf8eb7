#pragma once
// Helpers shared by the test binaries: temporary folders, small files, analytic meshes.
#include "scene/Mesh.h"

#include <glm/gtc/constants.hpp>

#include <cmath>
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

inline std::string dataPath(const std::string& rel) { return std::string(RTSDF_DATA_DIR) + "/" + rel; }

/// Icosphere of radius r, subdivided n times (20 * 4^n triangles), outward facing.
inline Mesh makeSphere(float r, int n) { return makeSphereMesh(r, n, "sphere"); }

/// Torus around the y axis (major radius R, minor r), nu x nv quads split in two, outward facing.
inline Mesh makeTorus(float R, float r, int nu, int nv) {
  Mesh m;
  m.name = m.source = "torus";
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const float u = 2.0f * glm::pi<float>() * i / nu, v = 2.0f * glm::pi<float>() * j / nv;
      m.positions.emplace_back((R + r * std::cos(v)) * std::cos(u), r * std::sin(v), (R + r * std::cos(v)) * std::sin(u));
    }
  auto id = [&](int i, int j) { return unsigned(((i + nu) % nu) * nv + (j + nv) % nv); };
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j) {
      const unsigned a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      m.triangles.emplace_back(a, c, b);
      m.triangles.emplace_back(a, d, c);
    }
  return m;
}

/// Signed volume (positive for a closed outward-facing mesh).
inline double signedVolume(const std::vector<glm::vec3>& p, const std::vector<glm::uvec3>& t) {
  double v = 0.0;
  for (const auto& f : t) v += glm::dot(glm::dvec3(p[f.x]), glm::cross(glm::dvec3(p[f.y]), glm::dvec3(p[f.z]))) / 6.0;
  return v;
}

} // namespace rtsdf::test
