#include "util/AtomicFile.h"

#include "util/Error.h"
#include "util/Interrupt.h"
#include "util/Text.h"

#include <fmt/format.h>

#include <fstream>
#include <random>
#include <system_error>
#include <cerrno>
#include <fcntl.h>
#include <unistd.h>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {

/// Flush @a tmp to the disk: a write the file system accepted into its cache can still fail there (a full disk
/// on a delayed allocation reports only at fsync or close).
void syncToDisk(const fs::path& tmp, const fs::path& target) {
  const int fd = ::open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw Error(fmt::format("{}: the file just written cannot be opened again: {}", target.string(),
                            std::generic_category().message(errno)));
  const int synced = ::fsync(fd);
  const int err = errno;
  ::close(fd);
  if (synced != 0)
    throw Error(fmt::format("{}: cannot write: {}", target.string(), std::generic_category().message(err)));
}

} // namespace

void writeFileAtomically(const fs::path& target,
                         const std::function<void(const fs::path&)>& write) {
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw Error(fmt::format("{}: output directory '{}' does not exist", target.string(), dir.string()));
  if (fs::is_directory(target, ec))
    throw Error(fmt::format("{}: is a directory, not a file", target.string()));
  std::random_device rd;
  const fs::path tmp = dir / fmt::format(".{}.tmp-{}-{:08x}", target.filename().string(), getpid(), rd());
  // Registered before it exists: SIGINT/SIGTERM during the write or the rename remove it (util/Interrupt.h).
  const TemporaryFileGuard guard(tmp);
  try {
    write(tmp);
    syncToDisk(tmp, target);
  } catch (...) {
    fs::remove(tmp, ec);
    throw;
  }
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw Error(fmt::format("{}: cannot move the finished file into place: {}", target.string(), ec.message()));
  }
}

void writeTextAtomically(const fs::path& target, const std::string& text) {
  writeFileAtomically(target, [&](const fs::path& tmp) {
    std::ofstream out(tmp, std::ios::binary);
    out << text;
    out.close();
    if (!out || fs::file_size(tmp) != text.size())
      throw Error(fmt::format("{}: cannot write (is the disk full?)", target.string()));
  });
}


void checkOutputPath(const std::filesystem::path& p, const std::string& extension,
                     const std::vector<std::filesystem::path>& inputs) {
  namespace fs = std::filesystem;
  if (p.empty()) throw Error("the output path is empty");
  std::error_code ec;
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    throw Error(fmt::format("{}: output folder '{}' does not exist", p.string(), dir.string()));
  if (fs::is_directory(p, ec)) throw Error(fmt::format("{}: is a folder, not a file", p.string()));
  for (const fs::path& in : inputs) {
    std::error_code e1;
    if (!in.empty() && fs::exists(p, e1) && fs::exists(in, e1) && fs::equivalent(p, in, e1))
      throw Error(fmt::format("{}: the output would replace an input of this command ({})", p.string(), in.string()));
  }
  if (!extension.empty() && toLower(p.extension().string()) != toLower(extension))
    throw Error(fmt::format("{}: the output is a {} file: give it the extension {}", p.string(), extension, extension));
  // A file created and removed at once: a folder that cannot take files (read-only, /proc, no permission) fails
  // now, not after the work (permission bits alone do not tell: root passes them).
  const fs::path probe = dir / fmt::format(".{}.probe-{}", p.filename().string(), getpid());
  const TemporaryFileGuard guard(probe);
  std::ofstream out(probe, std::ios::binary);
  if (!out) throw Error(fmt::format("{}: cannot create files in the folder '{}'", p.string(), dir.string()));
  out.close();
  fs::remove(probe, ec);
}

} // namespace rtsdf
