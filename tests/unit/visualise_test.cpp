// The pictures' sRGB encoding by table (visualise.h's srgb_code) against the formula it replaces.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>
#include <random>

#include "inspect/visualise.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

uint8_t by_formula(float x) { return uint8_t(std::lround(std::clamp(double(linear_to_srgb(x)), 0.0, 1.0) * 255.0)); }

TEST(Visualise, SrgbCodeByTableIsTheFormulasCodeEverywhere) {
  // Ten million random values, every 97th float of [0, 1] (11 million, denser where sRGB is
  // steepest, near 0), and the ends.
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 10'000'000; ++i) {
    const float x = unit(random);
    ASSERT_EQ(srgb_code(x), by_formula(x)) << x;
  }
  for (uint32_t bits = 0; bits <= std::bit_cast<uint32_t>(1.0f); bits += 97) {
    const float x = std::bit_cast<float>(bits);
    ASSERT_EQ(srgb_code(x), by_formula(x)) << x;
  }
  EXPECT_EQ(srgb_code(0.0f), 0);
  EXPECT_EQ(srgb_code(1.0f), 255);
  EXPECT_EQ(srgb_code(0.5f), 188);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
