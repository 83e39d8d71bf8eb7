#pragma once
/// @file CascadeScene.h
/// @brief What one cascade level sees of a scene (levelScene): the instances that can come near its box. A level's
///        passes then place, voxelize and search only those, so its cost and memory follow what lies around the
///        camera, not the size of the world.
#include "scene/Scene.h"
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

/// @brief The triangles of all instances of @a scene (what a pipeline places and voxelizes each frame).
std::uint64_t instanceTriangles(const Scene& scene);

} // namespace rtsdf
