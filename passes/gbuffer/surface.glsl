// The G-buffer surface both geometry passes write: gbuffer.opaque (static instances, the
// camera's motion) and gbuffer.dynamic (moving instances, their own motion). `previous_position`
// is the surface point at the previous frame's time, relative to this frame's camera.
#include "../frame/half.glsl"
#include "../frame/types.glsl"

layout(std430, set = 0, binding = NC_BINDING(draws)) readonly buffer DrawBlock { GpuDraw draws[]; };
#include "../frame/views.glsl"
layout(std430, set = 0, binding = NC_BINDING(scene_materials)) readonly buffer MaterialBlock { GpuMaterial materials[]; };
layout(set = 0, binding = NC_BINDING(scene_texture)) uniform sampler2D base_color_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 1) uniform sampler2D metallic_roughness_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 2) uniform sampler2D normal_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 3) uniform sampler2D occlusion_map;
layout(set = 0, binding = NC_BINDING(scene_texture) + 4) uniform sampler2D emissive_map;

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec4 in_tangent;
layout(location = 3) in vec4 in_uv;
layout(location = 4) in vec4 in_color;
layout(location = 5) flat in uint in_draw;

layout(location = 0) out vec4 out_albedo;    // A2B10G10R10: linear albedo, a: object flags
layout(location = 1) out vec4 out_normal;    // A2B10G10R10: 0.5n+0.5, a: hair marker
layout(location = 2) out vec4 out_material;  // metalness, roughness, translucency, emissive
layout(location = 3) out vec2 out_motion;    // uv(current) - uv(previous)
layout(location = 4) out vec3 out_emissive;  // B10G11R11: emitted radiance
layout(location = 5) out float out_occlusion;  // R8: the material's occlusion, for indirect light alone

const float FLAG_UNLIT = 1.0 / 3.0;  // 2-bit alpha of RT0

vec2 slot_uv(GpuMaterial m, int slot) {
  return ((m.textures2.y >> slot) & 1) != 0 ? in_uv.zw : in_uv.xy;
}

void write_gbuffer(vec3 previous_position) {
  GpuMaterial m = materials[draws[in_draw].material];
  vec4 base = m.base_color * in_color;
  if (m.textures.x >= 0) base *= texture(base_color_map, slot_uv(m, 0));
  // MASK: alpha below the cutoff is a hole (pbr.z < 0 for other modes).
  if (m.pbr.z >= 0.0 && base.a < m.pbr.z) discard;

  float metallic = m.pbr.x, roughness = m.pbr.y;
  if (m.textures.y >= 0) {
    vec4 mr = texture(metallic_roughness_map, slot_uv(m, 1));
    roughness *= mr.g;
    metallic *= mr.b;
  }

  // A degenerate vertex normal falls back to the face's geometric normal.
  vec3 n = dot(in_normal, in_normal) > 1e-20 ? normalize(in_normal)
                                              : normalize(cross(dFdx(in_position), dFdy(in_position)));
  if (any(isnan(n))) n = vec3(0.0, 0.0, 1.0);
  if (m.textures.z >= 0) {
    vec2 uv = slot_uv(m, 2);
    vec3 t, b;
    if (dot(in_tangent.xyz, in_tangent.xyz) > 0.0) {
      t = normalize(in_tangent.xyz - n * dot(n, in_tangent.xyz));
      b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
    } else {
      // No tangents in the asset: the face's dP/du from screen-space derivatives, and glTF's
      // handedness (the bitangent points to -v, the normal texture's +Y), so flat regions get
      // the frame MikkTSpace gives them.
      vec3 dp1 = dFdx(in_position), dp2 = dFdy(in_position);
      vec2 duv1 = dFdx(uv), duv2 = dFdy(uv);
      float det = duv1.x * duv2.y - duv2.x * duv1.y;
      vec3 dpdu = (dp1 * duv2.y - dp2 * duv1.y) * sign(det);
      vec3 dpdv = (dp2 * duv1.x - dp1 * duv2.x) * sign(det);
      t = dpdu - n * dot(n, dpdu);
      t = dot(t, t) > 1e-30 ? normalize(t) : vec3(0.0);
      b = cross(n, t) * (dot(cross(n, t), dpdv) < 0.0 ? 1.0 : -1.0);
    }
    vec3 tn = texture(normal_map, uv).xyz * 2.0 - 1.0;
    tn.xy *= m.pbr.w;
    vec3 mapped = t * tn.x + b * tn.y + n * tn.z;
    if (dot(mapped, mapped) > 1e-12) n = normalize(mapped);
  }
  // A visible back face has the front's normal reversed, mapped normal included (glTF 3.9.5).
  if (!gl_FrontFacing) n = -n;

  float occlusion = 1.0;
  if (m.textures.w >= 0) occlusion = 1.0 + m.extra.x * (texture(occlusion_map, slot_uv(m, 3)).r - 1.0);

  vec3 emitted = m.emissive.rgb;
  if (m.textures2.x >= 0) emitted *= texture(emissive_map, slot_uv(m, 4)).rgb;
  // B10G11R11 overflows to infinity above 65024: clamp below its largest finite value.
  emitted = min(emitted, vec3(64512.0));

  bool unlit = (int(m.extra.w) & 1) != 0;
  out_albedo = vec4(clamp(base.rgb, 0.0, 1.0), unlit ? FLAG_UNLIT : 0.0);
  out_occlusion = unlit ? 1.0 : clamp(occlusion, 0.0, 1.0);
  out_normal = vec4(n * 0.5 + 0.5, 0.0);
  // Emissive intensity as log2(1 + luminance) / 16: the seeds' RT2.a, a mask for later passes.
  float luminance = dot(emitted, vec3(0.2126, 0.7152, 0.0722));
  out_material = vec4(clamp(metallic, 0.0, 1.0), clamp(roughness, 0.0, 1.0), m.extra.y,
                      clamp(log2(1.0 + luminance) / 16.0, 0.0, 1.0));

  GpuView view = views[draws[in_draw].view];
  vec4 previous = view.previous_view_projection * vec4(previous_position, 1.0);
  vec2 previous_uv = previous.xy / previous.w * 0.5 + 0.5;
  // Where this pixel's surface point sits unjittered: motion vectors hold no jitter.
  vec2 current_uv = gl_FragCoord.xy * view.viewport.zw - view.jitter.zw;
  out_motion = nearest_half(current_uv - previous_uv);
  out_emissive = emitted;
}
