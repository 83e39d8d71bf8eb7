#pragma once
/// @file CascadeBake.h
/// @brief A bake of camera-centred cascade levels (PipelineSettings::cascades > 1): one level set per level, each
///        named cascadeGridName(level) with its own transform and rtsdf:* metadata, and how compare finds them.
#include "jobs/Bake.h"
#include "scene/Scene.h"
#include "util/JobControl.h"

#include <openvdb/openvdb.h>

#include <string>
#include <vector>

namespace rtsdf {

/// @brief The grid name of cascade level @a level in a .vdb: "surface_L0", "surface_L1", ...
std::string cascadeGridName(int level);

/// @brief Where the levels are centred for a bake at @a time: the scene camera's position then, or the centre of the
///        scene's bounds when it has no camera.
glm::dvec3 cascadeCentre(const Scene& scene, double time);

/// @brief Bake @a scene's cascade levels (options.pipeline.cascades of them) at options.time: CascadeSet around
///        cascadeCentre(), options.frames frames, then each level's refined voxels as a level set of the level's band
///        (d 2^level), stamped as a single rtsdf bake is plus rtsdf:cascade_level, rtsdf:cascades and
///        rtsdf:cascade_centre. BakeResult::grid and spec are level 0's.
/// @throw As bake().
BakeResult bakeCascades(const BakeOptions& options, const Scene& scene, const JobControl& control);

/// @brief The cascade level grids among @a grids (named cascadeGridName(i)), by level; empty when there are none.
/// @throw Error when the levels are not 0..K-1 without gaps or are not float level sets.
std::vector<openvdb::FloatGrid::Ptr> cascadeLevelGrids(const openvdb::GridPtrVec& grids);

/// @brief The lines a cascade bake adds to bakeReport: each level's grid, band, mask and active voxels.
std::string cascadeReport(const BakeResult& result);

} // namespace rtsdf
