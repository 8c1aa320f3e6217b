// Decoding scene.geometry's vertex streams (passes/frame/vertex_streams.h has the layout and the
// CPU side of the encoding). The including shader declares the whole buffer, header included,
// as `uint geometry_words[]`.

struct SceneVertex {
  vec3 position;
  vec3 normal;
  vec4 tangent;
  vec2 uv0;
  vec2 uv1;
  vec4 color;
};

// Word indices of GeometryHeader::stream_offset[] (bytes), by stream.
const uint GEOMETRY_POSITION_OFFSET = 3u;
const uint GEOMETRY_UV0_OFFSET = 4u;
const uint GEOMETRY_FRAME_OFFSET = 5u;
const uint GEOMETRY_COLOR_UV1_OFFSET = 6u;
// The low half-word that marks a zero direction (kNoDirection).
const uint NO_DIRECTION = 0x8000u;

uint stream_word(uint offset_word, uint words_per_vertex, uint index, uint word) {
  return geometry_words[geometry_words[offset_word] / 4u + index * words_per_vertex + word];
}

vec3 from_octahedral(int x, int y, float x_max, float y_max) {
  vec2 e = max(vec2(float(x) / x_max, float(y) / y_max), vec2(-1.0));
  vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
  if (v.z < 0.0) v.xy = (1.0 - abs(e.yx)) * vec2(e.x >= 0.0 ? 1.0 : -1.0, e.y >= 0.0 ? 1.0 : -1.0);
  return normalize(v);
}

// Octahedral snorm 16:16; a zero direction stays zero.
vec3 decode_normal(uint code) {
  if ((code & 0xffffu) == NO_DIRECTION) return vec3(0.0);
  return from_octahedral(bitfieldExtract(int(code), 0, 16), bitfieldExtract(int(code), 16, 16), 32767.0, 32767.0);
}

// Octahedral snorm 16:15, bit 31 the handedness.
vec4 decode_tangent(uint code) {
  if ((code & 0xffffu) == NO_DIRECTION) return vec4(0.0);
  vec3 t = from_octahedral(bitfieldExtract(int(code), 0, 16), bitfieldExtract(int(code), 16, 15), 32767.0, 16383.0);
  return vec4(t, (code >> 31) != 0u ? -1.0 : 1.0);
}

// Vertex `index` with its position in the box origin + step · [0, 65535]³. `precise` keeps the
// multiply and the add apart (no fused multiply-add), so every pass places a vertex identically.
SceneVertex decode_vertex(uint index, vec3 origin, vec3 step) {
  SceneVertex v;
  uint xy = stream_word(GEOMETRY_POSITION_OFFSET, 2u, index, 0u);
  uint z = stream_word(GEOMETRY_POSITION_OFFSET, 2u, index, 1u);
  vec3 q = vec3(float(xy & 0xffffu), float(xy >> 16), float(z & 0xffffu));
  precise vec3 scaled = step * q;
  precise vec3 position = origin + scaled;
  v.position = position;
  v.uv0 = unpackHalf2x16(stream_word(GEOMETRY_UV0_OFFSET, 1u, index, 0u));
  v.normal = decode_normal(stream_word(GEOMETRY_FRAME_OFFSET, 2u, index, 0u));
  v.tangent = decode_tangent(stream_word(GEOMETRY_FRAME_OFFSET, 2u, index, 1u));
  v.color = unpackUnorm4x8(stream_word(GEOMETRY_COLOR_UV1_OFFSET, 2u, index, 0u));
  v.uv1 = unpackHalf2x16(stream_word(GEOMETRY_COLOR_UV1_OFFSET, 2u, index, 1u));
  return v;
}
