// scene.geometry's compact vertex streams (vertex_streams.h) against the float vertices they
// encode, on the CPU and decoded on the GPU by vertex_streams.glsl, the decode every pass that
// pulls vertices runs. Angles are atan2(|a×b|, a·b) in double.
//
// Stated bounds:
// - position, per axis: |decoded − p| ≤ step/2 + 2⁻²²·(extent + max(|min|, |max|)), step =
//   extent/65535 of the primitive's box. Half a step is the rounding to the grid; the second
//   term is float: the step itself is rounded (so 65535 steps may miss the box's end by ~2⁻²⁴ of
//   the extent) and the decode origin + step·q rounds twice. The GPU decode equals the CPU's bit
//   for bit (Vulkan rounds float add and multiply correctly; `precise` forbids fusing them).
// - normal (octahedral snorm 16:16, the best of the four surrounding codes): ≤ 0.0025° max,
//   ≤ 0.00125° mean over 2²⁰ Fibonacci directions plus the axes and octant diagonals; tangent
//   (16:15): ≤ 0.0043° max, ≤ 0.0019° mean. (Measured: 0.00248° / 0.00122° and 0.00427° /
//   0.00185°; the bounds are these plus ~1-3%, as the grid's worst case is not known in closed
//   form.) Next to gbuffer.normal's own 10:10:10 floor (0.097° max, 0.043° mean) that is under
//   3%. The handedness survives exactly; a zero or non-finite direction decodes to exactly
//   (0, 0, 0) (w 0 for tangents), which the G-buffer pass replaces with the face normal. The
//   GPU's float normalisation may add 2·10⁻⁵° to the bound.
// - UV (half): |decoded − uv| ≤ 2⁻¹¹·|uv| above 2⁻¹⁴, ≤ 2⁻²⁵ below (half an ULP), up to 65504.
// - colour (RGBA8 unorm): ≤ 0.5/255 + 2⁻²⁴ per component for colours in [0, 1].
#include <cmath>
#include <cstring>
#include <random>

#include "passes/core/shader.h"
#include "passes/frame/vertex_streams.h"
#include "tests/unit/gpu_fixture.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

double angle_degrees(const glm::dvec3& a, const glm::dvec3& b) {
  return glm::degrees(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
}

// n directions of a Fibonacci sphere, then the 6 axes and the 8 octant diagonals.
std::vector<glm::dvec3> directions(uint32_t n) {
  std::vector<glm::dvec3> out;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (uint32_t i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n, r = std::sqrt(1.0 - z * z), phi = golden * i;
    out.emplace_back(r * std::cos(phi), r * std::sin(phi), z);
  }
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      glm::dvec3 a(0.0);
      a[axis] = sign;
      out.push_back(a);
    }
  for (int octant = 0; octant < 8; ++octant)
    out.push_back(glm::normalize(glm::dvec3(octant & 1 ? -1 : 1, octant & 2 ? -1 : 1, octant & 4 ? -1 : 1)));
  return out;
}

constexpr double kNormalMax = 0.0025, kNormalMean = 0.00125, kTangentMax = 0.0043, kTangentMean = 0.0019;
constexpr double kGpuNormalise = 2e-5;

double position_bound(float lo, float hi) {
  const double extent = double(hi) - lo;
  return extent / 65535.0 / 2.0 + std::ldexp(extent + std::max(std::abs(lo), std::abs(hi)), -22);
}

double uv_bound(float uv) { return std::max(std::ldexp(std::abs(double(uv)), -11), std::ldexp(1.0, -25)); }

constexpr double kColorBound = 0.5 / 255.0 + 0x1p-24;

