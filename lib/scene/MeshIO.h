#pragma once
/// @file MeshIO.h
/// @brief Mesh import through assimp (OBJ, PLY, STL, glTF/GLB and the other formats assimp reads).
#include "scene/Mesh.h"

#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief How a mesh or scene load treats the files it refers to.
struct MeshLoadOptions {
  /// Let external references (glTF buffers and images, OBJ material libraries, scene mesh paths) resolve outside
  /// the referring file's folder, by '..', an absolute path or a symbolic link. Off by default: a hostile file
  /// could otherwise make rtsdf read any file the user can ("../../../../etc/passwd").
  bool allowOutsideReferences = false;
};

/// @brief Load every triangle of a mesh file into one Mesh (node transforms applied, polygons triangulated).
/// @param path the file; its extension picks the importer.
/// @param options whether the files it refers to may lie outside its folder.
/// @throw Error naming the file when it is missing, not a regular file, unreadable, malformed, holds no
///        triangles, its header declares more than its size can hold (OFF, PLY, binary STL, GLB), a face uses a
///        vertex index past its mesh's vertices, or it refers to a file outside its folder (the reference and
///        the reason named).
/// @note The mesh is not validated here: call validateMesh() on it.
Mesh loadMeshFile(const std::filesystem::path& path, const MeshLoadOptions& options = {});

/// @brief Load a mesh from bytes in memory (formats that reference other files cannot be read this way).
/// @param extension the format, as a file extension (".off", "ply").
/// @param name what errors call the bytes.
/// @throw Error as loadMeshFile.
Mesh loadMeshFromMemory(const std::string& bytes, const std::string& extension, const std::string& name);

/// @brief True when assimp has an importer for the file's extension.
bool isMeshFile(const std::filesystem::path& path);

} // namespace rtsdf
