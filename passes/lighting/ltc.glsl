// Linearly transformed cosines (Heitz et al. 2016) for tube and sphere lights: the float twin of
// passes/lighting/ltc/ltc.h, which derives each integral. A pass gets the table of
// passes/lighting/ltc/ggx_table.h as two images (lighting.ltc_table): M⁻¹ (RGBA: m00, m02, m20,
// m22) and the magnitudes (RG: norm, fresnel), which ltc_lookup() interpolates as ltc::lookup
// does. Positions are offsets from the shading point in the frame ltc_frame(n, v) gives; a lobe's
// M⁻¹ travels as those four values. Both weigh Schlick's Fresnel at the light's own directions
// rather than as the lobe's average (the table's fresnel, which only a sphere around the shading
// point uses). Lines take a range: glTF's window (1 − (d/range)⁴)² along them, which ltc.h
// leaves out (tests/unit/lighting_tiled_test.cpp holds it to the double-precision reference):
// light_falloff.glsl's range_window().

#include "light_falloff.glsl"

const float LTC_PI = 3.14159265358979;
const float LTC_MIN_ROUGHNESS = 0.02;  // ltc.h's kMinRoughness: the table's first column
const int LTC_SPHERE_SIDES = 8;        // ltc.h's kSphereSides

// Gauss–Legendre's 8 nodes on [-1, 1], by pairs ±x, for the line integral (ltc.h's kLineNodes).
// Gauss–Legendre along a line: the includer declares `const int LTC_LINE_NODES` (2, 4, 8 or 16;
// lighting.tiled makes it a specialization constant, its tube_nodes parameter). Node k of
// [-1, 1] (k < LTC_LINE_NODES) and its weight, from the positive half of each rule.
const float LTC_GL2_X[1] = float[](0.5773502691896257);
const float LTC_GL2_W[1] = float[](1.0);
const float LTC_GL4_X[2] = float[](0.3399810435848563, 0.8611363115940526);
const float LTC_GL4_W[2] = float[](0.6521451548625461, 0.3478548451374538);
const float LTC_GL8_X[4] = float[](0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363);
const float LTC_GL8_W[4] = float[](0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763);
const float LTC_GL16_X[8] = float[](0.0950125098376374, 0.2816035507792589, 0.4580167776572274, 0.6178762444026438,
                                    0.7554044083550030, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499);
const float LTC_GL16_W[8] = float[](0.1894506104550685, 0.1826034150449236, 0.1691565193950025, 0.1495959888165767,
                                    0.1246289712555339, 0.0951585116824928, 0.0622535239386479, 0.0271524594117541);

vec2 ltc_line_node(int k) {
  int half_count = LTC_LINE_NODES / 2, i = k % half_count;
  float sign = k < half_count ? -1.0 : 1.0;
  if (LTC_LINE_NODES == 2) return vec2(sign * LTC_GL2_X[i], LTC_GL2_W[i]);
  if (LTC_LINE_NODES == 4) return vec2(sign * LTC_GL4_X[i], LTC_GL4_W[i]);
  if (LTC_LINE_NODES == 16) return vec2(sign * LTC_GL16_X[i], LTC_GL16_W[i]);
  return vec2(sign * LTC_GL8_X[i], LTC_GL8_W[i]);
}

// The lobe at (roughness, n·v): the four nearest entries interpolated bilinearly in float, as
// ltc::lookup does (fetched rather than filtered: a sampler's weights may be coarser).
void ltc_lookup(sampler2D inverse, sampler2D magnitude, float roughness, float n_v, out vec4 minv, out vec2 lobe) {
  int n = textureSize(inverse, 0).x;
  float u = clamp((roughness - LTC_MIN_ROUGHNESS) / (1.0 - LTC_MIN_ROUGHNESS), 0.0, 1.0) * float(n - 1);
  float v = sqrt(clamp(1.0 - n_v, 0.0, 1.0)) * float(n - 1);
  ivec2 c = min(ivec2(u, v), ivec2(n - 2));
  vec2 f = vec2(u, v) - vec2(c);
  minv = mix(mix(texelFetch(inverse, c, 0), texelFetch(inverse, c + ivec2(1, 0), 0), f.x),
             mix(texelFetch(inverse, c + ivec2(0, 1), 0), texelFetch(inverse, c + ivec2(1, 1), 0), f.x), f.y);
  lobe = mix(mix(texelFetch(magnitude, c, 0).rg, texelFetch(magnitude, c + ivec2(1, 0), 0).rg, f.x),
             mix(texelFetch(magnitude, c + ivec2(0, 1), 0).rg, texelFetch(magnitude, c + ivec2(1, 1), 0).rg, f.x), f.y);
}


