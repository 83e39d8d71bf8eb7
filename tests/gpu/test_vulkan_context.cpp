#include "gpu/EmbeddedShaders.h"
#include "gpu/Resources.h"
#include "gpu/VulkanContext.h"
#include "gpu/VulkanError.h"

#include <gtest/gtest.h>

using namespace rtsdf;
using namespace rtsdf::gpu;

TEST(EmbeddedShaders, FillShaderIsValidSpirv) {
  const EmbeddedShader& s = embeddedShader("fill.comp");
  ASSERT_GT(s.count, 5u);
  EXPECT_EQ(s.words[0], 0x07230203u); // SPIR-V magic number
  EXPECT_THROW(embeddedShader("missing.comp"), Error);
  const auto names = embeddedShaderNames();
  EXPECT_NE(std::find(names.begin(), names.end(), "fill.comp"), names.end());
}

TEST(VulkanContext, ListsDevicesAndPrefersGpus) {
  const auto devices = listDevices();
  ASSERT_FALSE(devices.empty());
  for (const auto& d : devices) {
    EXPECT_FALSE(d.name.empty());
    EXPECT_GT(d.maxComputeInvocations, 0u);
  }
  std::vector<DeviceInfo> fake(3);
  fake[0].index = 0; fake[0].type = VK_PHYSICAL_DEVICE_TYPE_CPU; fake[0].name = "llvmpipe";
  fake[1].index = 1; fake[1].type = VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU; fake[1].name = "Intel";
  fake[2].index = 2; fake[2].type = VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU; fake[2].name = "NVIDIA H100";
  EXPECT_EQ(chooseDevice(fake, ""), 2u);
  EXPECT_EQ(chooseDevice(fake, "1"), 1u);
  EXPECT_EQ(chooseDevice(fake, "llvm"), 0u);
  EXPECT_EQ(chooseDevice(fake, "h100"), 2u);
  EXPECT_THROW(chooseDevice(fake, "7"), Error);
  EXPECT_THROW(chooseDevice(fake, "radeon"), Error);
}

TEST(VulkanContext, CreatesDeviceAndShaderModuleWithoutValidationErrors) {
  ContextOptions opt;
  opt.validation = true; // the suite runs with validation on; this test insists on it
  VulkanContext ctx(opt);
  EXPECT_TRUE(ctx.validationEnabled());
  EXPECT_NE(ctx.device(), VK_NULL_HANDLE);
  EXPECT_NE(ctx.queue(), VK_NULL_HANDLE);
  VkShaderModule m = ctx.createShaderModule("fill.comp");
  EXPECT_NE(m, VK_NULL_HANDLE);
  vkDestroyShaderModule(ctx.device(), m, nullptr);
  EXPECT_EQ(ctx.validationErrors(), 0u) << ctx.lastValidationMessage();
}

TEST(VulkanContext, ValidationErrorsAreCounted) {
  // Prove the messenger works: a shader module from garbage words is a validation error.
  ContextOptions opt;
  opt.validation = true;
  VulkanContext ctx(opt);
  const std::uint32_t junk[5] = {0x07230203u, 0x00010000u, 0u, 0u, 0u};
  VkShaderModuleCreateInfo ci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  ci.codeSize = sizeof(junk);
  ci.pCode = junk;
  VkShaderModule m = VK_NULL_HANDLE;
  vkCreateShaderModule(ctx.device(), &ci, nullptr, &m);
  if (m) vkDestroyShaderModule(ctx.device(), m, nullptr);
  EXPECT_GT(ctx.validationErrors(), 0u);
}

TEST(VulkanContext, ObjectsLeftAliveAreCountedWhenTheDeviceIsDestroyed) {
  // The validation layer reports a buffer still alive at vkDestroyDevice; close() destroys the device while the
  // messenger still listens, so that error is counted and readable after.
  ContextOptions opt;
  opt.validation = true;
  VulkanContext ctx(opt);
  VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bi.size = 256;
  bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
  VkBuffer leaked = VK_NULL_HANDLE;
  ASSERT_EQ(vkCreateBuffer(ctx.device(), &bi, nullptr, &leaked), VK_SUCCESS);
  EXPECT_EQ(ctx.validationErrors(), 0u) << ctx.lastValidationMessage();
  ctx.close();
  EXPECT_EQ(ctx.device(), VK_NULL_HANDLE);
  EXPECT_GT(ctx.validationErrors(), 0u);
  EXPECT_NE(ctx.lastValidationMessage().find("VkBuffer"), std::string::npos) << ctx.lastValidationMessage();
}

TEST(VulkanContext, SynchronizationValidationReportsAMissingBarrier) {
  // Prove the synchronization-validation switch works: a buffer fill followed by a copy that reads the
  // buffer, with no barrier between them, is a read-after-write hazard.
  ContextOptions opt;
  opt.validation = true;
  opt.syncValidation = true;
  VulkanContext ctx(opt);
  {
    Buffer a(ctx, 1024, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "a");
    Buffer b(ctx, 1024, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, Buffer::Memory::Device, "b");
    CommandBuffer cmd(ctx);
    vkCmdFillBuffer(cmd.handle(), a.handle(), 0, VK_WHOLE_SIZE, 7u);
    const VkBufferCopy region{0, 0, 1024};
    vkCmdCopyBuffer(cmd.handle(), a.handle(), b.handle(), 1, &region);
    cmd.submitAndWait();
  }
  EXPECT_GT(ctx.validationErrors(), 0u);
  EXPECT_NE(ctx.lastValidationMessage().find("SYNC"), std::string::npos) << ctx.lastValidationMessage();
}

TEST(VulkanContext, UnknownDeviceRequestIsAClearError) {
  ContextOptions opt;
  opt.validation = false;
  opt.device = "no-such-gpu";
  try {
    VulkanContext ctx(opt);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-gpu"), std::string::npos);
  }
}

TEST(VulkanError, CarriesResultAndReason) {
  const VulkanError e(VK_ERROR_OUT_OF_DEVICE_MEMORY, "allocating the seed image");
  EXPECT_EQ(e.result(), VK_ERROR_OUT_OF_DEVICE_MEMORY);
  EXPECT_NE(std::string(e.what()).find("VK_ERROR_OUT_OF_DEVICE_MEMORY"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("allocating the seed image"), std::string::npos);
}
