#pragma once
/// @file GltfChecks.h
/// @brief Checks on glTF 2.0 files before assimp reads them: a GLB's lengths against the file's size (assimp
///        allocates what a chunk header says: 2.1 GB for a 616-byte file), and every primitive's element count and
///        vertex indices against its vertex count.
#include <cstdint>
#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief When @a head starts a GLB (the magic "glTF"), check its header's total length and every chunk length
///        that @a head holds against the file's size and the bytes that remain after the chunk's header.
/// @param head the file's first bytes; chunks past them are not checked (see checkGlbFile).
/// @throw Error "<name>: GLB chunk 0 (JSON) says 2147483648 bytes but 596 remain after its header".
void checkGlbLengths(const std::string& head, std::uint64_t fileSize, const std::string& name);

/// @brief checkGlbLengths over every chunk of a .glb or .gltf file, reading only the chunk headers.
void checkGlbFile(const std::filesystem::path& path, std::uint64_t fileSize);

/// @brief Refuse bytes a glTF importer would not take as glTF: a .glb (@a extension, any case, with or without the
///        dot) that does not start with the binary glTF magic "glTF", and a .gltf that is neither a GLB nor JSON
///        (its first byte other than white space is not '{'). assimp would go on to try every other importer on
///        them, and one of them reads past the end of a short buffer (fuzz_gltf). Other extensions pass.
/// @param head the file's first bytes (a few suffice).
/// @throw Error "<name>: not a binary glTF: a .glb starts with 'glTF'".
void checkGltfForm(const std::string& head, const std::string& extension, const std::string& name);

/// @brief Check each primitive of a glTF's meshes (in a .gltf's JSON or a .glb's chunks), whatever its mode
///        (points, lines, loops, strips, triangles, fans): that it holds enough indices (or vertices, without
///        indices) for one element, and that every index lies within its vertex count. assimp drops a face with an
///        index past the vertices without an error, reads a loop's dropped first line through a null pointer, and
///        allocates 2^32 faces for a line strip of no indices. Indices the check cannot reach (a buffer it cannot
///        read, a sparse accessor, an accessor past its buffer) are left to assimp, which reports what is malformed.
///        Members are read as the importer reads them (a mode that is not a whole number is triangles, indices
///        that are not an index are none, no POSITION is no vertices). A JSON that does not parse is refused.
/// @param bytes the whole file; @param folder where its external buffers lie (empty: none are read).
/// @param allowOutside whether an external buffer may lie outside @a folder.
/// @throw Error "<name>: not a glTF: malformed JSON: ...",
///        "<name>: mesh 'tri' primitive 0: face 1 uses vertex index 99 but the primitive has 3 vertices",
///        "<name>: mesh 0 primitive 0: mode 3 (line strip) needs at least 2 indices but index accessor 1 has 0".
void checkGltfPrimitives(const std::string& bytes, const std::string& name, const std::filesystem::path& folder,
                      bool allowOutside);

} // namespace rtsdf
