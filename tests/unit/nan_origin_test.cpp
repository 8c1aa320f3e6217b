// The NaN-origin search on frames built in memory: which pass a NaN or an Inf was born in, that
// passes reading it and writing it on (into the resource they read or a fresh one) are not
// named, a birth in frame 1 after a clean frame 0, a version from outside the searched frames,
// and the outputs that can hold one besides float colour: float depth (with a stencil plane
// beside it) and the float fields of a buffer's schema. The NaNs are placed by hand, so where
// they are is known without the search.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include "inspect/nan_origin.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

// Versions in memory by hash, counting how often each is loaded.
struct Blobs {
  std::map<std::string, std::vector<uint8_t>> bytes;
  std::map<std::string, int> loads;

  LoadVersion loader() {
    return [this](const ResourceRecord& r) {
      ++loads[r.hash];
      return bytes.at(r.hash);
    };
  }

  ResourceRecord image(const std::string& resource, const std::string& hash, VkFormat format, ImageExtent extent,
                       std::vector<uint8_t> raw) {
    ResourceRecord r;
    r.resource = resource;
    r.kind = kinds::hdr_colour;
    r.is_buffer = false;
    r.format = format;
    r.extent = extent;
    r.hash = hash;
    EXPECT_EQ(raw.size(), raw_image_bytes(*format_info(format), extent)) << resource;
    bytes[hash] = std::move(raw);
    return r;
  }

  // A 4x1 R32_SFLOAT image.
  ResourceRecord floats(const std::string& resource, const std::string& hash, std::vector<float> texels) {
    return image(resource, hash, VK_FORMAT_R32_SFLOAT, {4, 1, 1, 1, 1}, raw_of(texels));
  }

  template <typename T>
  static std::vector<uint8_t> raw_of(const std::vector<T>& values) {
    std::vector<uint8_t> raw(values.size() * sizeof(T));
    std::memcpy(raw.data(), values.data(), raw.size());
    return raw;
  }
};

PassRecord pass(const std::string& name, std::vector<ResourceRecord> inputs, std::vector<ResourceRecord> outputs) {
  PassRecord p;
  p.name = name;
  p.ran = true;
  p.inputs = std::move(inputs);
  p.outputs = std::move(outputs);
  return p;
}

FrameRecord frame(uint32_t index, std::vector<PassRecord> passes) {
  FrameRecord f;
  f.index = index;
  f.width = 4;
  f.height = 1;
  f.passes = std::move(passes);
  return f;
}

std::vector<std::string> names(const std::vector<NanOrigin>& origins, const std::vector<FrameRecord>& frames) {
  std::vector<std::string> found;
  for (const NanOrigin& o : origins)
    found.push_back(std::string(o.how == NanOrigin::How::born ? "born " : "came in ") + "frame " +
                    std::to_string(frames[o.frame_position].index) + " " +
                    frames[o.frame_position].passes[o.pass_index].name);
  return found;
}

