#include "sdf/scenebvh/GpuSceneBvh.h"

#include <algorithm>
#include <cstring>

namespace rtsdf {

namespace {
using gpu::kStorage;
} // namespace

GpuSceneBvh::GpuSceneBvh(const gpu::VulkanContext& ctx, const Scene& scene, const glm::dvec3& frameOrigin)
    : mCtx(ctx), mScene(scene), mFrameOrigin(frameOrigin), mMeshes(buildMeshBvhs(scene)) {
  gpu::reserveAndUpload(ctx, mBlasNodes, mMeshes.nodes.data(), mMeshes.nodes.size() * sizeof(gpu::shared::BvhNode),
                        kStorage, "BLAS nodes");
  gpu::reserveAndUpload(ctx, mCorners, mMeshes.corners.data(), mMeshes.corners.size() * sizeof(glm::vec4), kStorage,
                        "BLAS triangles");
  gpu::reserveAndUpload(ctx, mTriangleIds, mMeshes.triangleIds.data(), mMeshes.triangleIds.size() * 4, kStorage,
                        "triangle ids");
  // Each triangle's closed piece, and room for every instance's closed pieces in a frame's overlap list.
  mPieces = sceneClosedPieces(scene, mMeshes);
  gpu::reserveAndUpload(ctx, mPieceOf, mPieces.pieceOfLeaf.data(), mPieces.pieceOfLeaf.size() * 4, kStorage,
                        "triangle pieces");
  mUnionPieces = gpu::Buffer(ctx,
                             sizeof(glm::uvec4) + std::max<std::size_t>(mPieces.instancedClosedPieces(scene), 1) *
                                                      sizeof(gpu::shared::UnionPiece),
                             kStorage, gpu::Buffer::Memory::Device, "overlapping closed pieces");
  // Where open meshes need the winding number, and the dipoles that sum it.
  mOpen = sceneOpenPieces(scene, mMeshes);
  gpu::reserveAndUpload(ctx, mOpenFlags, mOpen.flagsOfLeaf.data(), mOpen.flagsOfLeaf.size() * 4, kStorage,
                        "open-mesh flags");
  gpu::reserveAndUpload(ctx, mWindingNodes, mOpen.windingNodes.data(),
                        mOpen.windingNodes.size() * sizeof(gpu::shared::WindingNode), kStorage, "winding dipoles");
  // Where each instance's triangles lie; the transforms follow with every update.
  for (const Instance& inst : scene.instances) {
    gpu::shared::VoxelizeInstance v{};
    v.firstTriangle = mMeshes.firstTriangles.at(inst.mesh);
    v.triangleCount = std::uint32_t(scene.meshes.at(inst.mesh).triangles.size());
    v.firstInstanceTriangle = mTriangleCount;
    mTriangleCount += v.triangleCount;
    mVoxelizeInstances.push_back(v);
  }
  std::vector<glm::uvec2> ranges;
  for (const gpu::shared::VoxelizeInstance& v : mVoxelizeInstances) ranges.emplace_back(v.firstTriangle, v.triangleCount);
  if (ranges.empty()) ranges.emplace_back(0u, 0u);
  gpu::reserveAndUpload(ctx, mInstanceTriangles, ranges.data(), ranges.size() * sizeof(glm::uvec2), kStorage,
                        "instance triangles");
  // The top level of n instances has 2n - 1 nodes (one instance per leaf): sized once, so frames only write.
  const std::size_t n = std::max<std::size_t>(scene.instances.size(), 1);
  using gpu::Buffer;
  mTlasNodes = Buffer(ctx, (2 * n - 1) * sizeof(gpu::shared::BvhNode), kStorage, Buffer::Memory::Device, "TLAS nodes");
  mTlasSlots = Buffer(ctx, n * 4, kStorage, Buffer::Memory::Device, "TLAS slots");
  mInstances = Buffer(ctx, n * sizeof(gpu::shared::BvhInstance), kStorage, Buffer::Memory::Device, "instances");
  mVoxelizeBuf = Buffer(ctx, n * sizeof(gpu::shared::VoxelizeInstance), kStorage, Buffer::Memory::Device,
                        "voxelize instances");
}

void GpuSceneBvh::update(double time) {
  if (mHaveTop && time == mTime) return;
  gpu::CommandBuffer cmd(mCtx);
  recordUpdate(cmd.handle(), time);
  cmd.submitAndWait();
}

void GpuSceneBvh::recordUpdate(VkCommandBuffer cmd, double time) {
  if (mHaveTop && time == mTime) return;
  mTop = buildInstanceBvh(mScene, mMeshes, time, mFrameOrigin);
  for (std::size_t i = 0; i < mTop.instances.size(); ++i) {
    if (!mSeedOrigin) { // the top level's rows
      for (int r = 0; r < 3; ++r) mVoxelizeInstances[i].objectToFrame[r] = mTop.instances[i].objectToWorld[r];
      continue;
    }
    glm::dmat4 m = mScene.instances[i].matrixAt(time); // as buildInstanceBvh rounds its rows, from the seeds' origin
    m[3] -= glm::dvec4(*mSeedOrigin, 0.0);
    for (int r = 0; r < 3; ++r) mVoxelizeInstances[i].objectToFrame[r] = glm::vec4(m[0][r], m[1][r], m[2][r], m[3][r]);
  }
  gpu::computeBarrier(cmd); // earlier passes (of this or an earlier submission) are done reading
  gpu::recordUpload(cmd, mTlasNodes, mTop.nodes.data(), mTop.nodes.size() * sizeof(gpu::shared::BvhNode));
  gpu::recordUpload(cmd, mTlasSlots, mTop.slots.data(), mTop.slots.size() * 4);
  gpu::recordUpload(cmd, mInstances, mTop.instances.data(), mTop.instances.size() * sizeof(gpu::shared::BvhInstance));
  gpu::recordUpload(cmd, mVoxelizeBuf, mVoxelizeInstances.data(),
                    mVoxelizeInstances.size() * sizeof(gpu::shared::VoxelizeInstance));
  // The pieces that overlap at this moment (instances move): the header, then the list.
  mUnionList = overlappingClosedPieces(mScene, mPieces, mTop, mUnionReach);
  static_assert(sizeof(gpu::shared::UnionPiece) == 2 * sizeof(glm::uvec4), "UnionPiece is two uvec4s in std430");
  mUnionUpload.assign(1, glm::uvec4(std::uint32_t(mUnionList.size()), 0u, 0u, 0u));
  const std::size_t header = mUnionUpload.size();
  mUnionUpload.resize(header + 2 * mUnionList.size());
  if (!mUnionList.empty()) // memcpy from an empty vector's null data is undefined
    std::memcpy(mUnionUpload.data() + header, mUnionList.data(), mUnionList.size() * sizeof(gpu::shared::UnionPiece));
  gpu::recordUpload(cmd, mUnionPieces, mUnionUpload.data(), mUnionUpload.size() * sizeof(glm::uvec4));
  gpu::computeBarrier(cmd);
  mTime = time;
  mHaveTop = true;
}

InstancedTriangles GpuSceneBvh::instancedTriangles() const {
  return {mCorners, mVoxelizeBuf, std::uint32_t(mVoxelizeInstances.size()), mTriangleCount};
}

} // namespace rtsdf
