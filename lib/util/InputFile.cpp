#include "util/InputFile.h"

#include "util/Error.h"

#include <fmt/format.h>

#include <fstream>
#include <system_error>

namespace rtsdf {
namespace fs = std::filesystem;

namespace {
const char* kindOf(fs::file_type t) {
  switch (t) {
  case fs::file_type::directory: return "a folder";
  case fs::file_type::fifo: return "a FIFO";
  case fs::file_type::socket: return "a socket";
  case fs::file_type::block: return "a block device";
  case fs::file_type::character: return "a character device";
  default: return "not a file";
  }
}
} // namespace

std::uint64_t checkInputFile(const fs::path& path, const std::string& what) {
  if (path.empty()) throw Error(fmt::format("the {} path is empty", what));
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (st.type() == fs::file_type::not_found) throw Error(fmt::format("{}: {} not found", path.string(), what));
  if (ec) throw Error(fmt::format("{}: cannot access the {}: {}", path.string(), what, ec.message()));
  if (st.type() != fs::file_type::regular)
    throw Error(fmt::format("{}: the {} is {}, not a regular file", path.string(), what, kindOf(st.type())));
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw Error(fmt::format("{}: cannot read the {}: {}", path.string(), what, ec.message()));
  return size;
}

std::string readFileBytes(const fs::path& path, const std::string& what, std::uint64_t maxBytes) {
  const std::uint64_t size = checkInputFile(path, what);
  if (size > maxBytes)
    throw Error(fmt::format("{}: the {} has {} bytes, more than the {} this reader accepts", path.string(), what, size,
                            maxBytes));
  std::ifstream in(path, std::ios::binary);
  std::string bytes(size, '\0');
  if (!in || !in.read(bytes.data(), std::streamsize(size)))
    throw Error(fmt::format("{}: cannot read the {}", path.string(), what));
  return bytes;
}

std::string readFileHead(const fs::path& path, std::size_t count) {
  std::ifstream in(path, std::ios::binary);
  std::string bytes(count, '\0');
  in.read(bytes.data(), std::streamsize(count));
  bytes.resize(std::size_t(in.gcount()));
  return bytes;
}

} // namespace rtsdf
