// Indirect light from an environment (the sky's cube maps, a reflection probe) by the split sum,
// as lighting.composite lights the frame's pixels and the reflection probes' captures light their
// faces. Needs sh.glsl, the sky's irradiance (`irradiance`, GpuSkyIrradiance) and the DFG table
// (`dfg_lut`) declared.

// The irradiance about n over π (so times the albedo it is the reflected radiance) from the sky's
// spherical harmonics.
vec3 irradiance_over_pi(vec3 n) {
  float y[9];
  sh_basis(n, y);
  vec3 sum = vec3(0.0);
  for (int i = 0; i < 9; ++i) sum += irradiance.coefficients[i].rgb * y[i];
  return max(sum, vec3(0.0));
}

float table_coordinate(float x, float n) { return 0.5 / n + x * (1.0 - 1.0 / n); }

struct Indirect {
  vec3 diffuse, specular;
};

// The lobe's dominant direction, between the reflection and the normal as roughness grows
// (Lagarde and de Rousiers 2014): where the prefiltered map is read and the horizon is judged.
vec3 dominant_direction(vec3 n, vec3 v, float roughness) {
  float alpha = roughness * roughness, smoothness = 1.0 - alpha;
  return normalize(mix(n, reflect(-v, n), smoothness * (sqrt(smoothness) + alpha)));
}

// The environment's light reflected toward v (world directions: the environment maps are
// world-aligned, camera-relative positions world-oriented): `prefiltered`, its radiance
// prefiltered for `roughness` along r = dominant_direction(); `irradiance_n`, its irradiance
// about n over π. Split sum with the project's DFG table, with `multiple_scattering` the
// compensation of Fdez-Agüera (2019), and horizon occlusion: a reflection below the surface's
// geometric plane (`geometric`, zero when unknown) is cut (Jimenez et al. 2016). `visibility`:
// the material's occlusion; `ao_visibility` and `ao_specular`: the frame's AO on the diffuse and
// on the specular (1 and 1 without it).
Indirect environment_light(vec3 n, vec3 v, vec3 r, vec3 geometric, vec3 albedo, float metallic, float roughness,
                           float visibility, float ao_visibility, float ao_specular, bool multiple_scattering,
                           vec3 prefiltered, vec3 irradiance_n) {
  float n_v = clamp(dot(n, v), 1e-4, 1.0);
  vec2 dfg_size = vec2(textureSize(dfg_lut, 0));
  vec2 dfg = textureLod(dfg_lut, vec2(table_coordinate(n_v, dfg_size.x), table_coordinate(roughness, dfg_size.y)), 0.0).rg;
  vec3 f0 = mix(vec3(0.04), albedo, metallic);
  vec3 single = f0 * dfg.x + dfg.y;
  float single_albedo = dfg.x + dfg.y;
  vec3 fresnel_average = f0 + (1.0 - f0) / 21.0;
  vec3 multiple = !multiple_scattering ? vec3(0.0)
                  : single * fresnel_average * (1.0 - single_albedo) / (1.0 - (1.0 - single_albedo) * fresnel_average);
  if (dot(geometric, v) < 0.0) geometric = -geometric;  // the side the viewer sees
  float horizon = dot(geometric, geometric) > 0.0 ? clamp(1.0 + dot(r, geometric), 0.0, 1.0) : 1.0;
  // Lagarde and de Rousiers (2014): the specular share of the material's ambient visibility;
  // the frame's AO gives its own (ao_specular, from its visibility cone).
  float specular_visibility =
      clamp(pow(n_v + visibility, exp2(-16.0 * roughness - 1.0)) - 1.0 + visibility, 0.0, 1.0) * ao_specular;
  Indirect result;
  result.specular = (single * prefiltered * horizon * horizon + multiple * irradiance_n) * specular_visibility;
  result.diffuse =
      albedo * (1.0 - metallic) * (1.0 - single - multiple) * irradiance_n * (visibility * ao_visibility);
  return result;
}
