// The validation layer's errors are counted wherever they are raised, including while a device is
// destroyed: an object leaked by a pass or by the graph must fail the test or command that leaked it.
// The messages name objects by the names nightcap gives them, not by their handles.
#include <gtest/gtest.h>

#ifdef NIGHTCAP_SANITIZE_BUILD
#include <sanitizer/lsan_interface.h>
#endif

#include "passes/core/device.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

TEST(Validation, ObjectsLeakedAtDeviceDestructionAreCountedByName) {
  const uint32_t before = validation_errors_reported();
  testing::internal::CaptureStderr();
  {
    GpuDevice gpu({"", true});
    {
#ifdef NIGHTCAP_SANITIZE_BUILD
      // The leak is the point of the test: LeakSanitizer is not to report it.
      __lsan::ScopedDisabler leak_on_purpose;
#endif
      gpu.create_buffer(256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false, "leaked.on.purpose");  // never destroyed
    }
    EXPECT_EQ(validation_errors_reported(), before) << "creating a buffer is valid";
  }
  const std::string messages = testing::internal::GetCapturedStderr();
  EXPECT_GT(validation_errors_reported(), before) << "the leaked buffer and its memory went unreported";
  EXPECT_NE(messages.find("leaked.on.purpose"), std::string::npos) << messages;
  EXPECT_NE(messages.find("leaked.on.purpose memory"), std::string::npos) << messages;
}

// Synchronization validation is on with validation: two transfer writes of one buffer with no
// barrier between them are a write-after-write hazard, reported as an error.
TEST(Validation, SynchronizationHazardsAreErrors) {
  const uint32_t before = validation_errors_reported();
  testing::internal::CaptureStderr();
  {
    GpuDevice gpu({"", true});
    GpuBuffer buffer = gpu.create_buffer(256, VK_BUFFER_USAGE_TRANSFER_DST_BIT, false, "written.twice");
    VkCommandBuffer cmd = gpu.begin_commands("hazard on purpose");
    vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 1);
    vkCmdFillBuffer(cmd, buffer.buffer, 0, VK_WHOLE_SIZE, 2);
    gpu.end_and_wait(cmd);
    gpu.destroy(buffer);
  }
  const std::string messages = testing::internal::GetCapturedStderr();
  EXPECT_GT(validation_errors_reported(), before) << messages;
  EXPECT_NE(messages.find("SYNC-HAZARD-WRITE-AFTER-WRITE"), std::string::npos) << messages;
  EXPECT_NE(messages.find("written.twice"), std::string::npos) << messages;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
