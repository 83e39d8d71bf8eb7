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
inline Mesh makeSphere(float r, int n) {
  Mesh m;
  m.name = m.source = "sphere";
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<glm::vec3> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                              {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                               {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                               {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int s = 0; s < n; ++s) {
    std::map<std::pair<unsigned, unsigned>, unsigned> mid;
    auto midpoint = [&](unsigned a, unsigned b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(glm::normalize(v[a] + v[b]));
      return mid[key] = unsigned(v.size() - 1);
    };
    std::vector<glm::uvec3> g;
    for (const auto& tri : f) {
      const unsigned ab = midpoint(tri.x, tri.y), bc = midpoint(tri.y, tri.z), ca = midpoint(tri.z, tri.x);
      g.insert(g.end(), {{tri.x, ab, ca}, {tri.y, bc, ab}, {tri.z, ca, bc}, {ab, bc, ca}});
    }
    f.swap(g);
  }
  for (auto& p : v) p *= r;
  m.positions = v;
  m.triangles = f;
  return m;
}

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
