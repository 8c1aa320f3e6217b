// The debugger's decoding and statistics on images built here, whose answers are known by
// construction: NaN, Inf and half denormals counted, stencil tags named (in a depth-stencil and
// in a stencil-kind image such as stencil.half), motion.mask's bits, output pixels mapped to
// half-resolution mips.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "inspect/decode.h"
#include "inspect/stats.h"
#include "inspect/visualise.h"
#include "passes/depth/kinds.h"
#include "passes/scene/stencil_tags.h"
#include "tests/unit/image_record.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

TEST(InspectStats, CountsNanInfAndStoredHalfDenormals) {
  // One channel's halves across 6 texels: 1, NaN, +Inf, -Inf, the smallest denormal, -2.
  const uint16_t halves[6] = {0x3c00, 0x7e00, 0x7c00, 0xfc00, 0x0001, 0xc000};
  const ResourceRecord r = image_record(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, 6, 1, 1, "hdr");
  std::vector<uint8_t> raw(6 * 8, 0);
  for (int i = 0; i < 6; ++i) std::memcpy(raw.data() + 8 * i, &halves[i], 2);
  const std::vector<ChannelStats> stats = image_stats(r, raw, {}, {0, 0, 6, 1});
  ASSERT_EQ(stats.size(), 4u);
  const ChannelStats& red = stats[0];
  EXPECT_EQ(red.nan, 1u);
  EXPECT_EQ(red.inf, 2u);
  EXPECT_EQ(red.denormal, 1u);
  EXPECT_EQ(red.finite, 3u);
  EXPECT_EQ(red.min, -2.0);
  EXPECT_EQ(red.max, 1.0);
  EXPECT_DOUBLE_EQ(red.mean, (1.0 - 2.0 + std::ldexp(1.0, -24)) / 3.0);
  EXPECT_EQ(red.histogram.front(), 1u);  // -2
  EXPECT_EQ(red.histogram.back(), 1u);   // 1
  // Green is all zero: finite, one bin, no denormal (zero is not one).
  EXPECT_EQ(stats[1].finite, 6u);
  EXPECT_EQ(stats[1].denormal, 0u);
  EXPECT_EQ(stats[1].histogram[0], 6u);
}

TEST(InspectDecode, StencilClassesAndFlags) {
  const std::pair<uint32_t, const char*> classes[] = {{0x00, "plain"},   {0x08, "road"},    {0x15, "body"},
                                                      {0x35, "face"},    {0x40, "vehicle"}, {0x95, "hair"},
                                                      {0xA0, "foliage"}, {0x11, "unknown"}};
  for (const auto& [tag, name] : classes) {
    EXPECT_EQ(stencil_class_name(tag), name) << tag;
    EXPECT_EQ(stencil_class_name(tag | 0x02), name) << tag;
    EXPECT_TRUE(stencil_flags(tag).empty()) << tag;
    EXPECT_EQ(stencil_flags(tag | 0x02), std::vector<std::string>{"moving"}) << tag;
  }
}

TEST(InspectDecode, DepthStencilTexelInMetresAndClass) {
  const ResourceRecord r = image_record(VK_FORMAT_D32_SFLOAT_S8_UINT, kinds::depth_stencil, 2, 1, 1, "scene.depth");
  const float depths[2] = {0.0f, 0.004f};
  std::vector<uint8_t> raw(2 * 4 + 2);
  std::memcpy(raw.data(), depths, 8);
  raw[8] = 0x00;
  raw[9] = 0x97;  // hair, moving
  FrameRecord frame;
  frame.width = 2;
  frame.height = 1;
  frame.camera.znear = 0.1;
  const PixelReading sky = read_pixel(r, raw, frame, {0, 0, 0, 0});
  EXPECT_TRUE(sky.decoded["linear_m"].is_string());
  EXPECT_EQ(sky.decoded["class"], "plain");
  const PixelReading hit = read_pixel(r, raw, frame, {1, 0, 0, 0});
  EXPECT_DOUBLE_EQ(hit.decoded["linear_m"].get<double>(), 0.1 / double(0.004f));
  EXPECT_EQ(hit.decoded["stencil"], 0x97);
  EXPECT_EQ(hit.decoded["class"], "hair");
  EXPECT_EQ(hit.decoded["flags"], nlohmann::ordered_json::array({"moving"}));
}

