// Fuzz target: glTF 2.0, binary (.glb: chunk lengths from the file) and JSON (.gltf: buffers as data URIs,
// accessors, indices). The first byte picks the format; the rest are the file. Read from memory, so no external
// buffer can be opened. Any bytes must give a valid mesh or an rtsdf::Error.
#include "scene/Mesh.h"
#include "scene/MeshIO.h"
#include "util/Error.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const char* extension = data[0] % 2 ? ".gltf" : ".glb";
  try {
    rtsdf::Mesh mesh =
        rtsdf::loadMeshFromMemory(std::string(reinterpret_cast<const char*>(data + 1), size - 1), extension, "fuzz");
    rtsdf::validateMesh(mesh);
  } catch (const rtsdf::Error&) {
  }
  return 0;
}
