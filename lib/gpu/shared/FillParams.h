// Structs shared by C++ and GLSL: include from both (GLSL via GL_GOOGLE_include_directive).
// Only 32-bit scalars and vectors laid out in std430-compatible order go here.
#ifndef RTSDF_GPU_SHARED_FILLPARAMS_H
#define RTSDF_GPU_SHARED_FILLPARAMS_H

#ifdef __cplusplus
#include <cstdint>
namespace rtsdf::gpu::shared {
using uint = std::uint32_t;
#endif

/// Push constants of fill.comp: out[i] = i * scale + offset for i < count.
struct FillParams {
  uint count;
  uint scale;
  uint offset;
  uint pad0;
};

#ifdef __cplusplus
static_assert(sizeof(FillParams) == 16, "FillParams must match the GLSL push-constant layout");
} // namespace rtsdf::gpu::shared
#endif

#endif
