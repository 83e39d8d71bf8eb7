#pragma once
/// @file TownOfRooms.h
/// @brief The default room tiled n x n times, 2.2 units apart: a world one box cannot hold at render's counts
///        (scripts/make_rooms.py writes the same as a scene file).
#include "TestUtil.h"
#include "scene/SceneLoader.h"

#include <string>

namespace rtsdf::test {

/// @brief The default scene's instances repeated @a n x @a n times along x and z (room (0, 0) first, so its
///        instances keep their indices); orbits move with their room.
inline Scene tiledRooms(int n) {
  const Scene room = loadScene(dataPath("scenes/default.json"));
  Scene town = room;
  town.instances.clear();
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (const Instance& inst : room.instances) {
        Instance copy = inst;
        copy.name += "_" + std::to_string(i) + "_" + std::to_string(j);
        copy.transform.translation += glm::dvec3(2.2 * i, 0.0, 2.2 * j);
        if (copy.animation.kind == Animation::Kind::Orbit) copy.animation.center += glm::dvec3(2.2 * i, 0.0, 2.2 * j);
        town.instances.push_back(copy);
      }
  return town;
}

} // namespace rtsdf::test
