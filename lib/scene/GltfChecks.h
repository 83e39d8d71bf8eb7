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

/// @brief The glTF (a .gltf's JSON or a GLB) as the importer is to read it, after checking what the importer
///        trusts. Checked: glTF 2.0 (asset.version "2.x", GLB version 2); JSON that parses, nested at most 64
///        levels; buffers' uris without control characters, data URIs in base64 only; the GLB's chunks as the
///        importer finds them (its buffer 0 being the BIN chunk); and every primitive of every mesh, whatever its
///        mode: each accessor it names as the spec lays it out (type, component type, count, every element within
///        its view and the view within its buffer, byteStride, sparse parts), its index accessor packed unsigned
///        scalars, enough indices (or vertices) for one element of its mode, every index within its vertices.
///        Members are read as the importer reads them (a mode that is not a 32-bit integer is triangles, indices
///        that are not an index are none, no POSITION is no vertices). Returned: the document with only the
///        surface (geometryOnly in the source: the node tree, positions, indices, modes), external buffers named
///        by absolute path; skins, animations, materials, images and other attributes, which the importer reads
///        unchecked, are dropped.
/// @param bytes the whole file; @param name what messages call it.
/// @param folder where its external buffers lie (empty: none are read, and their uris are left as they are).
/// @param allowOutside whether an external buffer may lie outside @a folder.
/// @throw Error "<name>: not a glTF: malformed JSON: ...",
///        "<name>: mesh 'tri' primitive 0: face 1 uses vertex index 99 but the primitive has 3 vertices",
///        "<name>: mesh 0 primitive 0: mode 3 (line strip) needs at least 2 indices but index accessor 1 has 1".
std::string gltfGeometry(const std::string& bytes, const std::string& name, const std::filesystem::path& folder,
                         bool allowOutside);

} // namespace rtsdf
