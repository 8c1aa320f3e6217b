// The faces of a cube map as Vulkan orders them (+X, −X, +Y, −Y, +Z, −Z) and the direction
// through a point of a face (Vulkan's "Cube Map Face Selection" read backwards): `st` in
// [−1, 1]², s across the face and t down it, as texel (0, 0) is the face's first.
#ifndef NIGHTCAP_SKY_CUBE_GLSL
#define NIGHTCAP_SKY_CUBE_GLSL

vec3 cube_direction(uint face, vec2 st) {
  float s = st.x, t = st.y;
  if (face == 0u) return vec3(1.0, -t, -s);
  if (face == 1u) return vec3(-1.0, -t, s);
  if (face == 2u) return vec3(s, 1.0, t);
  if (face == 3u) return vec3(s, -1.0, -t);
  if (face == 4u) return vec3(s, -t, 1.0);
  return vec3(-s, -t, -1.0);
}

// The direction through the centre of texel `texel` of a face `size` texels wide.
vec3 cube_texel_direction(uint face, ivec2 texel, int size) {
  return normalize(cube_direction(face, (vec2(texel) + 0.5) / float(size) * 2.0 - 1.0));
}

#endif
