#pragma once
/// @file MeshFileChecks.h
/// @brief Checks on a mesh file's bytes before assimp reads them: every count and length its header declares
///        must fit in the file's size (assimp allocates for what a header says, and its messages hide the
///        culprit), and the statements that crash or hang assimp's readers are refused.
#include <cstdint>
#include <string>

namespace rtsdf {

/// @brief Check the counts declared by the header of an OFF, PLY (ASCII or binary) or binary STL file, and a
///        GLB's lengths, against the file's size.
/// @param head the file's first bytes (64 KiB or the whole file).
/// @param extension the format, as a file extension (".ply", "stl"; any case).
/// @param name what errors call the file.
/// @throw Error "<name>: ..." naming the field that does not fit ("binary STL says 1000000 triangles (50000084
///        bytes) but the file has 684 bytes").
void checkHeaderClaims(const std::string& head, std::uint64_t fileSize, const std::string& extension,
                       const std::string& name);

/// @brief Refuse OBJ line elements ('l') with one vertex: assimp's OBJ importer writes past its vertex array on
///        them. @param text the whole file. @throw Error naming the file and the line.
void checkObjLines(const std::string& text, const std::string& name);

} // namespace rtsdf
