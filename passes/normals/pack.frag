#version 460
// Best-fit normal packing: the 8-bit vector along n whose normalisation best matches n, its
// length read from normals.bfn_lut (see passes/normals/bfn_lut.h), plus roughness in alpha.
layout(set = 0, binding = NC_BINDING(gbuffer_normal)) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(gbuffer_material)) uniform sampler2D material_map;
layout(set = 0, binding = NC_BINDING(normals_bfn_lut)) uniform usampler2D bfn_lut;

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_packed;

float code_of(float value) { return floor(clamp(value * 0.5 + 0.5, 0.0, 1.0) * 255.0 + 0.5); }

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float roughness = texelFetch(material_map, pixel, 0).g;
  vec3 stored = texelFetch(normal_map, pixel, 0).xyz;
  if (stored == vec3(0.0)) {  // nothing drawn: the zero vector
    out_packed = vec4(vec3(128.0 / 255.0), roughness);
    return;
  }
  vec3 n = normalize(stored * 2.0 - 1.0);
  vec3 a = abs(n);
  float major = max(a.x, max(a.y, a.z));
  vec3 w = n / major;
  // The two minors, larger first, index the table.
  vec2 minors = a.x == major ? a.yz : (a.y == major ? a.xz : a.xy);
  minors /= major;
  vec2 uv = vec2(max(minors.x, minors.y), min(minors.x, minors.y));
  int size = textureSize(bfn_lut, 0).x;
  // The optimum is exact only at table entries: try the four around uv and keep the one
  // closest to n (smallest sin² of the angle, which float resolves well at these angles).
  vec2 f = uv * float(size - 1);
  ivec2 base = ivec2(floor(f));
  vec3 packed_codes = vec3(128.0);
  float best = 1e30;
  for (int k = 0; k < 4; ++k) {
    ivec2 entry = min(base + ivec2(k & 1, k >> 1), ivec2(size - 1));
    float t = float(texelFetch(bfn_lut, entry, 0).r) * (2.0 / 255.0) - 1.0;
    vec3 codes = vec3(code_of(w.x * t), code_of(w.y * t), code_of(w.z * t));
    vec3 d = codes * (2.0 / 255.0) - 1.0;
    vec3 c = cross(d, n);
    float sin2 = dot(c, c) / max(dot(d, d), 1e-30);
    if (sin2 < best) {
      best = sin2;
      packed_codes = codes;
    }
  }
  out_packed = vec4(packed_codes / 255.0, roughness);
}
