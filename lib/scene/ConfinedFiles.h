#pragma once
/// @file ConfinedFiles.h
/// @brief Keeping the files a mesh or scene refers to (glTF buffers and images, OBJ material libraries, scene
///        mesh paths) inside the referring file's folder: a hostile file must not make rtsdf read any file the
///        user can ("../../../../etc/passwd", or a symbolic link that leads out).
#include <assimp/DefaultIOSystem.h>

#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief Why @a target lies outside the folder @a root, or "" when it lies inside: "'..' leads out of it", "an
///        absolute path outside it" or "a symbolic link leads out of it, to <where>". Both paths may be relative (to
///        the working folder); @a target need not exist.
std::string escapeFromFolder(const std::filesystem::path& root, const std::filesystem::path& target);

/// @brief Require @a target, which @a referrer names as @a reference, to lie inside @a root.
/// @throw Error "<referrer>: the reference '<reference>' is refused: it resolves outside <root> (<reason>)".
void requireInsideFolder(const std::filesystem::path& referrer, const std::string& reference,
                         const std::filesystem::path& target, const std::filesystem::path& root);

/// @brief assimp's file access, confined to the folder of the file being imported: the file itself opens, and
///        so does any file inside its folder; any other is refused (it does not exist for the importer) and the
///        first refusal is kept, for the loader to report whether or not the import went on without the file.
class ConfinedIOSystem : public Assimp::DefaultIOSystem {
public:
  /// @param file the file being imported, exactly as handed to the importer (best absolute: see loadMeshFile).
  /// @param name what messages call it.
  ConfinedIOSystem(const std::filesystem::path& file, std::string name);

  /// @brief A file system with no file at all, for a mesh read from memory (@a name: what messages call it):
  ///        assimp would otherwise read the files it refers to from the working folder.
  explicit ConfinedIOSystem(std::string name);

  bool Exists(const char* path) const override;
  Assimp::IOStream* Open(const char* path, const char* mode = "rb") override;

  /// The first refused reference as a one-line message naming the file, the reference and the reason ("" when
  /// none was refused).
  const std::string& refusal() const { return mRefusal; }

private:
  bool allowed(const char* path) const;
  std::string referenceName(const char* path) const;

  std::filesystem::path mFile;
  std::string mName;
  std::filesystem::path mRoot;
  mutable std::string mRefusal;
};

} // namespace rtsdf
