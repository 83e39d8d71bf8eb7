#pragma once
/// @file Bvh.h
/// @brief BVHs built by Embree's builder API (rtcBuildBVH, SAH) and flattened for the GPU: one bottom level
///        per mesh in object space, built once, and a top level over the instances, rebuilt every frame.
#include "bvh/GpuBvhLayout.h"
#include "scene/Scene.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace rtsdf {

/// @brief The bottom levels of every mesh of a scene, concatenated: nodes (child and triangle indices are
///        absolute) and triangle corners in leaf order.
struct MeshBvhs {
  std::vector<gpu::shared::BvhNode> nodes;
  std::vector<glm::vec4> corners;        ///< 3 per triangle, object space, in leaf order
  std::vector<std::uint32_t> triangleIds; ///< original triangle index of each leaf-ordered triangle
  std::vector<std::uint32_t> roots;      ///< root node of each mesh
  std::vector<std::uint32_t> firstTriangles; ///< each mesh's first leaf-ordered triangle (its corners from 3x that)
  std::vector<glm::vec3> meshLo, meshHi; ///< object-space bounds of each mesh
};

/// @brief The top level at one moment: instances (in the scene's order) and a BVH over their world boxes,
///        measured from the frameOrigin it was built for.
struct InstanceBvh {
  std::vector<gpu::shared::BvhNode> nodes;
  std::vector<std::uint32_t> slots;            ///< leaf primitive -> instance index
  std::vector<gpu::shared::BvhInstance> instances;
};

/// @brief @a p mapped by the 3x4 matrix whose rows are @a m (BvhInstance::worldToObject or objectToWorld), in the
///        order of operations of the shaders' xformPoint (bvh_traverse.glsl), for the CPU copies of their queries.
inline glm::vec3 xformPoint(const glm::vec4 (&m)[3], const glm::vec3& p) {
  return {glm::dot(glm::vec3(m[0]), p) + m[0].w, glm::dot(glm::vec3(m[1]), p) + m[1].w,
          glm::dot(glm::vec3(m[2]), p) + m[2].w};
}

/// @brief Build the bottom level of every mesh of @a scene (once: meshes do not change).
/// @param maxLeafSize triangles per leaf at most (1 to 32).
MeshBvhs buildMeshBvhs(const Scene& scene, int maxLeafSize = 4);

/// @brief Build the top level for the instance transforms at @a time seconds.
/// @param frameOrigin the world point the top level measures from: instance transforms map object space to
///        world - frameOrigin (subtracted in double before rounding to float), so queries near a grid far from
///        the world's origin keep float precision.
InstanceBvh buildInstanceBvh(const Scene& scene, const MeshBvhs& meshes, double time,
                             const glm::dvec3& frameOrigin = glm::dvec3(0.0));

/// @brief Generic SAH build over boxes with Embree's rtcBuildBVH, flattened to BvhNode (children adjacent).
/// @param lo, hi the primitives' boxes; @param order receives the primitive index of each leaf slot.
std::vector<gpu::shared::BvhNode> buildBvh(const std::vector<glm::vec3>& lo, const std::vector<glm::vec3>& hi,
                                           int maxLeafSize, std::vector<std::uint32_t>& order);

} // namespace rtsdf
