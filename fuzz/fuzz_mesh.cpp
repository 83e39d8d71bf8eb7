// Fuzz target: mesh import (assimp) and validation. The first byte picks the format, the rest are the file.
#include "scene/Mesh.h"
#include "scene/MeshIO.h"
#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const kFormats[] = {".obj", ".ply", ".stl", ".off"};
  const char* extension = kFormats[data[0] % 4];
  try {
    rtsdf::Mesh mesh =
        rtsdf::loadMeshFromMemory(std::string(reinterpret_cast<const char*>(data + 1), size - 1), extension, "fuzz");
    rtsdf::validateMesh(mesh);
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