// A writes a NaN into R. B reads R and modifies it in place: the NaN stays and a blur spreads it
// to texel 2. C reads R and writes S fresh with the NaN in it. D reads only the finite T and
// writes an Inf into U: a second, independent birth. A search that counted every fresh output
// holding a NaN would name C; one that compared an output only with the version it started from
// would name B for texel 2; one that stopped at any NaN would name B and C.
TEST(NanOriginSearch, PassesThatCarryANanOnAreNotItsOrigin) {
  Blobs blobs;
  const ResourceRecord t = blobs.floats("T", "t", {1, 2, 3, 4});
  const ResourceRecord r_by_a = blobs.floats("R", "r1", {0, kNan, 0, 0});
  const ResourceRecord r_by_b = blobs.floats("R", "r2", {0, kNan, kNan, 5});
  const ResourceRecord s_by_c = blobs.floats("S", "s", {kNan, 1, 1, 1});
  const ResourceRecord u_by_d = blobs.floats("U", "u", {0, 0, 0, -kInf});
  const std::vector<FrameRecord> frames = {frame(0, {pass("A", {t}, {r_by_a}), pass("B", {r_by_a}, {r_by_b}),
                                                     pass("C", {t, r_by_b}, {s_by_c}), pass("D", {t}, {u_by_d})})};

  const std::vector<NanOrigin> origins = find_nan_origins(frames, std::nullopt, blobs.loader(), 8);
  ASSERT_EQ(names(origins, frames), (std::vector<std::string>{"born frame 0 A", "born frame 0 D"}));
  ASSERT_EQ(origins[0].resources.size(), 1u);
  const NonFiniteValues& r = origins[0].resources[0];
  EXPECT_EQ(r.resource->resource, "R");
  EXPECT_EQ(r.count, 1u);
  ASSERT_EQ(r.texels.size(), 1u);
  EXPECT_EQ(r.texels[0].x, 1u);
  ASSERT_EQ(r.texels[0].values.size(), 1u);
  EXPECT_TRUE(std::isnan(r.texels[0].values[0]));
  const NonFiniteValues& u = origins[1].resources.at(0);
  EXPECT_EQ(u.resource->resource, "U");
  ASSERT_EQ(u.texels.size(), 1u);
  EXPECT_EQ(u.texels[0].x, 3u);
  EXPECT_EQ(u.texels[0].values, std::vector<double>{-double(kInf)});

  for (const auto& [hash, loads] : blobs.loads) EXPECT_EQ(loads, 1) << hash << ": loaded more than once";
}

// Frame 0 is clean; frame 1's A writes the NaN and frame 1's B reads it on. Searched one frame at
// a time, frame 0 has none and frame 1 names A.
TEST(NanOriginSearch, TheFirstNanBornInFrameOneIsNamedThere) {
  Blobs blobs;
  const ResourceRecord t = blobs.floats("T", "t", {1, 2, 3, 4});
  const ResourceRecord clean = blobs.floats("R", "clean", {1, 1, 1, 1});
  const ResourceRecord clean_s = blobs.floats("S", "clean_s", {2, 2, 2, 2});
  const ResourceRecord dirty = blobs.floats("R", "dirty", {1, 1, kInf, 1});
  const ResourceRecord dirty_s = blobs.floats("S", "dirty_s", {2, 2, kInf, 2});
  const std::vector<FrameRecord> frames = {
      frame(0, {pass("A", {t}, {clean}), pass("B", {clean}, {clean_s})}),
      frame(1, {pass("A", {t}, {dirty}), pass("B", {dirty}, {dirty_s})}),
  };
  const std::vector<NanOrigin> origins = find_nan_origins(frames, std::nullopt, blobs.loader(), 8);
  EXPECT_EQ(names(origins, frames), std::vector<std::string>{"born frame 1 A"});
  ASSERT_EQ(origins.size(), 1u);
  EXPECT_EQ(origins[0].resources.at(0).texels.at(0).x, 2u);
  EXPECT_TRUE(find_nan_origins(frames, 0, blobs.loader(), 8).empty());
  EXPECT_EQ(names(find_nan_origins(frames, 1, blobs.loader(), 8), frames), std::vector<std::string>{"born frame 1 A"});
}

// A history: frame 0's A writes H with a NaN, frame 1's B reads it and writes it on. Over both
// frames A is the one origin; frame 1 alone did not write H, so H came in at B.
TEST(NanOriginSearch, AVersionNoSearchedPassWroteCameInWhereFirstRead) {
  Blobs blobs;
  const ResourceRecord h = blobs.floats("H", "h0", {kNan, 0, 0, 0});
  const ResourceRecord h_by_b = blobs.floats("H", "h1", {kNan, 1, 1, 1});
  const ResourceRecord out = blobs.floats("O", "o", {kNan, 1, 1, 1});
  const std::vector<FrameRecord> frames = {frame(0, {pass("A", {}, {h})}),
                                           frame(1, {pass("B", {h}, {h_by_b}), pass("C", {h}, {out})})};
  EXPECT_EQ(names(find_nan_origins(frames, std::nullopt, blobs.loader(), 8), frames),
            std::vector<std::string>{"born frame 0 A"});
  const std::vector<NanOrigin> alone = find_nan_origins(frames, 1, blobs.loader(), 8);
  ASSERT_EQ(names(alone, frames), std::vector<std::string>{"came in frame 1 B"}) << "and not again at C";
  EXPECT_EQ(alone[0].resources.at(0).resource->resource, "H");
  EXPECT_EQ(alone[0].resources.at(0).count, 1u);
}

