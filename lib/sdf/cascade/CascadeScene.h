#pragma once
/// @file CascadeScene.h
/// @brief What one cascade level sees of a scene (levelScene): the instances that can come near its box. A level's
///        passes then place, voxelize and search only those, so its cost and memory follow what lies around the
///        camera, not the size of the world.
#include "scene/Scene.h"
#include "sdf/cascade/CascadeLayout.h"
#include "util/Bounds.h"

#include <cstdint>

namespace rtsdf {

/// @brief The world box of @a instance at @a time, from its mesh's box (@a meshBounds: positionBounds per mesh).
Bounds instanceBoxAt(const Instance& instance, const Bounds& meshBounds, double time);

/// @brief The part of @a scene a level with box @a box needs: every animated instance, and every static one whose
///        box comes within @a margin of @a box; only the meshes they use (indices renumbered), the lights and the
///        camera. With @a margin at least the band plus two coarse diagonals of the level, no refined voxel of the
///        level can have its nearest surface in an instance left out (its kept neighbours are nearer), so the
///        level's refined distances equal those of the whole scene (closest mode).
Scene levelScene(const Scene& scene, const Bounds& box, double margin);

/// @brief The margin levelScene() keeps around a level of coarse voxel @a coarseVoxel and fine voxel
///        @a fineVoxel under band @a band: band + 2 sqrt(3) coarseVoxel + fineVoxel.
double levelSceneMargin(double band, double coarseVoxel, double fineVoxel);

/// @brief How far (scene units, along each axis) level @a level of @a shape may scroll from the box its scene was cut
///        around before the scene is cut again and the level rebuilt: a quarter of the level's side, at least one
///        move. Cutting the scene with this much more margin keeps every instance the scrolled level needs in it.
double levelSceneSlack(const CascadeShape& shape, int level);

/// @brief The margin a CascadeSet cuts level @a level's scene with (levelScene) under a band of @a band scene units:
///        levelSceneMargin and levelSceneSlack.
double levelCutMargin(const CascadeShape& shape, const CascadeLevel& level, double band);

/// @brief The triangles of all instances of @a scene (what a pipeline places and voxelizes each frame).
std::uint64_t instanceTriangles(const Scene& scene);

} // namespace rtsdf