TEST(VertexStreams, DirectionsWithinTheirBounds) {
  double worst[2] = {0, 0}, sum[2] = {0, 0};
  const std::vector<glm::dvec3> dirs = directions(1u << 20);
  for (const glm::dvec3& d : dirs) {
    const glm::vec3 n(d);
    const double e_n = angle_degrees(glm::dvec3(decode_normal(encode_normal(n))), d);
    const glm::vec4 t = decode_tangent(encode_tangent(glm::vec4(n, -1.0f)));
    const double e_t = angle_degrees(glm::dvec3(t), d);
    ASSERT_EQ(t.w, -1.0f);
    EXPECT_EQ(decode_tangent(encode_tangent(glm::vec4(n, 1.0f))).w, 1.0f);
    worst[0] = std::max(worst[0], e_n);
    worst[1] = std::max(worst[1], e_t);
    sum[0] += e_n;
    sum[1] += e_t;
  }
  std::printf("normal 16:16: max %.5f° mean %.5f°; tangent 16:15: max %.5f° mean %.5f° (%zu directions)\n", worst[0],
              sum[0] / dirs.size(), worst[1], sum[1] / dirs.size(), dirs.size());
  EXPECT_LE(worst[0], kNormalMax);
  EXPECT_LE(sum[0] / dirs.size(), kNormalMean);
  EXPECT_LE(worst[1], kTangentMax);
  EXPECT_LE(sum[1] / dirs.size(), kTangentMean);
}

TEST(VertexStreams, DirectionsOfAnyLengthKeepTheirWayAndZeroStaysZero) {
  const glm::vec3 d = glm::normalize(glm::vec3(0.3f, -0.8f, 0.52f));
  for (float length : {1e-30f, 1e-3f, 1.0f, 1e3f, 1e30f})
    EXPECT_LE(angle_degrees(glm::dvec3(decode_normal(encode_normal(d * length))), glm::dvec3(d)), kNormalMax);
  const float nan = std::nanf(""), inf = INFINITY;
  for (const glm::vec3& bad : {glm::vec3(0.0f), glm::vec3(-0.0f), glm::vec3(nan, 0, 1), glm::vec3(inf, 0, 0)}) {
    EXPECT_EQ(encode_normal(bad), kNoDirection);
    EXPECT_EQ(decode_normal(encode_normal(bad)), glm::vec3(0.0f));
    EXPECT_EQ(decode_tangent(encode_tangent(glm::vec4(bad, 0.0f))), glm::vec4(0.0f));
    EXPECT_EQ(decode_tangent(encode_tangent(glm::vec4(bad, -1.0f))), glm::vec4(0.0f));
  }
}

TEST(VertexStreams, PositionsWithinHalfAStep) {
  std::mt19937 rng(12);
  const std::pair<float, float> boxes[] = {{-1.0f, 1.0f},      {0.0f, 0.0f},    {3.0f, 3.0f + 1e-6f}, {-1e5f, 1e5f},
                                           {7990.0f, 8010.5f}, {-0.05f, 0.05f}, {-123.4f, 0.001f},    {1e-30f, 2e-30f}};
  for (const auto& [lo, hi] : boxes) {
    const float step = position_step(glm::vec3(lo), glm::vec3(hi)).x;
    double worst = 0;
    auto check = [&](float p) {
      const double error = std::abs(double(dequantise_position(quantise_position(p, lo, step), lo, step)) - p);
      worst = std::max(worst, error / position_bound(lo, hi));
    };
    check(lo);
    check(hi);
    std::uniform_real_distribution<double> in(lo, hi);
    for (int i = 0; i < 100000; ++i) check(std::clamp(float(in(rng)), lo, hi));
    EXPECT_LE(worst, 1.0) << "box [" << lo << ", " << hi << "]";
  }
}

TEST(VertexStreams, UvsWithinHalfAnUlpAndColoursWithinHalfACode) {
  std::mt19937 rng(7);
  for (int e = -30; e < 16; ++e)
    for (int i = 0; i < 2000; ++i) {
      const float uv[2] = {std::ldexp(1.0f + float(rng() % 4096) / 4096.0f, e), -std::ldexp(float(rng()) / 4e9f, e)};
      const glm::vec2 back = decode_uv(encode_uv(uv));
      for (int k = 0; k < 2; ++k) ASSERT_LE(std::abs(double(back[k]) - uv[k]), uv_bound(uv[k])) << uv[k];
    }
  const float huge[2] = {1e6f, -INFINITY};
  EXPECT_EQ(decode_uv(encode_uv(huge)), glm::vec2(65504.0f, -65504.0f)) << "clamped, not infinite";
  for (int i = 0; i <= 100000; ++i) {
    const float c = i / 100000.0f, rgba[4] = {c, 1.0f - c, c * c, 0.5f};
    const glm::vec4 back = decode_color(encode_color(rgba));
    for (int k = 0; k < 4; ++k) ASSERT_LE(std::abs(double(back[k]) - rgba[k]), kColorBound) << rgba[k];
  }
}

