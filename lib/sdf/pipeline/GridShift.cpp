#include "sdf/pipeline/GridShift.h"

#include "sdf/mask/MaskParams.h"
#include "util/Error.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>

namespace rtsdf {

namespace {

/// Append [offset, offset + size) to @a fills, merged with the last one when they touch.
void addFill(std::vector<GridShiftPlan::Fill>& fills, VkDeviceSize offset, VkDeviceSize size) {
  if (size == 0) return;
  if (!fills.empty() && fills.back().offset + fills.back().size == offset) {
    fills.back().size += size;
    return;
  }
  fills.push_back({offset, size});
}

/// Append a copy, merged with the last one when both its source and destination continue it.
void addCopy(std::vector<VkBufferCopy>& copies, VkDeviceSize src, VkDeviceSize dst, VkDeviceSize size) {
  if (size == 0) return;
  if (!copies.empty()) {
    VkBufferCopy& last = copies.back();
    if (last.srcOffset + last.size == src && last.dstOffset + last.size == dst) {
      last.size += size;
      return;
    }
  }
  copies.push_back({src, dst, size});
}

/// @throw Error naming @a who when the element is not a positive multiple of 4 bytes or the grid is empty.
void checkGrid(const char* who, const glm::ivec3& dims, std::uint32_t elementBytes) {
  if (elementBytes == 0 || elementBytes % 4 != 0)
    throw Error(fmt::format("{}: element of {} bytes (a positive multiple of 4 expected)", who, elementBytes));
  if (glm::any(glm::lessThanEqual(dims, glm::ivec3(0))))
    throw Error(fmt::format("{}: grid of {}x{}x{} cells", who, dims.x, dims.y, dims.z));
}

/// An empty plan over a grid of @a dims cells of @a elementBytes each (its bytes set).
GridShiftPlan emptyPlan(const glm::ivec3& dims, std::uint32_t elementBytes) {
  checkGrid("gridShiftPlan", dims, elementBytes);
  GridShiftPlan plan;
  plan.bytes = VkDeviceSize(dims.x) * elementBytes * VkDeviceSize(dims.y) * VkDeviceSize(dims.z);
  return plan;
}

} // namespace

GridShiftPlan gridShiftPlan(const glm::ivec3& dims, std::uint32_t elementBytes, const glm::ivec3& shift) {
  GridShiftPlan plan = emptyPlan(dims, elementBytes);
  const VkDeviceSize e = elementBytes;
  const VkDeviceSize row = VkDeviceSize(dims.x) * e;
  // Along x, the destination cells [x0, x1) read source cells [x0 + shift.x, x1 + shift.x).
  const int x0 = std::clamp(-shift.x, 0, dims.x), x1 = std::clamp(dims.x - shift.x, 0, dims.x);
  for (int z = 0; z < dims.z; ++z)
    for (int y = 0; y < dims.y; ++y) {
      const VkDeviceSize dst = (VkDeviceSize(z) * dims.y + y) * row;
      const int sy = y + shift.y, sz = z + shift.z;
      if (sy < 0 || sy >= dims.y || sz < 0 || sz >= dims.z || x1 <= x0) {
        addFill(plan.fills, dst, row);
        continue;
      }
      const VkDeviceSize src = (VkDeviceSize(sz) * dims.y + sy) * row;
      addFill(plan.fills, dst, VkDeviceSize(x0) * e);
      addCopy(plan.copies, src + VkDeviceSize(x0 + shift.x) * e, dst + VkDeviceSize(x0) * e,
              VkDeviceSize(x1 - x0) * e);
      addFill(plan.fills, dst + VkDeviceSize(x1) * e, VkDeviceSize(dims.x - x1) * e);
    }
  return plan;
}

GridShiftPlan gridShiftPlanLoose(const glm::ivec3& dims, std::uint32_t elementBytes, const glm::ivec3& shift) {
  GridShiftPlan plan = emptyPlan(dims, elementBytes);
  const long long offset =
      (static_cast<long long>(shift.z) * dims.y + shift.y) * static_cast<long long>(dims.x) + shift.x;
  const VkDeviceSize moved = VkDeviceSize(offset < 0 ? -offset : offset) * elementBytes;
  if (moved >= plan.bytes) return plan;
  // Cell v reads cell v + offset: the destination starts where the source does not and both run to the end.
  const VkDeviceSize src = offset > 0 ? moved : 0, dst = offset < 0 ? moved : 0;
  plan.copies.push_back({src, dst, plan.bytes - moved});
  return plan;
}

std::optional<glm::ivec3> scrollShift(const std::pair<GridSpec, GridSpec>& from, const std::pair<GridSpec, GridSpec>& to) {
  const GridSpec &c0 = from.first, &f0 = from.second, &c1 = to.first, &f1 = to.second;
  if (c0.dims != c1.dims || f0.dims != f1.dims || c0.voxelSize != c1.voxelSize || f0.voxelSize != f1.voxelSize ||
      c0.origin != f0.origin || c1.origin != f1.origin)
    return std::nullopt;
  glm::ivec3 shift(0);
  for (int a = 0; a < 3; ++a) {
    if (f0.dims[a] % c0.dims[a] != 0) return std::nullopt; // fine voxels straddle coarse ones
    const double cells = (c1.origin[a] - c0.origin[a]) / c0.voxelSize;
    const double whole = std::round(cells);
    // Layouts place corners at whole multiples of the coarse voxel: anything else is another lattice.
    if (std::fabs(cells - whole) > 1e-6 || std::fabs(whole) >= c0.dims[a]) return std::nullopt;
    shift[a] = int(whole);
    if ((shift[a] * (f0.dims[a] / c0.dims[a])) % RTSDF_BRICK != 0) return std::nullopt; // bricks would straddle
  }
  return shift;
}

void applyGridShift(const GridShiftPlan& plan, std::vector<std::uint32_t>& words, std::uint32_t fillWord) {
  if (VkDeviceSize(words.size()) * 4 != plan.bytes)
    throw Error(fmt::format("applyGridShift: {} bytes for a plan of {}", words.size() * 4, plan.bytes));
  const std::vector<std::uint32_t> scratch = words;
  for (const VkBufferCopy& c : plan.copies)
    std::memcpy(words.data() + c.dstOffset / 4, scratch.data() + c.srcOffset / 4, c.size);
  for (const GridShiftPlan::Fill& f : plan.fills)
    std::fill_n(words.begin() + std::ptrdiff_t(f.offset / 4), f.size / 4, fillWord);
}

gpu::shared::GridShiftParams gridShiftParams(const glm::ivec3& dims, std::uint32_t elementBytes,
                                              const glm::ivec3& shift, std::uint32_t fillWord) {
  checkGrid("gridShiftParams", dims, elementBytes);
  gpu::shared::GridShiftParams p{};
  p.dims = glm::ivec4(dims, int(elementBytes / 4));
  p.shift = glm::ivec4(shift, 0);
  p.fillWord = fillWord;
  return p;
}

namespace {

VkDeviceSize gridBytes(const gpu::shared::GridShiftParams& p) {
  return VkDeviceSize(p.dims.x) * VkDeviceSize(p.dims.y) * VkDeviceSize(p.dims.z) * VkDeviceSize(p.dims.w) * 4;
}

} // namespace

void GridShiftPass::execute(VkCommandBuffer cmd, gpu::GpuProfiler* profiler, const Inputs& in, const Outputs& out,
                            const Params& params) const {
  const VkDeviceSize bytes = gridBytes(params);
  if (in.source.size() < bytes || out.target.size() < bytes)
    throw Error(fmt::format("GridShiftPass: a grid of {} bytes from a buffer of {} into one of {}", bytes,
                            in.source.size(), out.target.size()));
  gpu::ProfileScope scope(profiler, cmd, kName);
  std::array<gpu::Binding, gpu::shared::kGridShiftBindingCount> b;
  b[gpu::shared::kGridShiftBindingSource] = &in.source;
  b[gpu::shared::kGridShiftBindingTarget] = &out.target;
  mPipeline.dispatch(cmd, b, &params,
                     {gpu::groupsFor(std::uint64_t(params.dims.x), RTSDF_GRID_SHIFT_GROUP_X),
                      gpu::groupsFor(std::uint64_t(params.dims.y), RTSDF_GRID_SHIFT_GROUP_Y),
                      gpu::groupsFor(std::uint64_t(params.dims.z), RTSDF_GRID_SHIFT_GROUP_Z)});
}

void recordGridShift(VkCommandBuffer cmd, const GridShiftPass& pass, const gpu::Buffer& buffer,
                     const gpu::Buffer& scratch, const gpu::shared::GridShiftParams& params) {
  const VkDeviceSize bytes = gridBytes(params);
  if (scratch.size() < bytes || buffer.size() < bytes)
    throw Error(fmt::format("recordGridShift: a shift of {} bytes with a scratch of {} over a buffer of {}", bytes,
                            scratch.size(), buffer.size()));
  gpu::computeBarrier(cmd); // the scratch may still be read by the previous shift
  const VkBufferCopy whole{0, 0, bytes};
  vkCmdCopyBuffer(cmd, buffer.handle(), scratch.handle(), 1, &whole);
  gpu::computeBarrier(cmd);
  pass.execute(cmd, nullptr, {scratch}, {buffer}, params);
  gpu::computeBarrier(cmd);
}

void recordGridShift(VkCommandBuffer cmd, const GridShiftPass* pass, const gpu::Buffer& buffer,
                     const gpu::Buffer& scratch, const glm::ivec3& dims, std::uint32_t elementBytes,
                     const glm::ivec3& shift, std::uint32_t fillWord) {
  if (pass) recordGridShift(cmd, *pass, buffer, scratch, gridShiftParams(dims, elementBytes, shift, fillWord));
  else recordGridShift(cmd, buffer, scratch, gridShiftPlan(dims, elementBytes, shift), fillWord);
}

void recordGridShift(VkCommandBuffer cmd, const gpu::Buffer& buffer, const gpu::Buffer& scratch,
                     const GridShiftPlan& plan, std::uint32_t fillWord) {
  if (scratch.size() < plan.bytes || buffer.size() < plan.bytes)
    throw Error(fmt::format("recordGridShift: a shift of {} bytes with a scratch of {} over a buffer of {}",
                            plan.bytes, scratch.size(), buffer.size()));
  gpu::computeBarrier(cmd); // the scratch may still be read by the previous shift's copies
  const VkBufferCopy whole{0, 0, plan.bytes};
  vkCmdCopyBuffer(cmd, buffer.handle(), scratch.handle(), 1, &whole);
  gpu::computeBarrier(cmd);
  if (!plan.copies.empty())
    vkCmdCopyBuffer(cmd, scratch.handle(), buffer.handle(), std::uint32_t(plan.copies.size()), plan.copies.data());
  for (const GridShiftPlan::Fill& f : plan.fills) vkCmdFillBuffer(cmd, buffer.handle(), f.offset, f.size, fillWord);
  gpu::computeBarrier(cmd);
}

} // namespace rtsdf