// D32_SFLOAT (a shadow map) and the depth plane of D32_SFLOAT_S8_UINT hold float depth. The
// stencil plane after it holds 0xFF tags, whose bytes read as a float would be a NaN: not read.
TEST(NanOriginSearch, FloatDepthHoldsNansTheStencilPlaneDoesNot) {
  Blobs blobs;
  const ImageExtent two_by_two{2, 2, 1, 1, 1};
  const ResourceRecord shadow = blobs.image("shadow", "shadow", VK_FORMAT_D32_SFLOAT, two_by_two,
                                            Blobs::raw_of(std::vector<float>{0.5f, 0.5f, kNan, 0.5f}));
  std::vector<uint8_t> depth_stencil = Blobs::raw_of(std::vector<float>{0.25f, 0.25f, 0.25f, kInf});
  depth_stencil.insert(depth_stencil.end(), 4, 0xFF);
  const ResourceRecord scene_depth =
      blobs.image("depth", "depth", VK_FORMAT_D32_SFLOAT_S8_UINT, two_by_two, depth_stencil);
  std::vector<uint8_t> finite_depth = Blobs::raw_of(std::vector<float>{1, 1, 1, 1});
  finite_depth.insert(finite_depth.end(), 4, 0xFF);
  const ResourceRecord clean_depth =
      blobs.image("clean", "clean", VK_FORMAT_D32_SFLOAT_S8_UINT, two_by_two, finite_depth);

  std::vector<FrameRecord> frames = {
      frame(0, {pass("tags", {}, {clean_depth}), pass("shadow", {}, {shadow}), pass("depth", {}, {scene_depth})})};
  frames[0].width = frames[0].height = 4;  // the 2x2 images are half the output
  const std::vector<NanOrigin> origins = find_nan_origins(frames, std::nullopt, blobs.loader(), 8);
  ASSERT_EQ(names(origins, frames), (std::vector<std::string>{"born frame 0 shadow", "born frame 0 depth"}));
  const NonFiniteTexel& in_shadow = origins[0].resources.at(0).texels.at(0);
  EXPECT_EQ(std::pair(in_shadow.x, in_shadow.y), std::pair(0u, 1u));
  EXPECT_EQ(std::pair(in_shadow.pixel_x, in_shadow.pixel_y), std::pair(0u, 2u));
  const NonFiniteValues& in_depth = origins[1].resources.at(0);
  EXPECT_EQ(in_depth.count, 1u) << "the stencil plane's bytes are no depth";
  const NonFiniteTexel& texel = in_depth.texels.at(0);
  EXPECT_EQ(std::pair(texel.x, texel.y), std::pair(1u, 1u));
  EXPECT_EQ(texel.values, std::vector<double>{double(kInf)}) << "one value: the depth";
}

