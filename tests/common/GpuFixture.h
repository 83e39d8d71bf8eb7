#pragma once
// A GoogleTest fixture that shares one Vulkan context (validation on) across a suite and fails the suite on
// any validation error or any Vulkan object still alive at its end.
#include "gpu/VulkanContext.h"

#include <gtest/gtest.h>

#include <memory>

namespace rtsdf::test {

template <typename Tag>
class VulkanSuite : public ::testing::Test {
protected:
  static void SetUpTestSuite() {
    gpu::ContextOptions opt;
    opt.validation = true;
    sCtx = std::make_unique<gpu::VulkanContext>(opt);
  }
  static void TearDownTestSuite() {
    Tag::releaseSuiteObjects();
    if (!sCtx) return; // SetUpTestSuite failed (no device, no validation layer): gtest reported it, the tests skipped
    EXPECT_EQ(sCtx->liveObjects(), 0);
    EXPECT_EQ(sCtx->validationErrors(), 0u) << sCtx->lastValidationMessage();
    sCtx->close(); // errors reported at vkDestroyDevice (objects left alive) count too
    EXPECT_EQ(sCtx->validationErrors(), 0u) << sCtx->lastValidationMessage();
    sCtx.reset();
  }
  void TearDown() override {
    if (sCtx) EXPECT_EQ(sCtx->validationErrors(), 0u) << sCtx->lastValidationMessage();
  }
  static inline std::unique_ptr<gpu::VulkanContext> sCtx;
};

/// For suites that keep no GPU objects of their own beyond a test.
struct NoSuiteObjects {
  static void releaseSuiteObjects() {}
};

} // namespace rtsdf::test
