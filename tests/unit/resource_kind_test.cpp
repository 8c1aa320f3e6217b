// Resource kinds are data: every kind the frame writes is registered by the code that owns it,
// names round-trip as captures store them, and a kind registered here (as a new pass would
// register one) is decoded by `inspect`, drawn by `export`, measured by `diff` and compressed by
// the capture as its registration says, with no edit to captures/, compare/ or inspect/.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "captures/codec_choice.h"
#include "compare/metrics.h"
#include "inspect/decode.h"
#include "inspect/visualise.h"
#include "passes/assembly/frame_passes.h"
#include "passes/sky/kinds.h"
#include "tests/unit/image_record.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

TEST(ResourceKinds, EveryKindTheFramesPassesDeclareIsRegistered) {
  std::set<std::string> seen;
  for (const PassDecl& pass : all_passes())
    for (const ResourceUse& use : pass.outputs) {
      const ResourceKind kind = use.is_buffer ? use.buffer.kind : use.image.kind;
      seen.insert(std::string(kind.name()));
      EXPECT_TRUE(kind_by_name(kind.name()))
          << pass.name << " writes " << use.resource << " as '" << kind.name() << "', which no code registers";
    }
  // The G-buffer's, the depth stage's, the light lists' and the shadow maps' own kinds among them.
  for (const char* owned : {"normal", "material", "motion", "packed_normal", "depth_stencil", "stencil", "depth_minmax",
                            "light_clusters", "light_depth"})
    EXPECT_TRUE(seen.count(owned)) << owned;
}

TEST(ResourceKinds, NamesRoundTripAndOnlyRegisteredNamesAreKinds) {
  for (const ResourceKind kind : registered_kinds()) {
    const std::optional<ResourceKind> found = kind_by_name(std::string(kind.name()));
    ASSERT_TRUE(found) << kind.name();
    EXPECT_EQ(*found, kind);
    EXPECT_EQ(kind_info(kind).kind, kind);
  }
  EXPECT_FALSE(kind_by_name("colour "));
  EXPECT_FALSE(kind_by_name(""));
  EXPECT_THROW(kind_info(ResourceKind("test_never_registered")), std::logic_error);
}

TEST(ResourceKinds, ANameIsRegisteredOnce) {
  EXPECT_THROW(register_kind({.kind = kinds::colour}), std::logic_error);
  EXPECT_THROW(register_kind({.kind = ResourceKind("")}), std::logic_error);
}

// A kind as a later pass would add one: 0.5n + 0.5 of a unit vector in RGBA32F, described, drawn
// as light and measured by angle.
constexpr ResourceKind kTestHemisphere{"test_hemisphere"};
const KindRegistration kHemisphere({
    .kind = kTestHemisphere,
    .describe =
        [](const TexelValues& t, const KindFrame& frame, nlohmann::ordered_json& out) {
          out["x"] = t.raw[0] * 2 - 1;
          out["output_width"] = frame.output_width;
        },
    .draw =
        [](const TexelValues& t, const KindFrame&) {
          return TexelPicture{TexelPicture::Scale::light, {t.raw[0], t.raw[1], 0.25}};
        },
    .light = true,
    .measure = KindMeasure::unit_vector,
    .compression = {KindCompression::Method::wavelet, 1},
});

// A table of any range (the sky's LUTs) is drawn relative to its largest channel.
TEST(ResourceKinds, ASkyLutIsDrawnRelativeToItsLargestValue) {
  const ResourceRecord record = image_record(VK_FORMAT_R32G32B32A32_SFLOAT, kinds::sky_lut, 2, 1, 1, "sky.view");
  const std::vector<uint8_t> raw = floats({400.0f, 100.0f, 0.0f, 1.0f, 800.0f, 200.0f, 50.0f, 1.0f});
  const Rgba8Image picture = visualise(record, raw, FrameRecord{}, {}, VisualAspect::depth_or_colour);
  EXPECT_EQ(picture.pixels[0], srgb_code(0.5f));
  EXPECT_EQ(picture.pixels[1], srgb_code(0.125f));
  EXPECT_EQ(picture.pixels[2], srgb_code(0.0f));
  EXPECT_EQ(picture.pixels[4], srgb_code(1.0f));
  EXPECT_EQ(picture.pixels[6], srgb_code(0.0625f));
}

TEST(ResourceKinds, ANewKindIsDecodedDrawnMeasuredAndCompressedAsItsRegistrationSays) {
  const ResourceRecord record =
      image_record(VK_FORMAT_R32G32B32A32_SFLOAT, kTestHemisphere, 2, 1, 1, "test.hemisphere");
  const std::vector<uint8_t> raw = floats({0.5f, 0.5f, 1.0f, 1.0f, 0.0f, 0.5f, 0.5f, 1.0f});
  FrameRecord frame;
  frame.width = 640;
  frame.height = 1;

  const PixelReading reading = read_pixel(record, raw, frame, {0, 0, 0, 0});
  EXPECT_EQ(reading.decoded["x"], 0.0);
  EXPECT_EQ(reading.decoded["output_width"], 640);

  const Rgba8Image picture = visualise(record, raw, frame, {}, VisualAspect::depth_or_colour);
  EXPECT_EQ(picture.pixels[0], srgb_code(0.5f));
  EXPECT_EQ(picture.pixels[1], srgb_code(0.5f));
  EXPECT_EQ(picture.pixels[2], srgb_code(0.25f));
  EXPECT_EQ(picture.pixels[4], srgb_code(0.0f));

  std::vector<uint8_t> turned = raw;
  // The first texel's (0, 0, 1) turned by 0.1 rad about y.
  const float turned_xz[2] = {0.5f + 0.5f * float(std::sin(0.1)), 0.5f + 0.5f * float(std::cos(0.1))};
  std::memcpy(turned.data(), &turned_xz[0], 4);
  std::memcpy(turned.data() + 8, &turned_xz[1], 4);
  const ResourceComparison comparison = compare_resource(record, raw, record, turned);
  EXPECT_EQ(comparison.metric, "angle");
  EXPECT_NEAR(comparison.angular_max_deg, 0.1 * 180 / M_PI, 1e-4);

  EXPECT_EQ(image_encoding_for(kTestHemisphere, *format_info(VK_FORMAT_R32G32B32A32_SFLOAT)).compression,
            ExrCompression::piz);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
