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
  using glm::uvec3; using glm::uvec4; using glm::min; using glm::max; using glm::abs; using glm::floor; \
  using glm::clamp; using glm::sqrt; using glm::length; using glm::normalize; using glm::dot; using glm::cross;
#define RTSDF_SHARED_END }
#define RTSDF_OUT(T) T&
#else
#define RTSDF_OUT(T) out T
#define RTSDF_FN
#define RTSDF_PRECISE precise
#define RTSDF_SHARED_BEGIN
#define RTSDF_SHARED_END
#endif

#endif