Vertex vertex_at(const glm::vec3& p) {
  Vertex v{};
  std::memcpy(v.position, &p[0], 12);
  v.normal[1] = 1.0f;
  return v;
}

TEST(VertexStreams, BoxesAreTheBoundsGrownToTheirVerticesAndSharedRanges) {
  Scene scene;
  for (const glm::vec3& p : {glm::vec3(0, 0, 0), glm::vec3(1, 2, 3), glm::vec3(-4, 0, 1), glm::vec3(5, 5, 5)})
    scene.vertices.push_back(vertex_at(p));
  scene.indices = {0, 1, 0, 1, 2, 1, 3, 3, 3};
  Primitive a;  // bounds as the loaders make them: its vertices' box
  a.index_count = 3;
  a.bounds_min = {0, 0, 0};
  a.bounds_max = {1, 2, 3};
  Primitive b = a;  // shares vertex 1 with a
  b.first_index = 3;
  b.bounds_min = {-4, 0, 1};
  b.bounds_max = {1, 2, 3};
  Primitive c;  // bounds that miss its vertex, and more room than it needs
  c.first_index = 6;
  c.index_count = 3;
  c.bounds_min = {4, 4, 4};
  c.bounds_max = {4.5f, 4.5f, 6};
  scene.primitives = {a, b, c};
  const PackedGeometry packed = pack_geometry(scene);
  ASSERT_EQ(packed.boxes.size(), 3u);
  for (int p : {0, 1}) {
    EXPECT_EQ(packed.boxes[p].min, glm::vec3(-4, 0, 0));
    EXPECT_EQ(packed.boxes[p].max, glm::vec3(1, 2, 3));
  }
  EXPECT_EQ(packed.boxes[2].min, glm::vec3(4, 4, 4));
  EXPECT_EQ(packed.boxes[2].max, glm::vec3(5, 5, 6));

  GeometryHeader header;
  std::memcpy(&header, packed.bytes.data(), sizeof(header));
  EXPECT_EQ(header.vertex_count, 4u);
  EXPECT_EQ(header.index_count, 9u);
  for (uint32_t s = 0; s < vertex_stream_count; ++s) EXPECT_EQ(header.stream_offset[s] % kGeometryAlignment, 0u);
  EXPECT_EQ(header.index_offset % kGeometryAlignment, 0u);
  EXPECT_EQ(packed.bytes.size(), header.index_offset + 9 * 4);
  const uint32_t owner[4] = {0, 0, 1, 2};
  for (uint32_t v = 0; v < 4; ++v) {
    const PositionBox& box = packed.boxes[owner[v]];
    const Vertex back = geometry_vertex(packed.bytes, v, box.min, position_step(box.min, box.max));
    for (int k = 0; k < 3; ++k)
      EXPECT_LE(std::abs(back.position[k] - scene.vertices[v].position[k]), position_bound(box.min[k], box.max[k]));
  }
}

// The GPU decode: vertex_streams.glsl's decode_vertex for every vertex, in its primitive's box.
const std::map<std::string, std::string> kShaders = {{"test/decode_vertices.comp", R"(#version 460
layout(local_size_x = 64) in;
layout(std430, set = 0, binding = 0) readonly buffer GeometryBlock { uint geometry_words[]; };
layout(std430, set = 0, binding = 1) readonly buffer BoxBlock { vec4 boxes[]; };  // origin, step per vertex
layout(std430, set = 0, binding = 2) writeonly buffer OutBlock { vec4 decoded[]; };
#include "../frame/vertex_streams.glsl"
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(boxes.length()) / 2u) return;
  SceneVertex v = decode_vertex(i, boxes[2u * i].xyz, boxes[2u * i + 1u].xyz);
  decoded[5u * i] = vec4(v.position, 0.0);
  decoded[5u * i + 1u] = vec4(v.normal, 0.0);
  decoded[5u * i + 2u] = v.tangent;
  decoded[5u * i + 3u] = vec4(v.uv0, v.uv1);
  decoded[5u * i + 4u] = v.color;
}
)"}};

// One primitive per box, each vertex with a direction of the Fibonacci sphere (every 16th a zero
// normal and tangent), UVs over many binades and every colour code region.
Scene stress_scene(std::vector<glm::dvec3>& dirs) {
  Scene scene;
  std::mt19937 rng(99);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  dirs = directions(1u << 14);
  const std::pair<glm::vec3, glm::vec3> boxes[] = {{glm::vec3(-1), glm::vec3(1)},
                                                   {glm::vec3(-1e5f, 2, -1e5f), glm::vec3(1e5f, 2, 1e5f)},
                                                   {glm::vec3(7990, -3, 12), glm::vec3(8010.5f, 40, 12.001f)},
                                                   {glm::vec3(0), glm::vec3(1e-6f)}};
  const uint32_t per_box = uint32_t(dirs.size() / std::size(boxes)) + 1;
  for (size_t b = 0; b < std::size(boxes); ++b) {
    Primitive p;
    p.vertex_offset = int32_t(scene.vertices.size());
    p.first_index = uint32_t(scene.indices.size());
    p.bounds_min = boxes[b].first;
    p.bounds_max = boxes[b].second;
    for (uint32_t k = 0; k < per_box && scene.vertices.size() < dirs.size(); ++k) {
      const size_t i = scene.vertices.size();
      const glm::vec3 t = glm::mix(boxes[b].first, boxes[b].second, glm::vec3(unit(rng), unit(rng), unit(rng)));
      Vertex v = vertex_at(k == 0 ? boxes[b].first : k == 1 ? boxes[b].second : t);
      const glm::vec3 d = i % 16 == 5 ? glm::vec3(0.0f) : glm::vec3(dirs[i]);
      std::memcpy(v.normal, &d[0], 12);
      std::memcpy(v.tangent, &d[0], 12);
      v.tangent[3] = i % 2 ? -1.0f : 1.0f;
      const int e = int(i % 40) - 28;  // 2⁻²⁸ … 2¹¹
      v.uv0[0] = std::ldexp(unit(rng), e);
      v.uv0[1] = -std::ldexp(unit(rng), e);
      v.uv1[0] = unit(rng);
      v.uv1[1] = 1.0f + unit(rng);
      for (float& c : v.color) c = unit(rng);
      scene.indices.push_back(k);
      scene.vertices.push_back(v);
    }
    p.index_count = uint32_t(scene.indices.size()) - p.first_index;
    scene.primitives.push_back(p);
  }
  return scene;
}

class VertexStreamsGpu : public GpuTest {};

TEST_F(VertexStreamsGpu, TheShaderDecodesWhatWasEncoded) {
  std::vector<glm::dvec3> dirs;
  const Scene scene = stress_scene(dirs);
  const PackedGeometry packed = pack_geometry(scene);
  const size_t count = scene.vertices.size();
  std::vector<glm::vec4> boxes;
  std::vector<uint32_t> owner;
  for (uint32_t p = 0; p < scene.primitives.size(); ++p) {
    const PositionBox& box = packed.boxes[p];
    for (uint32_t k = 0; k < scene.primitives[p].index_count; ++k) {
      boxes.emplace_back(box.min, 0.0f);
      boxes.emplace_back(position_step(box.min, box.max), 0.0f);
      owner.push_back(p);
    }
  }
  ASSERT_EQ(owner.size(), count);

  auto buffer = [](const void* data, size_t bytes) {
    IsolatedInput in;
    in.desc.is_buffer = true;
    in.desc.kind = kinds::buffer;
    in.desc.buffer_size = bytes;
    in.bytes = std::make_shared<const std::vector<uint8_t>>(static_cast<const uint8_t*>(data),
                                                            static_cast<const uint8_t*>(data) + bytes);
    return in;
  };
  const PassDecl decode = PassDecl("test.decode_vertices", PassType::compute)
                              .read("scene.geometry", Use::storage_read)
                              .read("test.boxes", Use::storage_read)
                              .write("test.decoded", Use::storage_write, BufferDecl{kinds::buffer, count * 80})
                              .shader("test/decode_vertices.comp")
                              .run([count](PassContext& ctx) {
                                ctx.bind_pipeline();
                                ctx.push({Binding::storage(ctx.slot("scene.geometry"), "scene.geometry"),
                                          Binding::storage(ctx.slot("test.boxes"), "test.boxes"),
                                          Binding::storage(ctx.slot("test.decoded"), "test.decoded")});
                                vkCmdDispatch(ctx.cmd(), uint32_t((count + 63) / 64), 1, 1);
                              });
  const IsolatedRun result = run_isolated(
      *gpu_, *cache_, decode,
      {{"scene.geometry", buffer(packed.bytes.data(), packed.bytes.size())},
       {"test.boxes", buffer(boxes.data(), boxes.size() * sizeof(glm::vec4))}},
      {}, 1, 1, [](const std::string&, const std::string& path, const std::string& bindings) {
        auto it = kShaders.find(path);
        return it == kShaders.end() ? builtin_spirv(path, bindings) : compile_glsl(path, it->second, bindings);
      });
  const std::vector<uint8_t>& out = *result.outputs.at("test.decoded");
  ASSERT_EQ(out.size(), count * 80);
  std::vector<glm::vec4> gpu(count * 5);
  std::memcpy(gpu.data(), out.data(), out.size());

  double worst_normal = 0, worst_tangent = 0;
  size_t zero = 0;
  for (size_t i = 0; i < count; ++i) {
    const Vertex& v = scene.vertices[i];
    const PositionBox& box = packed.boxes[owner[i]];
    const Vertex cpu = geometry_vertex(packed.bytes, uint32_t(i), box.min, position_step(box.min, box.max));
    const glm::vec4* g = &gpu[5 * i];
    for (int k = 0; k < 3; ++k) {
      ASSERT_EQ(g[0][k], cpu.position[k]) << "vertex " << i << " axis " << k;
      ASSERT_LE(std::abs(double(g[0][k]) - v.position[k]), position_bound(box.min[k], box.max[k]))
          << "vertex " << i << " axis " << k;
    }
    if (glm::length(glm::make_vec3(v.normal)) == 0.0f) {
      ASSERT_EQ(g[1], glm::vec4(0.0f)) << "vertex " << i;
      ASSERT_EQ(g[2], glm::vec4(0.0f)) << "vertex " << i;
      ++zero;
    } else {
      worst_normal = std::max(worst_normal, angle_degrees(glm::dvec3(g[1]), dirs[i]));
      worst_tangent = std::max(worst_tangent, angle_degrees(glm::dvec3(g[2]), dirs[i]));
      ASSERT_EQ(g[2].w, v.tangent[3]) << "vertex " << i;
    }
    const float uvs[4] = {v.uv0[0], v.uv0[1], v.uv1[0], v.uv1[1]};
    for (int k = 0; k < 4; ++k) ASSERT_LE(std::abs(double(g[3][k]) - uvs[k]), uv_bound(uvs[k])) << "vertex " << i;
    for (int k = 0; k < 4; ++k) ASSERT_LE(std::abs(double(g[4][k]) - v.color[k]), kColorBound) << "vertex " << i;
  }
  std::printf("GPU decode of %zu vertices: normal max %.5f°, tangent max %.5f°, %zu zero directions\n", count,
              worst_normal, worst_tangent, zero);
  EXPECT_GT(zero, 0u);
  EXPECT_LE(worst_normal, kNormalMax + kGpuNormalise);
  EXPECT_LE(worst_tangent, kTangentMax + kGpuNormalise);
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
