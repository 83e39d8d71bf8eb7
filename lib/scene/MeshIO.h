#pragma once
/// @file MeshIO.h
/// @brief Mesh import through assimp (OBJ, PLY, STL, glTF/GLB and the other formats assimp reads).
#include "scene/Mesh.h"

#include <filesystem>

namespace rtsdf {

/// @brief Load every triangle of a mesh file into one Mesh (node transforms applied, polygons triangulated).
/// @param path the file; its extension picks the importer.
/// @throw Error naming the file when it is missing, unreadable, malformed or holds no triangles.
/// @note The mesh is not validated here: call validateMesh() on it.
Mesh loadMeshFile(const std::filesystem::path& path);

/// @brief True when assimp has an importer for the file's extension.
bool isMeshFile(const std::filesystem::path& path);

} // namespace rtsdf