// World offsets → the frame n = +z, v in the xz-plane: ltc_frame(n, v) * offset.
mat3 ltc_frame(vec3 n, vec3 v) {
  vec3 t = v - n * dot(n, v);
  // At normal incidence any tangent will do: the lobe is symmetric about n.
  t = dot(t, t) > 1e-12 ? normalize(t) : normalize(cross(n, abs(n.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0)));
  return transpose(mat3(t, cross(n, t), n));
}

vec3 ltc_to_cosine(vec4 minv, vec3 w) {
  return vec3(minv.x * w.x + minv.y * w.z, w.y, minv.z * w.x + minv.w * w.z);
}

vec3 ltc_from_cosine(vec4 minv, vec3 w) {
  float det = minv.x * minv.w - minv.y * minv.z;
  return vec3((minv.w * w.x - minv.y * w.z) / det, w.y, (minv.x * w.z - minv.z * w.x) / det);
}

// The part of segment [a, b] with z ≥ 0; false when there is none.
bool ltc_clip_to_upper(inout vec3 a, inout vec3 b) {
  if (a.z < 0.0 && b.z < 0.0) return false;
  if (a.z < 0.0) a = b + (a - b) * (b.z / (b.z - a.z));
  if (b.z < 0.0) b = a + (b - a) * (a.z / (a.z - b.z));
  return true;
}

// The part of segment [a, b] within `range` of the origin (all of it without a range); false
// when there is none.
bool ltc_clip_to_range(inout vec3 a, inout vec3 b, float range) {
  if (range <= 0.0) return true;
  vec3 d = b - a;
  float dd = dot(d, d), ad = dot(a, d), c = dot(a, a) - range * range;
  // A point: what ltc_line_plane makes of it (no light) does not depend on where it is.
  if (dd == 0.0) return c < 0.0;
  float disc = ad * ad - dd * c;
  if (disc <= 0.0) return false;
  float root = sqrt(disc);
  float t0 = max((-ad - root) / dd, 0.0), t1 = min((-ad + root) / dd, 1.0);
  if (!(t0 < t1)) return false;
  vec3 start = a + d * t0;
  b = a + d * t1;
  a = start;
  return true;
}

// The plane of the origin and the line through a and b: unit `toward` its nearest point at
// `distance`, unit `along` it, and the angles (phi.x, phi.y) of a and b seen from the origin.
bool ltc_line_plane(vec3 a, vec3 b, out vec3 toward, out vec3 along, out float distance, out vec2 phi) {
  float len = length(b - a);
  along = (b - a) / max(len, 1e-30);
  float ta = dot(a, along);
  vec3 foot = a - along * ta;
  distance = length(foot);
  toward = foot / max(distance, 1e-30);
  phi = vec2(atan(ta, distance), atan(ta + len, distance));
  // A line through the shading point lights it from no direction.
  return len > 0.0 && distance > 0.0;
}

