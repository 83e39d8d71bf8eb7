#pragma once
/// @file MeshIO.h
/// @brief Mesh import through assimp (OBJ, PLY, STL, glTF/GLB and the other formats assimp reads).
#include "scene/Mesh.h"

#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief Load every triangle of a mesh file into one Mesh (node transforms applied, polygons triangulated).
/// @param path the file; its extension picks the importer.
/// @throw Error naming the file when it is missing, not a regular file, unreadable, malformed, holds no
///        triangles, or its header declares more elements than its size can hold (OFF, PLY).
/// @note The mesh is not validated here: call validateMesh() on it.
Mesh loadMeshFile(const std::filesystem::path& path);

/// @brief Load a mesh from bytes in memory (formats that reference other files cannot be read this way).
/// @param extension the format, as a file extension (".off", "ply").
/// @param name what errors call the bytes.
/// @throw Error as loadMeshFile.
Mesh loadMeshFromMemory(const std::string& bytes, const std::string& extension, const std::string& name);

/// @brief True when assimp has an importer for the file's extension.
bool isMeshFile(const std::filesystem::path& path);

} // namespace rtsdf
