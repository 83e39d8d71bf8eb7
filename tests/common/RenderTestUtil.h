#pragma once
// Helpers the render tests share: the default scene, a scene's bounds, and counting pixels that differ.
#include "TestUtil.h"
#include "scene/SceneGeometry.h"
#include "scene/SceneLoader.h"

#include <cmath>
#include <cstddef>
#include <vector>

namespace rtsdf::test {

/// The bundled default scene (data/scenes/default.json).
inline Scene defaultScene() { return loadScene(dataPath("scenes/default.json")); }

/// The bounds of @a s's geometry at time @a t.
inline Bounds boundsOf(const Scene& s, double t = 0.0) { return buildSceneGeometry(s, t).bounds; }

/// How many entries of @a a and @a b differ by more than @a tol.
inline std::size_t countAbove(const std::vector<float>& a, const std::vector<float>& b, float tol) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += std::fabs(a[i] - b[i]) > tol;
  return n;
}

} // namespace rtsdf::test
