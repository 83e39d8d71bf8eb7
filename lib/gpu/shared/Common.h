// Lets one header declare structs and functions for both C++ (with GLM) and GLSL.
// Include first from any shared header. In GLSL: RTSDF_FN is empty and RTSDF_PRECISE is 'precise' (no FMA
// contraction), so the C++ reference (compiled with -ffp-contract=off) runs the same float operations.
#ifndef RTSDF_GPU_SHARED_COMMON_H
#define RTSDF_GPU_SHARED_COMMON_H

#ifdef __cplusplus
#include <glm/glm.hpp>
#include <cstdint>
#define RTSDF_FN inline
#define RTSDF_PRECISE
#define RTSDF_SHARED_BEGIN namespace rtsdf::gpu::shared { \
  using uint = std::uint32_t; using glm::vec3; using glm::vec4; using glm::ivec3; using glm::ivec4; \
  using glm::ivec2; using glm::uvec2; using glm::uvec3; using glm::uvec4; using glm::min; using glm::max; using glm::abs; using glm::floor; \
  using glm::clamp; using glm::sqrt; using glm::length; using glm::normalize; using glm::dot; using glm::cross; \
  using glm::cos; using glm::sin; using glm::exp2; using glm::log2;
#define RTSDF_SHARED_END }
#define RTSDF_OUT(T) T&
#define RTSDF_INOUT(T) T&
#else
#define RTSDF_OUT(T) out T
#define RTSDF_INOUT(T) inout T
#define RTSDF_FN
#define RTSDF_PRECISE precise
#define RTSDF_SHARED_BEGIN
#define RTSDF_SHARED_END
#endif

RTSDF_SHARED_BEGIN

/// PCG hash (O'Neill's PCG-RXS-M-XS, as in Jarzynski and Olano 2020): a well-mixed 32-bit hash.
RTSDF_FN uint pcgHash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

/// A uniform number in [0, 1) from the top 24 bits of a hash.
RTSDF_FN float unitFloat(uint h) { return float(h >> 8) * (1.0 / 16777216.0); }

RTSDF_SHARED_END

#endif
