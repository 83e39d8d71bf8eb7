#pragma once
/// @file EmbeddedShaders.h
/// @brief SPIR-V compiled by glslc at build time (lib/Shaders.cmake: one row per shader) and linked into the library.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtsdf::gpu {

/// @brief One embedded SPIR-V module.
struct EmbeddedShader {
  const char* name;           ///< its name in lib/Shaders.cmake, e.g. "fill.comp"
  const std::uint32_t* words; ///< SPIR-V words
  std::size_t count;          ///< number of words
};

/// @brief The embedded module named @a name (lib/Shaders.cmake's first column). @throw Error when there is none.
const EmbeddedShader& embeddedShader(const std::string& name);

/// @brief Names of every embedded shader.
std::vector<std::string> embeddedShaderNames();

namespace detail {
extern const EmbeddedShader kShaders[];
extern const std::size_t kShaderCount;
} // namespace detail

} // namespace rtsdf::gpu
