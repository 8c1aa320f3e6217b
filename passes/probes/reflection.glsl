// The reflection probes as lighting.composite reads them: which probes light a point, the
// parallax-corrected direction each is read along, and its prefiltered radiance there. Needs
// capture_layout.glsl.h and paraboloid.glsl.h, and, for probe_radiance(), probes.array declared
// as `probe_array` (sampler2DArray).
#ifndef NIGHTCAP_PROBES_REFLECTION_GLSL
#define NIGHTCAP_PROBES_REFLECTION_GLSL

// Parallax correction [000] (Lagarde and Zanuttini 2012): the reflection ray from `position`
// along `r` leaves the probe's box at a point, which the probe at `probe` sees along the
// direction returned. `position` must lie inside the box (every slab's exit is then ahead).
vec3 parallax_direction(vec3 position, vec3 r, vec3 box_min, vec3 box_max, vec3 probe) {
  vec3 to_max = (box_max - position) / r, to_min = (box_min - position) / r;
  vec3 exits = max(to_max, to_min);
  float t = min(min(exits.x, exits.y), exits.z);
  return normalize(position + r * t - probe);
}

// How much the probe of `slot` lights a point: 0 outside its box, rising linearly to 1 over
// `fade_metres` inside the box's faces.
float probe_weight(GpuProbeSlot slot, vec3 position, float fade_metres) {
  vec3 inside = min(position - slot.box_min.xyz, slot.box_max.xyz - position);
  float margin = min(min(inside.x, inside.y), inside.z);
  return margin > 0.0 ? clamp(margin / max(fade_metres, 1e-6), 0.0, 1.0) : 0.0;
}

// Texel coordinates (uv) and layer of probes.array that the direction d of slot `slot` is at.
vec3 probe_texel(uint slot, vec3 d) {
  return vec3(paraboloid_point(d) * 0.5 + 0.5, float(2u * slot + paraboloid_hemisphere(d)));
}

#ifdef NC_BINDING_probes_array
// The radiance of slot `slot` along d, prefiltered at `lod` (roughness × (kProbeArrayMips − 1)).
vec3 probe_radiance(uint slot, vec3 d, float lod) { return textureLod(probe_array, probe_texel(slot, d), lod).rgb; }
#endif

#endif
