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

#ifdef NC_PROBE_SLOTS
// The two probes nearest a point among those whose boxes hold it, of the `count` that `slots`
// (probes.slots, declared with NC_PROBE_SLOTS defined) lists: their indices in it and how much
// each lights the point (probe_weight(); 0: none). Choosing first and reading after keeps a
// caller's texture reads at two: lavapipe would run a read in the loop for every slot.
struct NearestProbes {
  uint index[2];
  float weight[2];
};
NearestProbes nearest_probes(vec3 position, uint count, float fade_metres) {
  NearestProbes nearest = NearestProbes(uint[2](0u, 0u), float[2](0.0, 0.0));
  float distances[2] = float[2](1e30, 1e30);
  for (uint k = 0u; k < count; ++k) {
    float w = probe_weight(slots[k], position, fade_metres);
    float d = length(position - slots[k].position.xyz);
    if (w <= 0.0 || d >= distances[1]) continue;
    bool first = d < distances[0];
    nearest.index[1] = first ? nearest.index[0] : k;
    nearest.weight[1] = first ? nearest.weight[0] : w;
    distances[1] = first ? distances[0] : d;
    nearest.index[0] = first ? k : nearest.index[0];
    nearest.weight[0] = first ? w : nearest.weight[0];
    distances[0] = first ? d : distances[0];
  }
  return nearest;
}
#endif

// Texel coordinates (uv) and layer of probes.array that the direction d of slot `slot` is at.
vec3 probe_texel(uint slot, vec3 d) {
  return vec3(paraboloid_point(d) * 0.5 + 0.5, float(2u * slot + paraboloid_hemisphere(d)));
}

#ifdef NC_BINDING_probes_array
// The radiance of slot `slot` along d, prefiltered at `lod` (roughness × (kProbeArrayMips − 1)).
vec3 probe_radiance(uint slot, vec3 d, float lod) { return textureLod(probe_array, probe_texel(slot, d), lod).rgb; }
#endif

#endif
