// Buffers decoded by their declared schema: the schema matches the struct it describes, survives
// the manifest, and diff/replay compare by it — the first differing element and field named,
// floats held to the contract's bound, integers and padding exactly.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <cstring>

#include "captures/capture.h"
#include "compare/metrics.h"
#include "passes/frame/gpu_types.h"

namespace nightcap {
namespace {
namespace NIGHTCAP_FILE_ID {

const SchemaField& field_named(const BufferSchema& schema, const std::string& name) {
  for (const SchemaField& f : schema.fields)
    if (f.name == name) return f;
  throw std::runtime_error("no field " + name);
}

TEST(BufferSchema, OffsetsAndTypesComeFromTheStruct) {
  const BufferSchema draws = draw_schema();
  EXPECT_EQ(draws.stride, sizeof(GpuDraw));
  EXPECT_EQ(field_named(draws, "normal_matrix").offset, offsetof(GpuDraw, normal_matrix));
  EXPECT_EQ(field_named(draws, "material").offset, offsetof(GpuDraw, material));
  EXPECT_EQ(field_named(draws, "mirrored").offset, offsetof(GpuDraw, mirrored));
  EXPECT_EQ(type_name(field_named(draws, "model")), "mat4");
  EXPECT_EQ(type_name(field_named(draws, "vertex_offset")), "i32");
  EXPECT_EQ(type_name(field_named(draws, "stencil")), "u32");
  const BufferSchema constants = frame_constants_schema();
  EXPECT_EQ(constants.stride, sizeof(GpuFrameConstants));
  EXPECT_EQ(type_name(field_named(constants, "sun_direction")), "vec4");
  const BufferSchema views = view_schema();
  EXPECT_EQ(views.stride, sizeof(GpuView));
  EXPECT_EQ(field_named(views, "viewport").offset, offsetof(GpuView, viewport));
  EXPECT_EQ(field_named(draws, "view").offset, offsetof(GpuDraw, view));
  EXPECT_EQ(type_name(field_named(constants, "counts")), "uvec4");
  EXPECT_EQ(field_named(constants, "counts").offset, offsetof(GpuFrameConstants, counts));
  EXPECT_EQ(light_schema().stride, sizeof(GpuLight));
  // A schema generated from a struct's field list (gpu_layout.glsl.h) names every member in
  // order but the padding.
  for (const auto& [schema, padding] : {std::pair{draws, 0u}, std::pair{constants, 0u}, std::pair{views, 0u},
                                        std::pair{light_schema(), 0u}, std::pair{decal_schema(), 0u}}) {
    uint32_t end = 0, bytes = 0;
    for (const SchemaField& f : schema.fields) {
      EXPECT_GE(f.offset, end) << f.name;
      end = f.offset + f.bytes();
      bytes += f.bytes();
    }
    EXPECT_EQ(bytes + padding, schema.stride);
  }
  // Fields of a struct of another size are refused rather than given wrong offsets.
  EXPECT_THROW(BufferSchema::of<GpuLight>().field("model", &GpuDraw::model), std::logic_error);
}

TEST(BufferSchema, JsonRoundTripsAndRejectsWhatItCannotRead) {
  struct Record {
    double world[16];
    glm::ivec2 cell;
    float weight;
    uint32_t pad;
  };
  const BufferSchema schema = BufferSchema::of<Record>()
                                  .field("world", &Record::world)
                                  .field("cell", &Record::cell)
                                  .field("weight", &Record::weight);
  const nlohmann::json j = to_json(schema);
  EXPECT_EQ(j.at("fields")[0].at("type"), "f64[16]");
  EXPECT_EQ(j.at("fields")[1].at("type"), "ivec2");
  const BufferSchema back = schema_from_json(j);
  EXPECT_EQ(to_json(back), j);
  ASSERT_EQ(back.fields.size(), 3u);
  EXPECT_EQ(back.fields[0].scalar, Scalar::f64);
  EXPECT_EQ(back.fields[0].count, 16u);

  nlohmann::json unknown = j;
  unknown["fields"][2]["type"] = "quaternion";
  EXPECT_THROW(schema_from_json(unknown), std::invalid_argument);
  nlohmann::json past = j;
  past["fields"][2]["offset"] = sizeof(Record) - 2;
  EXPECT_THROW(schema_from_json(past), std::invalid_argument);
  EXPECT_THROW(schema_from_json(nlohmann::json{{"stride", 0}, {"fields", nlohmann::json::array()}}),
               std::invalid_argument);
}

TEST(BufferSchema, EveryTypeNameReadsBackAndNoOther) {
  for (Scalar s : {Scalar::u32, Scalar::i32, Scalar::f32, Scalar::f64})
    for (uint32_t count = 1; count <= 1024; ++count) {
      const std::string name = type_name({"", s, count, 0});
      SchemaField read;
      ASSERT_TRUE(read_type(name, read)) << name;
      EXPECT_EQ(read.scalar, s) << name;
      EXPECT_EQ(read.count, count) << name;
    }
  SchemaField read;
  for (const char* other : {"", "f32[3]", "f32[016]", "f32[1025]", "f64[0]", "f32[]", "u32[4x]", "u32[+5]", "vec5",
                            "vec1", "dvec3", "ivec", "mat3", "f16", "u32 ", "f64[16]]"})
    EXPECT_FALSE(read_type(other, read)) << other;
}

class DrawListComparison : public ::testing::Test {
 protected:
  void SetUp() override {
    record.resource = "draws.test";
    record.kind = kinds::draw_list;
    record.is_buffer = true;
    record.schema = draw_schema();
    std::vector<GpuDraw> draws(3);
    for (uint32_t i = 0; i < draws.size(); ++i) {
      draws[i].model = glm::mat4(float(i + 1));
      draws[i].model[3] = glm::vec4(100.0f * i, 2.0f, -3.0f, 1.0f);
      draws[i].material = i;
      draws[i].index_count = 36;
    }
    a.resize(draws.size() * sizeof(GpuDraw));
    std::memcpy(a.data(), draws.data(), a.size());
    record.buffer_size = a.size();
    b = a;
  }
  template <typename T>
  void set(uint32_t element, size_t offset, T value) {
    std::memcpy(b.data() + element * sizeof(GpuDraw) + offset, &value, sizeof value);
  }
  ResourceRecord record;
  std::vector<uint8_t> a, b;
};

TEST_F(DrawListComparison, NamesTheFirstDifferingElementAndField) {
  set(1, offsetof(GpuDraw, model) + 13 * 4, 2.5f);  // model[3].y: 2 → 2.5
  set(2, offsetof(GpuDraw, material), 9u);
  const ResourceComparison c = compare_resource(record, a, record, b);
  EXPECT_EQ(c.metric, "buffer fields");
  EXPECT_EQ(c.differing, 2u);  // elements, not words
  EXPECT_EQ(c.first_difference, "element 1 model[13]: 2 vs 2.5");
  EXPECT_DOUBLE_EQ(c.max_abs, 7.0);  // material 2 → 9
  EXPECT_DOUBLE_EQ(c.over_threshold_share, 2.0 / 3.0);
}

TEST_F(DrawListComparison, FloatsHoldToTheContractIntegersAndPaddingExactly) {
  const auto contract = ComparisonContract::floats(0.0, 1e-3, "test");
  set(2, offsetof(GpuDraw, model) + 12 * 4, 200.1f);  // model[3].x 200 → 200.1: 0.5 of the bound
  ContractCheck check = check_contract(contract, record, a, record, b);
  EXPECT_TRUE(check.holds);
  EXPECT_NEAR(check.worst, 0.1 / 0.2, 1e-4);
  set(2, offsetof(GpuDraw, model) + 12 * 4, 200.3f);  // 1.5 of the bound
  EXPECT_FALSE(check_contract(contract, record, a, record, b).holds);

  set(2, offsetof(GpuDraw, model) + 12 * 4, 200.0f);
  set(0, offsetof(GpuDraw, instance), 1u);  // an integer field moved by one
  check = check_contract(contract, record, a, record, b);
  EXPECT_FALSE(check.holds);
  EXPECT_TRUE(std::isinf(check.worst));

  set(0, offsetof(GpuDraw, instance), 0u);
  // Bytes no field covers (padding) are still compared: the schema without `view` leaves a gap.
  std::erase_if(record.schema->fields, [](const SchemaField& f) { return f.name == "view"; });
  set(0, offsetof(GpuDraw, view), 5u);
  EXPECT_FALSE(check_contract(contract, record, a, record, b).holds);
  EXPECT_EQ(compare_resource(record, a, record, b).first_difference, "element 0 byte 220 outside the fields: 0 vs 5");
}

TEST_F(DrawListComparison, NanInBothIsAgreement) {
  set(1, offsetof(GpuDraw, model), NAN);
  a = b;
  set(1, offsetof(GpuDraw, model), -NAN);  // another NaN bit pattern
  const ResourceComparison c = compare_resource(record, a, record, b);
  EXPECT_EQ(c.differing, 0u);
  EXPECT_TRUE(c.first_difference.empty());
  EXPECT_EQ(c.nan_a, 1u);
  EXPECT_TRUE(check_contract(ComparisonContract::floats(0.0, 1e-6, "test"), record, a, record, b).holds);
}

TEST(BufferSchema, TheManifestRecordsItWithTheOutput) {
  CaptureManifest m;
  m.device = m.settings = m.scene = nlohmann::json::object();
  FrameRecord frame;
  frame.width = frame.height = 4;
  PassRecord pass;
  pass.name = "cull.main";
  pass.ran = true;
  ResourceRecord out;
  out.resource = "draws.gbuffer.opaque";
  out.kind = kinds::draw_list;
  out.buffer_size = 2 * sizeof(GpuDraw);
  out.hash = std::string(32, 'a');
  out.blob = "blobs/" + out.hash + ".zst";
  out.schema = draw_schema();
  pass.outputs.push_back(out);
  out.resource = "draws.depth.prepass";
  out.schema.reset();
  pass.outputs.push_back(out);
  frame.passes.push_back(pass);
  m.frames.push_back(frame);
  const nlohmann::json j = to_json(m);
  const nlohmann::json& recorded = j.at("frames")[0].at("passes")[0].at("outputs");
  EXPECT_EQ(recorded[0].at("schema"), to_json(draw_schema()));
  EXPECT_FALSE(recorded[1].contains("schema"));
  const CaptureManifest back = manifest_from_json(j, "manifest.json");
  const auto& outputs = back.frames.at(0).passes.at(0).outputs;
  ASSERT_TRUE(outputs.at(0).schema);
  EXPECT_EQ(to_json(*outputs.at(0).schema), to_json(draw_schema()));
  EXPECT_FALSE(outputs.at(1).schema);

  nlohmann::json bad = j;
  bad["frames"][0]["passes"][0]["outputs"][0]["schema"]["fields"][0]["type"] = "vec9";
  try {
    manifest_from_json(bad, "manifest.json");
    FAIL() << "an unknown field type was read";
  } catch (const CaptureError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown type 'vec9'"), std::string::npos) << e.what();
  }
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap
