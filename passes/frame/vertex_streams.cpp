#include "passes/frame/vertex_streams.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "passes/core/format.h"

namespace nightcap {
namespace {

uint32_t align(uint32_t value) { return (value + kGeometryAlignment - 1) / kGeometryAlignment * kGeometryAlignment; }

// Octahedral map of a unit direction onto the square [−1, 1]² (Cigolle et al. 2014), in double.
glm::dvec2 octahedral(const glm::dvec3& n) {
  const glm::dvec2 p = glm::dvec2(n.x, n.y) / (std::abs(n.x) + std::abs(n.y) + std::abs(n.z));
  if (n.z >= 0.0) return p;
  return glm::dvec2((1.0 - std::abs(p.y)) * (p.x >= 0.0 ? 1.0 : -1.0),
                    (1.0 - std::abs(p.x)) * (p.y >= 0.0 ? 1.0 : -1.0));
}

// The point of the octahedron at e in [−1, 1]², in T's arithmetic (not normalised).
template <typename T>
glm::vec<3, T> unfold(T ex, T ey) {
  const T one(1), z = one - std::abs(ex) - std::abs(ey);
  if (z >= T(0)) return {ex, ey, z};
  return {(one - std::abs(ey)) * (ex >= T(0) ? one : -one), (one - std::abs(ex)) * (ey >= T(0) ? one : -one), z};
}

// The shader's decode of two snorm codes with `x_max`, `y_max` steps per unit, in float.
glm::vec3 from_octahedral(int32_t x, int32_t y, float x_max, float y_max) {
  return glm::normalize(unfold(std::max(float(x) / x_max, -1.0f), std::max(float(y) / y_max, -1.0f)));
}

// The codes of `n` on a grid of ±x_max × ±y_max: of the four grid points around its octahedral
// position, the one whose direction is closest to n (rounding each coordinate alone is up to
// ~1.5× worse). Compared in double: a float normalisation's length error (~10⁻⁷) would outweigh
// the 1 − cos of the angles compared (~10⁻⁹).
std::pair<int32_t, int32_t> oct_codes(const glm::dvec3& n, int32_t x_max, int32_t y_max) {
  const glm::dvec2 p = octahedral(n);
  const double fx = std::floor(std::clamp(p.x, -1.0, 1.0) * x_max), fy = std::floor(std::clamp(p.y, -1.0, 1.0) * y_max);
  std::pair<int32_t, int32_t> best{0, 0};
  double best_cos = -2.0;
  for (int dx = 0; dx < 2; ++dx)
    for (int dy = 0; dy < 2; ++dy) {
      const int32_t x = std::clamp(int32_t(fx) + dx, -x_max, x_max), y = std::clamp(int32_t(fy) + dy, -y_max, y_max);
      const double c = glm::dot(glm::normalize(unfold(double(x) / x_max, double(y) / y_max)), n);
      if (c > best_cos) {
        best_cos = c;
        best = {x, y};
      }
    }
  return best;
}

bool usable_direction(const glm::vec3& v) {
  const double length = glm::length(glm::dvec3(v));
  return std::isfinite(length) && length > 0.0;
}

int32_t sign_extend(uint32_t bits, uint32_t width) { return int32_t(bits << (32 - width)) >> (32 - width); }

uint32_t half_bits(float value) {
  if (std::isnan(value)) return 0;
  return float_to_half(std::clamp(value, -65504.0f, 65504.0f));
}

// Disjoint sets of primitives, merged where two draw the same vertex.
struct Groups {
  std::vector<uint32_t> parent;
  explicit Groups(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void merge(uint32_t a, uint32_t b) { parent[find(a)] = find(b); }
};

}  // namespace

glm::vec3 position_step(const glm::vec3& lo, const glm::vec3& hi, uint32_t levels) { return (hi - lo) / float(levels); }

uint32_t quantise_position(float p, float origin, float step, uint32_t levels) {
  if (!std::isfinite(p) || !(step > 0.0f)) return 0;
  const double nearest = std::round((double(p) - origin) / step);
  const uint32_t q = uint32_t(std::clamp(nearest, 0.0, double(levels)));
  // The float decode rounds twice: a neighbour may land closer to p.
  uint32_t best = q;
  for (uint32_t c : {q == 0 ? q : q - 1, std::min(q + 1, levels)})
    if (std::abs(double(dequantise_position(c, origin, step)) - p) <
        std::abs(double(dequantise_position(best, origin, step)) - p))
      best = c;
  return best;
}

float dequantise_position(uint32_t q, float origin, float step) {
  const float scaled = step * float(q);
  return origin + scaled;
}

uint32_t encode_normal(const glm::vec3& n) {
  if (!usable_direction(n)) return kNoDirection;
  const auto [x, y] = oct_codes(glm::normalize(glm::dvec3(n)), 32767, 32767);
  return (uint32_t(x) & 0xffff) | uint32_t(y) << 16;
}

glm::vec3 decode_normal(uint32_t code) {
  if ((code & 0xffff) == kNoDirection) return glm::vec3(0.0f);
  return from_octahedral(sign_extend(code & 0xffff, 16), sign_extend(code >> 16, 16), 32767.0f, 32767.0f);
}

uint32_t encode_tangent(const glm::vec4& t) {
  const glm::vec3 xyz(t);
  if (!usable_direction(xyz)) return kNoDirection;
  const auto [x, y] = oct_codes(glm::normalize(glm::dvec3(xyz)), 32767, 16383);
  return (uint32_t(x) & 0xffff) | (uint32_t(y) & 0x7fff) << 16 | (t.w < 0.0f ? 1u << 31 : 0u);
}

glm::vec4 decode_tangent(uint32_t code) {
  if ((code & 0xffff) == kNoDirection) return glm::vec4(0.0f);
  const glm::vec3 xyz =
      from_octahedral(sign_extend(code & 0xffff, 16), sign_extend((code >> 16) & 0x7fff, 15), 32767.0f, 16383.0f);
  return glm::vec4(xyz, code >> 31 ? -1.0f : 1.0f);
}

uint32_t encode_uv(const float uv[2]) { return half_bits(uv[0]) | half_bits(uv[1]) << 16; }

glm::vec2 decode_uv(uint32_t code) {
  return {half_to_float(uint16_t(code & 0xffff)), half_to_float(uint16_t(code >> 16))};
}

uint32_t encode_color(const float rgba[4]) {
  uint32_t code = 0;
  for (int c = 0; c < 4; ++c) {
    const float v = std::isnan(rgba[c]) ? 0.0f : std::clamp(rgba[c], 0.0f, 1.0f);
    code |= uint32_t(std::lround(v * 255.0f)) << (8 * c);
  }
  return code;
}

glm::vec4 decode_color(uint32_t code) {
  glm::vec4 v;
  for (int c = 0; c < 4; ++c) v[c] = float((code >> (8 * c)) & 0xff) / 255.0f;
  return v;
}

PackedGeometry pack_geometry(const Scene& scene) {
  const uint32_t vertex_count = uint32_t(scene.vertices.size());
  const size_t primitive_count = scene.primitives.size();
  auto for_each_vertex = [&](const Primitive& p, auto&& visit) {
    for (uint32_t k = 0; k < p.index_count && size_t(p.first_index) + k < scene.indices.size(); ++k) {
      const int64_t v = int64_t(p.vertex_offset) + scene.indices[p.first_index + k];
      if (v >= 0 && v < int64_t(vertex_count)) visit(uint32_t(v));
    }
  };

  // Which primitive group quantises each vertex (UINT32_MAX: drawn by none).
  Groups groups(primitive_count);
  std::vector<uint32_t> owner(vertex_count, UINT32_MAX);
  for (uint32_t i = 0; i < primitive_count; ++i)
    for_each_vertex(scene.primitives[i], [&](uint32_t v) {
      if (owner[v] == UINT32_MAX)
        owner[v] = i;
      else
        groups.merge(owner[v], i);
    });
  std::vector<PositionBox> group_box(primitive_count);
  for (uint32_t i = 0; i < primitive_count; ++i)
    group_box[i] = {scene.primitives[i].bounds_min, scene.primitives[i].bounds_max};
  for (uint32_t i = 0; i < primitive_count; ++i) {
    PositionBox& box = group_box[groups.find(i)];
    box.min = glm::min(box.min, scene.primitives[i].bounds_min);
    box.max = glm::max(box.max, scene.primitives[i].bounds_max);
    for_each_vertex(scene.primitives[i], [&](uint32_t v) {
      const glm::vec3 p = glm::make_vec3(scene.vertices[v].position);
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return;
      box.min = glm::min(box.min, p);
      box.max = glm::max(box.max, p);
    });
  }

  PackedGeometry out;
  out.boxes.resize(primitive_count);
  for (uint32_t i = 0; i < primitive_count; ++i) out.boxes[i] = group_box[groups.find(i)];

  GeometryHeader header{};
  header.vertex_count = vertex_count;
  header.index_count = uint32_t(scene.indices.size());
  uint32_t offset = kGeometryAlignment;
  for (uint32_t s = 0; s < vertex_stream_count; ++s) {
    header.stream_offset[s] = offset;
    offset = align(offset + vertex_count * kVertexStreamBytes[s]);
  }
  header.index_offset = offset;
  out.bytes.assign(header.index_offset + header.index_count * 4, 0);
  std::memcpy(out.bytes.data(), &header, sizeof(header));
  auto store = [&](VertexStream s, uint32_t vertex, uint32_t word, uint32_t value) {
    std::memcpy(out.bytes.data() + header.stream_offset[s] + vertex * kVertexStreamBytes[s] + 4 * word, &value, 4);
  };
  for (uint32_t v = 0; v < vertex_count; ++v) {
    const Vertex& vertex = scene.vertices[v];
    if (owner[v] != UINT32_MAX) {
      const PositionBox& box = out.boxes[owner[v]];
      const glm::vec3 step = position_step(box.min, box.max);
      uint32_t q[3];
      for (int k = 0; k < 3; ++k) q[k] = quantise_position(vertex.position[k], box.min[k], step[k]);
      store(position_stream, v, 0, q[0] | q[1] << 16);
      store(position_stream, v, 1, q[2]);
    }
    store(uv0_stream, v, 0, encode_uv(vertex.uv0));
    store(frame_stream, v, 0, encode_normal(glm::make_vec3(vertex.normal)));
    store(frame_stream, v, 1, encode_tangent(glm::make_vec4(vertex.tangent)));
    store(color_uv1_stream, v, 0, encode_color(vertex.color));
    store(color_uv1_stream, v, 1, encode_uv(vertex.uv1));
  }
  if (!scene.indices.empty())
    std::memcpy(out.bytes.data() + header.index_offset, scene.indices.data(), scene.indices.size() * 4);
  return out;
}

Vertex geometry_vertex(const std::vector<uint8_t>& geometry, uint32_t vertex, const glm::vec3& origin,
                       const glm::vec3& step) {
  GeometryHeader header;
  std::memcpy(&header, geometry.data(), sizeof(header));
  auto word = [&](VertexStream s, uint32_t k) {
    uint32_t value;
    std::memcpy(&value, geometry.data() + header.stream_offset[s] + vertex * kVertexStreamBytes[s] + 4 * k, 4);
    return value;
  };
  Vertex v{};
  const uint32_t q[3] = {word(position_stream, 0) & 0xffff, word(position_stream, 0) >> 16,
                         word(position_stream, 1) & 0xffff};
  for (int k = 0; k < 3; ++k) v.position[k] = dequantise_position(q[k], origin[k], step[k]);
  const glm::vec3 n = decode_normal(word(frame_stream, 0));
  const glm::vec4 t = decode_tangent(word(frame_stream, 1));
  const glm::vec2 uv0 = decode_uv(word(uv0_stream, 0)), uv1 = decode_uv(word(color_uv1_stream, 1));
  const glm::vec4 color = decode_color(word(color_uv1_stream, 0));
  std::memcpy(v.normal, &n[0], sizeof(v.normal));
  std::memcpy(v.tangent, &t[0], sizeof(v.tangent));
  std::memcpy(v.uv0, &uv0[0], sizeof(v.uv0));
  std::memcpy(v.uv1, &uv1[0], sizeof(v.uv1));
  std::memcpy(v.color, &color[0], sizeof(v.color));
  return v;
}

}  // namespace nightcap
