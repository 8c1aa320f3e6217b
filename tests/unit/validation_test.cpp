// The validation layer's errors are counted wherever they are raised, including while a device is
// destroyed: an object leaked by a pass or by the graph must fail the test or command that leaked it.
#include <gtest/gtest.h>

#include "passes/core/device.h"

namespace nightcap::test {
namespace {

TEST(Validation, ObjectsLeakedAtDeviceDestructionAreCounted) {
  const uint32_t before = validation_errors_reported();
  {
    GpuDevice gpu({"", true});
    gpu.create_buffer(256, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, false);  // never destroyed, on purpose
    EXPECT_EQ(validation_errors_reported(), before) << "creating a buffer is valid";
  }
  EXPECT_GT(validation_errors_reported(), before) << "the leaked buffer and its memory went unreported";
}

}  // namespace
}  // namespace nightcap::test
