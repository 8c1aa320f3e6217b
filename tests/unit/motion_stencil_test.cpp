// motion.stencil against the brute-force CPU dilation of tests/reference/motion_mask_reference.h:
// the mask must equal it exactly (integer data, no rounding anywhere).
//
// Today's scene has no moving, hair or foliage pixel, so the stencil is crafted: every class and
// flag of passes/scene/scene.h, including road and vehicle marks on tagged and untagged classes,
// with tagged pixels sparse enough that the dilated mask is neither empty nor full. Stress:
// 1×1 (tagged and not), 1279×719, a frame of sky only (nothing tagged: all 0), radius 0 (the
// mask is the tag itself) and a radius wider than the image; a radius above the largest the
// shader's tile holds is refused.
#include <cstring>
#include <random>

#include "passes/depth/kinds.h"
#include "passes/motion/stage.h"
#include "tests/reference/motion_mask_reference.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

enum class Fill { sparse, sky, one_tagged };

struct Case {
  uint32_t width, height;
  int radius;
  Fill fill;
};

std::vector<uint8_t> crafted_tags(uint32_t width, uint32_t height, Fill fill) {
  const uint8_t untagged[] = {stencil::plain, stencil::road,    stencil::body,
                              stencil::face,  stencil::vehicle, stencil::body | stencil::road};
  const uint8_t tagged[] = {stencil::hair,
                            stencil::foliage,
                            stencil::body | stencil::moving,
                            stencil::face | stencil::moving,
                            stencil::vehicle | stencil::moving,
                            stencil::moving,
                            stencil::hair | stencil::road,
                            stencil::foliage | stencil::vehicle};
  std::vector<uint8_t> tags(size_t(width) * height, stencil::plain);
  if (fill == Fill::sky) return tags;
  if (fill == Fill::one_tagged) {
    tags[0] = stencil::foliage;
    return tags;
  }
  std::mt19937 rng(width * 31u + height);
  for (uint8_t& t : tags)
    t = rng() % 200 == 0 ? tagged[rng() % std::size(tagged)] : untagged[rng() % std::size(untagged)];
  return tags;
}

class MotionStencil : public GpuTest, public ::testing::WithParamInterface<Case> {};

TEST_P(MotionStencil, EqualsTheCpuDilation) {
  const auto [width, height, radius, fill] = GetParam();
  const std::vector<uint8_t> tags = crafted_tags(width, height, fill);
  const size_t pixels = tags.size();
  // D32_SFLOAT_S8_UINT raw layout: the depth plane (0: sky), then a byte of stencil per texel.
  std::vector<uint8_t> depth_bytes(pixels * 5, 0);
  std::memcpy(depth_bytes.data() + pixels * 4, tags.data(), pixels);
  const IsolatedRun result =
      run(motion_stencil_pass(),
          {{"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, width, height, depth_bytes)}},
          width, height, {{"radius", double(radius)}});
  const std::vector<uint8_t> expected = reference::motion_mask(tags, width, height, radius);
  const std::vector<uint8_t>& mask = *result.outputs.at("motion.mask");
  ASSERT_EQ(mask.size(), pixels);
  size_t masked = 0, wrong = 0;
  for (size_t i = 0; i < pixels; ++i) {
    masked += expected[i];
    wrong += mask[i] != expected[i];
  }
  EXPECT_EQ(wrong, 0u) << masked << " pixels masked in the reference";
  if (fill == Fill::sky) {
    EXPECT_EQ(masked, 0u);
  }
  if (fill == Fill::sparse) {
    EXPECT_GT(masked, 0u);
    EXPECT_LT(masked, pixels);
  }
  std::printf("motion.mask %ux%u radius %d: %zu of %zu pixels masked, %zu differ\n", width, height, radius, masked,
              pixels, wrong);
}

INSTANTIATE_TEST_SUITE_P(, MotionStencil,
                         ::testing::Values(Case{64, 48, 0, Fill::sparse}, Case{64, 48, 1, Fill::sparse},
                                           Case{64, 48, 2, Fill::sparse}, Case{64, 48, 5, Fill::sparse},
                                           Case{1, 1, 2, Fill::one_tagged}, Case{1, 1, 2, Fill::sky},
                                           Case{13, 7, 16, Fill::one_tagged}, Case{1279, 719, 2, Fill::sparse},
                                           Case{1279, 719, 2, Fill::sky}));

class MotionStencilRadius : public GpuTest {};

TEST_F(MotionStencilRadius, AboveTheTilesApronIsRefused) {
  const std::vector<uint8_t> depth_bytes(4 * 4 * 5, 0);
  EXPECT_THROW(run(motion_stencil_pass(),
                   {{"scene.depth", image(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, 4, 4, depth_bytes)}}, 4,
                   4, {{"radius", 17.0}}),
               GraphError);
}

TEST(MotionStencilSkip, SkippedOnlyWhenNothingMovesAndTheCameraIsStill) {
  const PassDecl pass = motion_stencil_pass();
  SkipContext still;
  still.features = {"opaque_geometry", "sun"};
  EXPECT_EQ(pass.skip_if(still), "nothing moves and the camera is still");
  SkipContext camera = still;
  camera.camera_moved = true;
  EXPECT_EQ(pass.skip_if(camera), "");
  SkipContext moving = still;
  moving.features.insert("moving_geometry");
  EXPECT_EQ(pass.skip_if(moving), "");
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
