// Writes that are true: an output that cannot be written whole (a full disk, a file-size limit) is an error
// naming the file, with a non-zero exit, and the file that was there before is left as it was.
#include "TestUtil.h"
#include "grid/VdbIO.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <sys/wait.h>

using namespace rtsdf;
using rtsdf::test::TempDir;

namespace {

std::string contents(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

/// A tmpfs of @a kib KiB mounted on @a dir for the test's life (needs root, as CI runs); mounted() is false
/// elsewhere.
class SmallDisk {
public:
  SmallDisk(const std::filesystem::path& dir, int kib) : mDir(dir) {
    int status = 0;
    test::runCommand(fmt::format("mount -t tmpfs -o size={}k tmpfs '{}' 2>&1", kib, dir.string()), status);
    mMounted = status == 0;
  }
  ~SmallDisk() {
    int status = 0;
    if (mMounted) test::runCommand(fmt::format("umount '{}' 2>&1", mDir.string()), status);
  }
  bool mounted() const { return mMounted; }

private:
  std::filesystem::path mDir;
  bool mMounted = false;
};

/// Bake the bunny exactly at @a res into @a out, under @a limit (a shell prefix such as "ulimit -f 64;").
int bake(const std::filesystem::path& out, int res, std::string& output, const std::string& limit = "") {
  int status = 0;
  output = test::runCommand(fmt::format("{} '{}' bake '{}' -m exact -r {} --band 1vox -o '{}' 2>&1", limit, RTSDF_BINARY,
                                        test::dataPath("meshes/bunny.obj"), res, out.string()),
                            status);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// What each full-disk case checks: the small bake fits and reads back; the large one fails naming the file and
/// the reason, and leaves the small one's bytes and no other file.
void expectFailedWriteKeepsTheOldFile(const std::filesystem::path& dir, const std::string& limit) {
  const std::filesystem::path out = dir / "bunny.vdb";
  std::string log;
  ASSERT_EQ(bake(out, 32, log, limit), 0) << log;
  const std::string before = contents(out);
  ASSERT_GT(before.size(), 0u);
  EXPECT_NO_THROW(readLevelSet(out));
  EXPECT_NE(bake(out, 160, log, limit), 0) << log;
  EXPECT_NE(log.find(out.string()), std::string::npos) << log;
  EXPECT_NE(log.find("disk full"), std::string::npos) << log;
  EXPECT_EQ(contents(out), before); // the old output, byte for byte
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1u); // no temporary left behind
}

} // namespace

TEST(Writes, AFullDiskFailsTheBakeAndKeepsTheOldFile) {
  TempDir dir;
  const std::filesystem::path mnt = dir / "disk";
  std::filesystem::create_directory(mnt);
  const SmallDisk disk(mnt, 160); // the bunny at 32 fits, at 160 it does not
  if (!disk.mounted()) GTEST_SKIP() << "mounting a tmpfs needs root (CI runs as root); Writes.AFileSizeLimit... "
                                       "covers the same failure without it";
  expectFailedWriteKeepsTheOldFile(mnt, "");
}

TEST(Writes, AFileSizeLimitFailsTheBakeAndKeepsTheOldFile) {
  TempDir dir;
  expectFailedWriteKeepsTheOldFile(dir.path(), "ulimit -f 160;"); // KiB
}
