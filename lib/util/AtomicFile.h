#pragma once
/// @file AtomicFile.h
/// @brief Write-to-temporary-then-rename, so a failed write never leaves a partial output file.
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace rtsdf {

/// @brief Call @a write with a temporary path beside @a target, flush the file to the disk (fsync), then rename it
///        onto @a target.
/// @param target the final path; its directory must exist.
/// @param write  writes the complete file to the path it is given and checks it (the stream's state, or a
///               read-back where the writer does not report errors); throws on failure.
/// @throw Error naming @a target when @a write throws or the flush fails (a full disk).
/// @note On any exception the temporary file is removed and @a target is left untouched.
void writeFileAtomically(const std::filesystem::path& target,
                         const std::function<void(const std::filesystem::path&)>& write);

/// @brief Fail early (before any work) when @a path cannot or must not be written: it is empty, its folder is
///        missing or takes no files (probed by creating and removing a file beside it), it is a folder, its
///        extension is not @a extension, or it is one of @a inputs.
/// @param extension the format's extension with its dot (".vdb"), compared ignoring case; empty: any.
/// @param inputs files the command reads: an output never replaces one of them.
/// @throw Error naming the path and the problem.
void checkOutputPath(const std::filesystem::path& path, const std::string& extension = {},
                     const std::vector<std::filesystem::path>& inputs = {});

/// @brief Write @a text to @a target atomically. @throw Error naming the file on failure.
void writeTextAtomically(const std::filesystem::path& target, const std::string& text);

} // namespace rtsdf
