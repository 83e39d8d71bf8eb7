#include "scene/ConfinedFiles.h"

#include "util/Error.h"
#include "util/Text.h"

#include <fmt/format.h>

#include <algorithm>
#include <system_error>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

/// @a path absolute and without '.', '..' or a trailing separator (lexically: links are not followed).
fs::path normalAbsolute(const fs::path& path) {
  fs::path p = fs::absolute(path).lexically_normal();
  if (!p.has_filename() && p.has_parent_path() && p != p.root_path()) p = p.parent_path();
  return p;
}

/// Whether @a path is @a root or lies below it (both normal and absolute).
bool isWithin(const fs::path& path, const fs::path& root) {
  auto r = root.begin(), p = path.begin();
  for (; r != root.end(); ++r, ++p)
    if (p == path.end() || *p != *r) return false;
  return true;
}

} // namespace

std::string escapeFromFolder(const fs::path& root, const fs::path& target) {
  const fs::path lexicalRoot = normalAbsolute(root), lexicalTarget = normalAbsolute(target);
  if (!isWithin(lexicalTarget, lexicalRoot))
    return std::find(target.begin(), target.end(), "..") != target.end() ? "'..' leads out of it"
                                                                          : "an absolute path outside it";
  std::error_code ec1, ec2;
  const fs::path realRoot = fs::weakly_canonical(lexicalRoot, ec1);
  const fs::path realTarget = fs::weakly_canonical(lexicalTarget, ec2);
  if (ec1 || ec2) return "its path cannot be resolved";
  if (!isWithin(realTarget, realRoot))
    return fmt::format("a symbolic link leads out of it, to {}", oneLine(realTarget.string(), 80));
  return "";
}

void requireInsideFolder(const fs::path& referrer, const std::string& reference, const fs::path& target,
                         const fs::path& root) {
  const std::string reason = escapeFromFolder(root, target);
  if (!reason.empty())
    throw Error(fmt::format("{}: the reference '{}' is refused: it resolves outside {} ({})",
                            oneLine(referrer.string(), 120), oneLine(reference, 60),
                            oneLine(normalAbsolute(root).string(), 60), reason));
}

ConfinedIOSystem::ConfinedIOSystem(const fs::path& file, std::string name)
    : mFile(file), mName(std::move(name)), mRoot(fs::absolute(file).parent_path()) {}

ConfinedIOSystem::ConfinedIOSystem(std::string name) : mName(std::move(name)) {}

bool ConfinedIOSystem::allowed(const char* path) const {
  if (path == nullptr) return false;
  if (mRoot.empty()) { // a mesh in memory: no file is its neighbour
    if (mRefusal.empty())
      mRefusal = fmt::format("{}: the reference '{}' is refused: a mesh read from memory cannot refer to files",
                             oneLine(mName, 120), oneLine(path, 60));
    return false;
  }
  if (fs::path(path) == mFile) return true; // the file itself, whatever folder a link puts it in
  try {
    requireInsideFolder(mName, referenceName(path), path, mRoot);
    return true;
  } catch (const Error& e) {
    if (mRefusal.empty()) mRefusal = e.what();
    return false;
  }
}

std::string ConfinedIOSystem::referenceName(const char* path) const {
  // assimp hands over the referring file's folder and the reference joined: name the reference as written.
  const std::string p = path, folder = mFile.parent_path().string();
  if (!folder.empty() && p.size() > folder.size() + 1 && p.compare(0, folder.size(), folder) == 0 &&
      (p[folder.size()] == '/' || p[folder.size()] == '\\'))
    return p.substr(folder.size() + 1);
  return p;
}

bool ConfinedIOSystem::Exists(const char* path) const {
  return allowed(path) && DefaultIOSystem::Exists(path);
}

Assimp::IOStream* ConfinedIOSystem::Open(const char* path, const char* mode) {
  return allowed(path) ? DefaultIOSystem::Open(path, mode) : nullptr;
}

} // namespace rtsdf