// ∫ D(l)/d² ds of the LTC M⁻¹ along the line p1 → p2, and the same weighted by Schlick's
// (1 − v·h)⁵ (v the view in the frame): 8-point Gauss–Legendre over the angle in the cosine
// space of |MT|·det M⁻¹/h · D_o(q̂)·|Mq̂|, Fresnel taken at each node's direction (ltc.h,
// line_integral). With a range, the line is cut where it leaves the range, so the integrand
// stays smooth, and each node is weighed by the window at its point of the line: along the
// node's direction l that lies |a × e|/|l × e| away (e the line's direction).
vec2 ltc_line(vec4 minv, vec3 v, vec3 p1, vec3 p2, float range) {
  // Below the surface's horizon first: the LTC's mass there belongs to no light.
  vec3 a = p1, b = p2;
  if (!ltc_clip_to_upper(a, b) || !ltc_clip_to_range(a, b, range)) return vec2(0.0);
  vec3 e = b - a;
  float moment = length(cross(a, e));
  a = ltc_to_cosine(minv, a);
  b = ltc_to_cosine(minv, b);
  vec3 toward, along;
  float distance;
  vec2 phi;
  if (!ltc_clip_to_upper(a, b) || !ltc_line_plane(a, b, toward, along, distance, phi)) return vec2(0.0);
  vec3 mn = ltc_from_cosine(minv, toward), mt = ltc_from_cosine(minv, along);
  float nn = dot(mn, mn), nt = dot(mn, mt), tt = dot(mt, mt);
  float middle = 0.5 * (phi.x + phi.y), half_width = 0.5 * (phi.y - phi.x);
  vec2 sum = vec2(0.0);
  for (int k = 0; k < LTC_LINE_NODES; ++k) {
    vec2 node = ltc_line_node(k);
    float x = node.x;
    float angle = middle + half_width * x, c = cos(angle), s = sin(angle);
    float cosine = max(toward.z * c + along.z * s, 0.0);
    // |Mq̂| for q̂ = N cos φ + T sin φ, and the direction Mq̂ it stands for.
    float len = sqrt(max(nn * c * c + 2.0 * nt * c * s + tt * s * s, 1e-30));
    vec3 l = (mn * c + mt * s) / len;
    float v_h = clamp(dot(v, normalize(v + l)), 0.0, 1.0);
    float window = range > 0.0 ? range_window(moment / max(length(cross(l, e)), 1e-30), range) : 1.0;
    sum += node.y * cosine * len * window * vec2(1.0, pow(1.0 - v_h, 5.0));
  }
  float det = minv.x * minv.w - minv.y * minv.z;
  return sum * (sqrt(tt) * det / distance * half_width / LTC_PI);
}

// Lambert's ∫ max(n·l, 0)/π/d² ds along p1 → p2: in closed form without a range; with one, the
// line cut to the range and 8-point Gauss–Legendre over the angle φ from its nearest point, at
// which n·l = toward.z cos φ + along.z sin φ and the point lies distance/cos φ away.
float ltc_lambert_line(vec3 p1, vec3 p2, float range) {
  vec3 a = p1, b = p2, toward, along;
  float distance;
  vec2 phi;
  if (!ltc_clip_to_upper(a, b) || !ltc_clip_to_range(a, b, range) ||
      !ltc_line_plane(a, b, toward, along, distance, phi))
    return 0.0;
  float integral = 0.0;
  if (range <= 0.0) {
    integral = toward.z * (sin(phi.y) - sin(phi.x)) - along.z * (cos(phi.y) - cos(phi.x));
  } else {
    float middle = 0.5 * (phi.x + phi.y), half_width = 0.5 * (phi.y - phi.x);
    for (int k = 0; k < LTC_LINE_NODES; ++k) {
      vec2 node = ltc_line_node(k);
      float angle = middle + half_width * node.x;
      float c = cos(angle);
      float cosine = max(toward.z * c + along.z * sin(angle), 0.0);
      integral += node.y * cosine * range_window(distance / max(c, 1e-30), range);
    }
    integral *= half_width;
  }
  return max(integral, 0.0) / (LTC_PI * distance);
}

// A tube light per candela per metre: (x, y, diffuse) with specular = f0·x + (1 − f0)·y and the
// diffuse part without albedo·(1 − metallic). `norm` is the table's; v is the view in the
// frame; `radius` spreads the line over the tube's apparent width by two lines ±radius/√3 off
// its axis; `range` (0: none) windows it.
vec3 ltc_tube(vec4 minv, float norm, vec3 v, vec3 p1, vec3 p2, float radius, float range) {
  vec3 across = cross(p2 - p1, 0.5 * (p1 + p2));
  float spread = dot(across, across) > 0.0 ? radius / sqrt(3.0) : 0.0;
  vec3 offset = spread > 0.0 ? normalize(across) * spread : vec3(0.0);
  int lines = spread > 0.0 ? 2 : 1;
  vec2 specular = vec2(0.0);
  float diffuse = 0.0;
  for (int i = 0; i < lines; ++i) {
    vec3 o = i == 0 ? offset : -offset;
    specular += ltc_line(minv, v, p1 + o, p2 + o, range);
    diffuse += ltc_lambert_line(p1 + o, p2 + o, range);
  }
  return vec3(norm * specular, diffuse) / float(lines);
}

