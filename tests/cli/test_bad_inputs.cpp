// The bad-input table (tests/cli/bad_inputs.json, docs/reliability.md): one row per kind of bad input, each a
// test of its own. A row names the files to create, the command, the exit code and the words its message must
// hold. Every row also checks what the README promises of every refused command: it ends (no hang), its message
// is short (no line longer than 300 characters), it leaves no file behind (no output, no temporary) and it
// changes none of its inputs. Then SIGINT and SIGTERM, which must leave nothing behind either.
#include "TestUtil.h"
#include "LevelSetFiles.h"
#include "grid/VdbIO.h"
#include "util/AtomicFile.h"
#include "util/Interrupt.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <sstream>
#include <thread>

#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

using namespace rtsdf;
namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

struct Row {
  std::string kind;
  json files;
  std::vector<std::string> args;
  int exit = 1;
  std::vector<std::string> words;
  std::string tableError; ///< set on the one row that stands for an unreadable table
};

/// How gtest names a row in its output (instead of the struct's bytes).
void PrintTo(const Row& row, std::ostream* os) { *os << row.kind; }

/// The table; a table that cannot be read becomes one failing row that says why.
std::vector<Row> loadRows() {
  std::vector<Row> rows;
  try {
    std::ifstream in(RTSDF_BAD_INPUTS_TABLE);
    const json table = json::parse(in);
    for (const json& r : table.at("rows"))
      rows.push_back({r.at("kind"), r.value("files", json::object()), r.at("args"), r.at("exit"),
                      r.value("words", std::vector<std::string>{})});
  } catch (const std::exception& e) {
    rows = {{"table_is_readable", json::object(), {}, 0, {}, std::string("cannot read the table: ") + e.what()}};
  }
  return rows;
}

/// Files the rows copy: written once per test process into a folder of their own.
class Fixtures {
public:
  static const Fixtures& get() {
    static const Fixtures f;
    return f;
  }
  fs::path path(const std::string& name) const {
    const fs::path p = mDir / name;
    if (!fs::exists(p)) throw std::runtime_error("no fixture named '" + name + "'");
    return p;
  }

private:
  Fixtures() {
    const GridSpec g = GridSpec::fromBounds({{-1, -1, -1}, {1, 1, 1}}, 64, 0.25);
    writeSphere("sphere.vdb", g, 0.8);
    GridSpec shifted = g;
    shifted.origin += glm::dvec3(0.4 * g.voxelSize, 0, 0);
    writeSphere("sphere_shifted.vdb", shifted, 0.8);
    auto empty = openvdb::FloatGrid::create(0.1f);
    stampLevelSet(*empty, g, {{"method", "test"}});
    writeVdb(mDir.path() / "empty.vdb", {empty});
    test::writeText(mDir.path() / "cube.obj", cubeObj());
    test::writeLevelSetFiles(mDir.path()); // fog.vdb, nan.vdb, two.vdb, ...: files compare must refuse or read
  }
  void writeSphere(const std::string& name, const GridSpec& g, double radius) {
    auto grid = denseToLevelSet(test::sphereField(g, {0, 0, 0}, radius), g, float(3 * g.voxelSize));
    stampLevelSet(*grid, g, {{"method", "test"}});
    writeVdb(mDir.path() / name, {grid});
  }
  static std::string cubeObj() {
    std::string s;
    for (int i = 0; i < 8; ++i) s += fmt::format("v {} {} {}\n", i & 1, (i >> 1) & 1, (i >> 2) & 1);
    for (const char* f : {"1 3 2", "2 3 4", "5 6 7", "6 8 7", "1 2 5", "2 6 5", "3 7 4", "4 7 8", "1 5 3", "3 5 7",
                          "2 4 6", "4 8 6"})
      s += fmt::format("f {}\n", f);
    return s;
  }
  test::TempDir mDir;
};