// Half floats over mips and layers: the NaN's place is found in mip 1 of layer 1, and its other
// channels come with it. The limit caps the listing, not the count.
TEST(NanOriginSearch, ATexelIsPlacedByMipAndLayerAndTheLimitCapsTheList) {
  Blobs blobs;
  const FormatInfo half4 = *format_info(VK_FORMAT_R16G16B16A16_SFLOAT);
  const ImageExtent extent{4, 2, 1, 2, 2};
  std::vector<uint16_t> texels(raw_image_bytes(half4, extent) / 2, float_to_half(0.5f));
  // Mip 0: 8 texels a layer, two layers; mip 1 (2x1), layer 1 starts at texel 16 + 2.
  const size_t nan_texel = 16 + 2 + 1;
  texels[nan_texel * 4 + 2] = 0x7E00;
  for (size_t t : {0, 1, 2}) texels[t * 4 + 3] = 0x7C00;  // +Inf alpha in three texels of mip 0
  const ResourceRecord chain =
      blobs.image("chain", "chain", VK_FORMAT_R16G16B16A16_SFLOAT, extent, Blobs::raw_of(texels));
  const std::vector<FrameRecord> frames = {frame(0, {pass("bloom", {}, {chain})})};
  const std::vector<NanOrigin> origins = find_nan_origins(frames, std::nullopt, blobs.loader(), 3);
  ASSERT_EQ(origins.size(), 1u);
  const NonFiniteValues& found = origins[0].resources.at(0);
  EXPECT_EQ(found.count, 4u);
  ASSERT_EQ(found.texels.size(), 3u);
  for (const NonFiniteTexel& t : found.texels) EXPECT_EQ(t.mip, 0u) << "by mip first";

  const std::vector<NanOrigin> all = find_nan_origins(frames, std::nullopt, blobs.loader(), 8);
  const NonFiniteTexel& nan = all.at(0).resources.at(0).texels.at(3);
  EXPECT_EQ(nan.mip, 1u);
  EXPECT_EQ(nan.layer, 1u);
  EXPECT_EQ(std::pair(nan.x, nan.y), std::pair(1u, 0u));
  ASSERT_EQ(nan.values.size(), 4u);
  EXPECT_EQ(nan.values[0], 0.5);
  EXPECT_TRUE(std::isnan(nan.values[2]));
}

struct Particle {
  glm::vec3 position;
  uint32_t id;
  double age;
};

ResourceRecord particles(Blobs& blobs, const std::string& hash, const std::vector<Particle>& elements, bool schema) {
  ResourceRecord r;
  r.resource = "particles";
  r.hash = hash;
  r.buffer_size = elements.size() * sizeof(Particle);
  if (schema)
    r.schema = BufferSchema::of<Particle>()
                   .field("position", &Particle::position)
                   .field("id", &Particle::id)
                   .field("age", &Particle::age);
  blobs.bytes[hash] = Blobs::raw_of(elements);
  return r;
}

// The float fields of a schema hold NaNs; an integer field whose bits read as a float would be a
// NaN does not, and a buffer without a schema is not read. The reader of the buffer, whose input
// record carries no schema, finds it on the output that wrote the version.
TEST(NanOriginSearch, BufferFieldsTheirSchemaDeclaresFloatHoldNans) {
  Blobs blobs;
  const std::vector<Particle> elements = {
      {{0, 1, 2}, 0xFFFFFFFFu, 1.0}, {{0, 1, 2}, 7, 2.0}, {{0, kNan, 2}, 0x7FC00000u, -double(kInf)}};
  ResourceRecord written = particles(blobs, "p", elements, true);
  ResourceRecord read = written;
  read.schema.reset();  // inputs record no schema
  const ResourceRecord unknown = particles(blobs, "q", elements, false);
  const std::vector<FrameRecord> frames = {frame(0, {pass("opaque", {}, {unknown}), pass("simulate", {}, {written}),
                                                     pass("draw", {read}, {blobs.floats("O", "o", {kNan, 0, 0, 0})})})};

  const std::vector<NanOrigin> origins = find_nan_origins(frames, std::nullopt, blobs.loader(), 8);
  ASSERT_EQ(names(origins, frames), std::vector<std::string>{"born frame 0 simulate"}) << "draw read the NaN";
  const NonFiniteValues& found = origins[0].resources.at(0);
  EXPECT_EQ(found.count, 2u);
  ASSERT_EQ(found.fields.size(), 2u);
  EXPECT_EQ(found.fields[0].element, 2u);
  EXPECT_EQ(found.fields[0].field, "position.y");
  EXPECT_TRUE(std::isnan(found.fields[0].value));
  EXPECT_EQ(found.fields[1].element, 2u);
  EXPECT_EQ(found.fields[1].field, "age");
  EXPECT_EQ(found.fields[1].value, -double(kInf));
  EXPECT_TRUE(found.texels.empty());
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
