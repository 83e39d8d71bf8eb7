#pragma once
/// @file InputFile.h
/// @brief Checks on a file before it is read: it exists and is a regular file (a FIFO, a device or a folder
///        would block or mislead a reader), and claims made by its header are bounded by its size.
#include <cstdint>
#include <filesystem>
#include <string>

namespace rtsdf {

/// @brief Require @a path to name an existing regular file (symbolic links are followed).
/// @param what the kind of file, for the message ("scene file", "mesh file", ".vdb file").
/// @return the file's size in bytes.
/// @throw Error "<path>: <what> not found" or "<path>: not a regular file (a FIFO)" and the like.
std::uint64_t checkInputFile(const std::filesystem::path& path, const std::string& what);

/// @brief The whole file as bytes. @throw Error naming the file when it cannot be read.
/// @param maxBytes files larger than this are refused before anything is read.
std::string readFileBytes(const std::filesystem::path& path, const std::string& what,
                          std::uint64_t maxBytes = std::uint64_t(1) << 32);

/// @brief At most @a count bytes from the start of the file (fewer when it is shorter).
std::string readFileHead(const std::filesystem::path& path, std::size_t count);

} // namespace rtsdf