/// Create one file of a row: text, bytes in hex, a fuzzer's regression input, a copy of a fixture or of data/
/// (optionally cut to its first bytes), a FIFO or a folder.
void createFile(const fs::path& p, const json& spec) {
  if (spec.is_string()) return test::writeText(p, spec.get<std::string>());
  if (spec.value("fifo", false)) {
    ASSERT_EQ(mkfifo(p.c_str(), 0600), 0) << p;
    return;
  }
  if (spec.value("folder", false)) return (void)fs::create_directories(p);
  if (spec.contains("hex")) {
    const std::string hex = spec["hex"];
    std::string bytes;
    for (std::size_t i = 0; i + 1 < hex.size(); i += 2) bytes += char(std::stoi(hex.substr(i, 2), nullptr, 16));
    return test::writeText(p, bytes);
  }
  if (spec.contains("regression")) { // a crash input the fuzzers found, minus its leading format bytes
    std::ifstream in(fs::path(RTSDF_FUZZ_REGRESSIONS) / spec["regression"].get<std::string>(), std::ios::binary);
    ASSERT_TRUE(in) << spec;
    const std::string bytes(std::istreambuf_iterator<char>(in), {});
    return test::writeText(p, bytes.substr(std::min(bytes.size(), spec.value("skip", std::size_t(0)))));
  }
  const fs::path from = spec.contains("fixture") ? Fixtures::get().path(spec["fixture"])
                                                 : fs::path(test::dataPath(spec.at("data")));
  fs::copy_file(from, p);
  if (spec.contains("bytes")) fs::resize_file(p, spec["bytes"].get<std::uintmax_t>());
}

/// Every entry of a folder with its size and contents (FIFOs and folders by kind only).
std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> s;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    std::string state = e.is_regular_file() ? "file:" : e.is_fifo() ? "fifo" : "folder";
    if (e.is_regular_file()) {
      std::ifstream in(e.path(), std::ios::binary);
      state += std::string(std::istreambuf_iterator<char>(in), {});
    }
    s[fs::relative(e.path(), dir).string()] = std::move(state);
  }
  return s;
}

struct ChildRun {
  int status = 0;
  bool hung = false;
  std::string output;
};

/// Run rtsdf with @a args in @a dir (stdout and stderr to one file), killed after a minute.
ChildRun runIn(const fs::path& dir, const std::vector<std::string>& args, const fs::path& log) {
  const pid_t pid = fork();
  if (pid == 0) {
    if (chdir(dir.c_str()) != 0) _exit(126);
    // No row opens a window: view's rows expect the error of a machine without a window system.
    unsetenv("DISPLAY");
    unsetenv("WAYLAND_DISPLAY");
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    dup2(fd, 1);
    dup2(fd, 2);
#ifndef RTSDF_SANITIZED_BINARY // ASan reserves terabytes of address space
    // A regression that believes a header's size fails here instead of taking the machine's memory.
    const rlimit as{8ull << 30, 8ull << 30};
    setrlimit(RLIMIT_AS, &as);
#endif
    std::vector<char*> argv{const_cast<char*>(RTSDF_BINARY)};
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv(RTSDF_BINARY, argv.data());
    _exit(127);
  }
  ChildRun r;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(1);
  while (waitpid(pid, &r.status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &r.status, 0);
      r.hung = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::ifstream in(log, std::ios::binary);
  r.output.assign(std::istreambuf_iterator<char>(in), {});
  return r;
}

/// The names whose state differs between two snapshots (created, changed or removed).
std::string differences(const std::map<std::string, std::string>& a, const std::map<std::string, std::string>& b) {
  std::string d;
  for (const auto& [name, state] : a)
    if (!b.count(name)) d += " removed " + name;
    else if (b.at(name) != state) d += " changed " + name;
  for (const auto& [name, state] : b)
    if (!a.count(name)) d += " created " + name;
  return d;
}

class BadInput : public testing::TestWithParam<Row> {};

TEST_P(BadInput, IsRefusedClearlyLeavingNothingBehind) {
  const Row& row = GetParam();
  ASSERT_EQ(row.tableError, "");
  test::TempDir work, logs;
  for (const auto& [name, spec] : row.files.items()) createFile(work / name, spec);
  const auto before = snapshot(work.path());
  const ChildRun r = runIn(work.path(), row.args, logs / "output.txt");
  ASSERT_FALSE(r.hung) << "no answer within a minute:\n" << r.output;
  ASSERT_TRUE(WIFEXITED(r.status)) << "killed by signal " << WTERMSIG(r.status) << ":\n" << r.output.substr(0, 2000);
  EXPECT_EQ(WEXITSTATUS(r.status), row.exit) << r.output;
  for (const std::string& w : row.words) EXPECT_NE(r.output.find(w), std::string::npos) << "'" << w << "' in:\n"
                                                                                         << r.output;
  std::istringstream lines(r.output);
  for (std::string line; std::getline(lines, line);) EXPECT_LE(line.size(), 300u) << line.substr(0, 300) << "...";
  EXPECT_EQ(differences(before, snapshot(work.path())), "") << r.output;
}

std::string rowName(const testing::TestParamInfo<Row>& info) { return info.param.kind; }

INSTANTIATE_TEST_SUITE_P(Table, BadInput, testing::ValuesIn(loadRows()), rowName);

} // namespace

