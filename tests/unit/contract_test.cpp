// Comparison contracts on inputs whose answer is known: each kind holds exactly up to its bound
// and fails just past it.
#include <gtest/gtest.h>

#include <cstring>

#include "inspect/metrics.h"

namespace nightcap::test {
namespace {

ResourceRecord image(VkFormat format, ResourceKind kind, uint32_t width, uint32_t height) {
  ResourceRecord r;
  r.is_buffer = false;
  r.kind = kind;
  r.format = format;
  r.extent.width = width;
  r.extent.height = height;
  return r;
}

std::vector<uint8_t> floats(std::initializer_list<float> values) {
  std::vector<uint8_t> bytes(values.size() * 4);
  std::memcpy(bytes.data(), std::data(values), bytes.size());
  return bytes;
}

TEST(Contract, FloatValuesHoldUpToAbsolutePlusRelative) {
  const ResourceRecord r = image(VK_FORMAT_R32_SFLOAT, ResourceKind::hdr_colour, 2, 1);
  const auto contract = ComparisonContract::floats(0.01, 0.1, "test");
  const auto a = floats({1.0f, 100.0f});
  // Allowed: 0.01 + 0.1·1 = 0.11 and 0.01 + 0.1·100 = 10.01.
  EXPECT_TRUE(check_contract(contract, r, a, r, floats({1.1f, 110.0f})).holds);
  EXPECT_FALSE(check_contract(contract, r, a, r, floats({1.12f, 100.0f})).holds);
  EXPECT_FALSE(check_contract(contract, r, a, r, floats({1.0f, 110.02f})).holds);
  const ContractCheck nan = check_contract(contract, r, a, r, floats({NAN, 100.0f}));
  EXPECT_FALSE(nan.holds);
  EXPECT_TRUE(std::isinf(nan.worst));
}

TEST(Contract, ExactMeansEveryByte) {
  const ResourceRecord r = image(VK_FORMAT_R32_SFLOAT, ResourceKind::hdr_colour, 2, 1);
  const ComparisonContract exact;
  EXPECT_TRUE(check_contract(exact, r, floats({1.0f, 2.0f}), r, floats({1.0f, 2.0f})).holds);
  const ContractCheck one =
      check_contract(exact, r, floats({1.0f, 2.0f}), r, floats({1.0f, std::nextafter(2.0f, 3.0f)}));
  EXPECT_FALSE(one.holds);
  EXPECT_EQ(one.worst, 1.0);
}

TEST(Contract, UnormCodesCountStepsOfTheFormat) {
  const ResourceRecord r = image(VK_FORMAT_R8G8B8A8_UNORM, ResourceKind::colour, 1, 1);
  const auto contract = ComparisonContract::codes(1, "test");
  const std::vector<uint8_t> a = {10, 20, 30, 255};
  EXPECT_TRUE(check_contract(contract, r, a, r, std::vector<uint8_t>{11, 19, 30, 255}).holds);
  const ContractCheck two = check_contract(contract, r, a, r, std::vector<uint8_t>{12, 20, 30, 255});
  EXPECT_FALSE(two.holds);
  EXPECT_NEAR(two.worst, 2.0, 1e-9);
}

TEST(Contract, SrgbCodesAreCountedBeforeDecoding) {
  const ResourceRecord r = image(VK_FORMAT_R8G8B8A8_SRGB, ResourceKind::colour, 1, 1);
  const std::vector<uint8_t> a = {200, 20, 3, 255};
  EXPECT_TRUE(
      check_contract(ComparisonContract::codes(1, "test"), r, a, r, std::vector<uint8_t>{201, 19, 4, 255}).holds);
  EXPECT_FALSE(
      check_contract(ComparisonContract::codes(1, "test"), r, a, r, std::vector<uint8_t>{200, 22, 3, 255}).holds);
}

TEST(Contract, AnglesOfNormals) {
  const ResourceRecord r = image(VK_FORMAT_A2B10G10R10_UNORM_PACK32, ResourceKind::normal, 1, 1);
  auto word = [](int x, int y, int z) {
    const uint32_t w = uint32_t(x) | uint32_t(y) << 10 | uint32_t(z) << 20;
    std::vector<uint8_t> bytes(4);
    std::memcpy(bytes.data(), &w, 4);
    return bytes;
  };
  // +Z against a normal tilted by one code in x: atan(2/1023 / 1) ≈ 0.112°.
  const auto a = word(512, 512, 1023), b = word(513, 512, 1023);
  EXPECT_TRUE(check_contract(ComparisonContract::degrees(0.2, "test"), r, a, r, b).holds);
  EXPECT_FALSE(check_contract(ComparisonContract::degrees(0.05, "test"), r, a, r, b).holds);
}

TEST(Contract, LinearDepthIsRelativeAndStencilExact) {
  const ResourceRecord r = image(VK_FORMAT_D32_SFLOAT_S8_UINT, ResourceKind::depth_stencil, 1, 1);
  auto texel = [](float depth, uint8_t stencil) {
    std::vector<uint8_t> bytes(5);
    std::memcpy(bytes.data(), &depth, 4);
    bytes[4] = stencil;
    return bytes;
  };
  const auto contract = ComparisonContract::depth(1e-3, "test");
  EXPECT_TRUE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5004f, 8)).holds);
  EXPECT_FALSE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5006f, 8)).holds);
  EXPECT_FALSE(check_contract(contract, r, texel(0.5f, 8), r, texel(0.5f, 0x0A)).holds);
}

TEST(Contract, SetsIgnoreOrderButNotContent) {
  ResourceRecord r;
  r.is_buffer = true;
  r.buffer_size = 12;
  auto words = [](uint32_t a, uint32_t b, uint32_t c) {
    std::vector<uint8_t> bytes(12);
    const uint32_t w[3] = {a, b, c};
    std::memcpy(bytes.data(), w, 12);
    return bytes;
  };
  const auto contract = ComparisonContract::unordered("test");
  EXPECT_TRUE(contract.order_dependent);
  EXPECT_TRUE(check_contract(contract, r, words(1, 2, 3), r, words(3, 1, 2)).holds);
  EXPECT_FALSE(check_contract(contract, r, words(1, 2, 3), r, words(3, 1, 1)).holds);
}

}  // namespace
}  // namespace nightcap::test
