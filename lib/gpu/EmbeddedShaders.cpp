#include "gpu/EmbeddedShaders.h"

#include "util/Error.h"

#include <fmt/format.h>

namespace rtsdf::gpu {

const EmbeddedShader& embeddedShader(const std::string& name) {
  for (std::size_t i = 0; i < detail::kShaderCount; ++i)
    if (name == detail::kShaders[i].name) return detail::kShaders[i];
  throw Error(fmt::format("no embedded shader named '{}'", name));
}

std::vector<std::string> embeddedShaderNames() {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < detail::kShaderCount; ++i) names.emplace_back(detail::kShaders[i].name);
  return names;
}

} // namespace rtsdf::gpu