// ∫ D above the horizon: ltc.h's visible_mass.
float ltc_visible_mass(vec4 minv) {
  return 0.5 * (1.0 + minv.x / length(minv.xz));
}

// A sphere light per unit radiance: (x, y) with specular = f0·x + (1 − f0)·y. `magnitude` is
// (norm, fresnel), v the view in the frame. The silhouette disk as a regular polygon of the
// disk's area, clipped to the horizon, mapped, clipped to q.z ≥ 0 and integrated edge by edge,
// Fresnel weighed at the polygon's mean direction (ltc.h, sphere_integral).
vec2 ltc_sphere(vec4 minv, vec2 magnitude, vec3 v, vec3 centre, float radius) {
  float distance = length(centre);
  // From inside the sphere, light comes from everywhere: all of D above the horizon, and the
  // lobe's own average Fresnel.
  if (distance <= radius) return ltc_visible_mass(minv) * magnitude;
  vec3 axis = centre / distance;
  vec3 e1 = normalize(cross(axis, abs(axis.x) < 0.9 ? vec3(1, 0, 0) : vec3(0, 1, 0)));
  vec3 e2 = cross(axis, e1);
  float disk = radius * distance / sqrt(distance * distance - radius * radius);
  float sides = float(LTC_SPHERE_SIDES);
  float polygon = disk * sqrt(2.0 * LTC_PI / (sides * sin(2.0 * LTC_PI / sides)));
  // Sutherland–Hodgman against z ≥ 0, in the surface's frame and then in the cosine space: each
  // clip adds at most one vertex to the convex polygon.
  vec3 above[LTC_SPHERE_SIDES + 1];
  int count = 0;
  for (int k = 0; k < LTC_SPHERE_SIDES; ++k) {
    float angle_a = 2.0 * LTC_PI * float(k) / sides, angle_b = 2.0 * LTC_PI * float(k + 1) / sides;
    vec3 a = centre + polygon * (cos(angle_a) * e1 + sin(angle_a) * e2);
    vec3 b = centre + polygon * (cos(angle_b) * e1 + sin(angle_b) * e2);
    if (a.z >= 0.0) above[count++] = ltc_to_cosine(minv, a);
    if ((a.z < 0.0) != (b.z < 0.0)) above[count++] = ltc_to_cosine(minv, a + (b - a) * (a.z / (a.z - b.z)));
  }
  vec3 clipped[LTC_SPHERE_SIDES + 2];
  int clipped_count = 0;
  for (int k = 0; k < count; ++k) {
    vec3 a = above[k], b = above[(k + 1) % count];
    if (a.z >= 0.0) clipped[clipped_count++] = a;
    if ((a.z < 0.0) != (b.z < 0.0)) clipped[clipped_count++] = a + (b - a) * (a.z / (a.z - b.z));
  }
  // The vector form factor: its z is ∫ D_o, its direction the polygon's mean.
  vec3 sum = vec3(0.0);
  for (int k = 0; k < clipped_count; ++k) {
    vec3 a = normalize(clipped[k]), b = normalize(clipped[(k + 1) % clipped_count]);
    vec3 c = cross(a, b);
    float sine = length(c);
    // atan keeps the angle of nearly parallel edges, which acos of their dot product loses.
    if (sine > 0.0) sum += atan(sine, dot(a, b)) / sine * c;
  }
  sum = (sum.z < 0.0 ? -sum : sum) / (2.0 * LTC_PI);
  if (sum.z <= 0.0) return vec2(0.0);
  vec3 l = normalize(ltc_from_cosine(minv, sum));
  float v_h = clamp(dot(v, normalize(v + l)), 0.0, 1.0);
  return magnitude.x * sum.z * vec2(1.0, pow(1.0 - v_h, 5.0));
}
