// A lavapipe device for reference tests of single passes, with the validation layer on when
// NIGHTCAP_VALIDATION=1 (CTest sets it); a test fails if the layer reported any error, and the
// suite fails if destroying the device reports any (objects leaked by the tests or the graph).
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <memory>

#include "passes/assembly/renderer.h"
#include "passes/core/format.h"
#include "passes/core/isolated.h"

namespace nightcap::test {

class GpuTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const char* validation = std::getenv("NIGHTCAP_VALIDATION");
    gpu_ = std::make_unique<GpuDevice>(GpuDevice::Options{"", validation && std::string(validation) == "1"});
    cache_ = std::make_unique<PipelineCache>(*gpu_);
  }
  static void TearDownTestSuite() {
    const uint32_t before = validation_errors_reported();
    cache_.reset();
    gpu_.reset();
    if (validation_errors_reported() != before)
      ADD_FAILURE() << "Vulkan validation reported errors while the device was destroyed";
  }
  void SetUp() override { errors_before_ = validation_errors_reported(); }
  void TearDown() override {
    EXPECT_EQ(validation_errors_reported(), errors_before_) << "Vulkan validation reported errors";
  }
  uint32_t errors_before_ = 0;

  static IsolatedRun run(const PassDecl& pass, const std::map<std::string, IsolatedInput>& inputs, uint32_t width,
                         uint32_t height, ParamValues params = {}) {
    return run_isolated(*gpu_, *cache_, pass, inputs, params, width, height, builtin_shaders());
  }

  static IsolatedInput image(VkFormat format, ResourceKind kind, uint32_t width, uint32_t height,
                             std::vector<uint8_t> bytes) {
    IsolatedInput input;
    input.desc.format = format;
    input.desc.kind = kind;
    input.desc.extent.width = width;
    input.desc.extent.height = height;
    input.bytes = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
    return input;
  }

  // The first texel of a float image version that is NaN or ±Inf ("resource texel N"), or "".
  static std::string first_non_finite(const Execution& execution) {
    for (const VersionData& v : execution.versions) {
      if (v.desc.is_buffer || !v.bytes) continue;
      const FormatInfo f = *format_info(v.desc.format);
      if (!is_float(f)) continue;
      const uint64_t texels = raw_subresource_offset(f, v.desc.extent, 1, 0, 0) / f.texel_bytes;
      float texel[4];
      for (uint64_t t = 0; t < texels; ++t) {
        decode_texel(f, 0, *v.bytes, t, texel);
        for (uint32_t c = 0; c < f.channels && c < 4; ++c)
          if (!std::isfinite(texel[c])) return v.resource + " texel " + std::to_string(t);
      }
    }
    return "";
  }

  static inline std::unique_ptr<GpuDevice> gpu_;
  static inline std::unique_ptr<PipelineCache> cache_;
};

}  // namespace nightcap::test