TEST(InspectDecode, HalfResolutionStencilByClassAndTheMotionMask) {
  FrameRecord frame;
  frame.width = 5;
  frame.height = 1;
  // stencil.half of a 5-wide output: 3 texels, foliage, vehicle moving, an unknown tag.
  const ResourceRecord half = image_record(VK_FORMAT_R8_UINT, kinds::stencil, 3, 1, 1, "stencil.half");
  const std::vector<uint8_t> tags = {0xA0, 0x42, 0x11};
  const PixelReading foliage = read_pixel(half, tags, frame, {0, 0, 0, 0});
  EXPECT_EQ(foliage.decoded["stencil"], 0xA0);
  EXPECT_EQ(foliage.decoded["class"], "foliage");
  EXPECT_TRUE(foliage.decoded["flags"].empty());
  const PixelReading vehicle = read_pixel(half, tags, frame, {1, 0, 0, 0});
  EXPECT_EQ(vehicle.decoded["class"], "vehicle");
  EXPECT_EQ(vehicle.decoded["flags"], nlohmann::ordered_json::array({"moving"}));
  EXPECT_EQ(read_pixel(half, tags, frame, {2, 0, 0, 0}).decoded["class"], "unknown");
  const Rgba8Image palette = visualise(half, tags, frame, {}, VisualAspect::depth_or_colour);
  for (size_t i = 0; i < tags.size(); ++i) {
    const auto expected = stencil_colour(tags[i]);
    EXPECT_TRUE(std::equal(expected.begin(), expected.end(), palette.pixels.begin() + 4 * i)) << i;
  }

  const ResourceRecord mask = image_record(VK_FORMAT_R8_UINT, kinds::mask, 5, 1, 1, "motion.mask");
  const std::vector<uint8_t> bits = {0, 1, 1, 0, 0};
  EXPECT_EQ(read_pixel(mask, bits, frame, {0, 0, 0, 0}).decoded["masked"], false);
  EXPECT_EQ(read_pixel(mask, bits, frame, {1, 0, 0, 0}).decoded["masked"], true);
  const Rgba8Image shown = visualise(mask, bits, frame, {}, VisualAspect::depth_or_colour);
  for (size_t i = 0; i < bits.size(); ++i) EXPECT_EQ(shown.pixels[4 * i], bits[i] ? 255 : 0) << i;
}

TEST(InspectDecode, OutputPixelsMapToHalfResolutionMips) {
  FrameRecord frame;
  frame.width = 1280;
  frame.height = 720;
  const ResourceRecord half = image_record(VK_FORMAT_R16G16B16A16_SFLOAT, kinds::hdr_colour, 640, 360, 6, "chain");
  const TexelAddress mip2 = texel_for_output_pixel(half, frame, 1279, 719, {2, 0, 0});
  EXPECT_EQ(mip2.x, 159u);  // mip 2 of 640x360 is 160x90
  EXPECT_EQ(mip2.y, 89u);
  const TexelAddress centre = texel_for_output_pixel(half, frame, 640, 360, {});
  EXPECT_EQ(centre.x, 320u);
  EXPECT_EQ(centre.y, 180u);
  EXPECT_THROW(texel_for_output_pixel(half, frame, 1280, 0, {}), InspectError);
  EXPECT_THROW(texel_for_output_pixel(half, frame, 0, 0, {6, 0, 0}), InspectError);
  EXPECT_THROW(texel_for_output_pixel(half, frame, 0, 0, {0, 1, 0}), InspectError);
  EXPECT_THROW(texel_for_output_pixel(half, frame, 0, 0, {0, 0, 1}), InspectError) << "a 2D image has slice 0 only";
}

// A 16x8x4 R32_SFLOAT volume with 2 mips whose texel (x, y, z) of mip m holds 1000m + 100z + 10y + x:
// each slice is read where the raw layout puts it (mip, then z, then rows).
TEST(InspectDecode, SlicesOfA3DImage) {
  ResourceRecord volume = image_record(VK_FORMAT_R32_SFLOAT, kinds::buffer, 16, 8, 2, "froxels");
  volume.extent.depth = 4;
  std::vector<uint8_t> raw;
  for (uint32_t m = 0; m < 2; ++m)
    for (uint32_t z = 0; z < (4u >> m); ++z)
      for (uint32_t y = 0; y < (8u >> m); ++y)
        for (uint32_t x = 0; x < (16u >> m); ++x) {
          const float v = float(1000 * m + 100 * z + 10 * y + x);
          const auto* bytes = reinterpret_cast<const uint8_t*>(&v);
          raw.insert(raw.end(), bytes, bytes + 4);
        }
  FrameRecord frame;
  frame.width = 16;
  frame.height = 8;
  const TexelAddress texel = texel_for_output_pixel(volume, frame, 5, 3, {0, 0, 2});
  EXPECT_EQ(texel.slice, 2u);
  EXPECT_EQ(read_texel(volume, raw, texel).raw, std::vector<double>{235});
  EXPECT_EQ(read_texel(volume, raw, texel_for_output_pixel(volume, frame, 5, 3, {1, 0, 1})).raw,
            std::vector<double>{1000 + 100 + 10 * 1 + 2});
  EXPECT_THROW(texel_for_output_pixel(volume, frame, 0, 0, {1, 0, 2}), InspectError) << "mip 1 has 2 slices";
  const std::vector<ChannelStats> stats = image_stats(volume, raw, {0, 0, 3}, {0, 0, 16, 8});
  EXPECT_EQ(stats.at(0).min, 300);
  EXPECT_EQ(stats.at(0).max, 385);  // 300 + 10·7 + 15
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