// SIGINT and SIGTERM at any moment leave no file behind and exit 130 / 143. Deterministic first: the signal is
// raised inside an atomic write, after its temporary file exists.
namespace {

int statusOfWriteInterruptedBy(int sig, const fs::path& target) {
  const pid_t pid = fork();
  if (pid == 0) {
    installInterruptHandlers();
    std::freopen("/dev/null", "w", stderr);
    writeFileAtomically(target, [sig](const fs::path& tmp) {
      test::writeText(tmp, "half a file");
      raise(sig);
      _exit(3); // not reached when the handler exits
    });
    _exit(4);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

} // namespace

TEST(Interrupt, SignalDuringAnAtomicWriteRemovesTheTemporaryFile) {
  for (const int sig : {SIGINT, SIGTERM}) {
    test::TempDir dir;
    const int status = statusOfWriteInterruptedBy(sig, dir / "x.vdb");
    ASSERT_TRUE(WIFEXITED(status)) << "signal " << sig;
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    EXPECT_TRUE(fs::is_empty(dir.path())) << "signal " << sig << " left a file behind";
  }
}

// End to end: the signal is sent the moment the bake's temporary .vdb appears (a 40 MB zip write).
TEST(Interrupt, SignalDuringTheFinalWriteOfABakeLeavesNothing) {
  for (const int sig : {SIGINT, SIGTERM}) {
    test::TempDir dir, logs;
    fs::copy_file(Fixtures::get().path("cube.obj"), dir / "cube.obj");
    const pid_t pid = fork();
    if (pid == 0) {
      if (chdir(dir.path().c_str()) != 0) _exit(126);
      std::freopen((logs / "out.txt").c_str(), "w", stderr);
      std::freopen("/dev/null", "w", stdout);
      execl(RTSDF_BINARY, RTSDF_BINARY, "bake", "cube.obj", "-o", "x.vdb", "--res", "300", "--band", "0.03",
            "--compression", "zip", static_cast<char*>(nullptr));
      _exit(127);
    }
    bool seen = false;
    int status = 0;
    while (!seen && waitpid(pid, &status, WNOHANG) == 0) {
      for (const auto& e : fs::directory_iterator(dir.path()))
        seen = seen || e.path().filename().string().rfind(".x.vdb.tmp", 0) == 0;
      if (seen) kill(pid, sig);
      else std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
    if (seen) waitpid(pid, &status, 0);
    ASSERT_TRUE(seen) << "the bake ended before its temporary file was seen";
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
    std::ifstream log(logs / "out.txt");
    EXPECT_NE(std::string(std::istreambuf_iterator<char>(log), {}).find("interrupted"), std::string::npos);
    std::vector<std::string> left;
    for (const auto& e : fs::directory_iterator(dir.path())) left.push_back(e.path().filename().string());
    EXPECT_EQ(left, std::vector<std::string>{"cube.obj"});
  }
}
