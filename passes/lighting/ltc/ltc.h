// Linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) for the project's GGX, on the
// CPU in double precision: what the fitter and the tests evaluate, and the model
// passes/lighting/ltc.glsl follows in float.
//
// An LTC is the clamped cosine D_o(w) = max(w.z, 0)/π pushed through a 3×3 matrix M:
// D(ω) = D_o(M⁻¹ω/|M⁻¹ω|)·|det M⁻¹|/|M⁻¹ω|³, normalised by construction. For the isotropic GGX
// lobe seen from v = (sin θv, 0, cos θv) in the frame n = +z, M⁻¹ keeps the form
// [[m00, 0, m02], [0, 1, 0], [m20, 0, m22]] (scaling M changes nothing, so m11 is 1), and
// GGX × n·l without Fresnel ≈ norm·D. Schlick's Fresnel f0 + (1 − f0)·(1 − v·h)⁵ splits the
// specular into the coefficients of f0 and of (1 − f0), as tests/reference/lighting_reference.h's
// ggx_cos_parts does: lights weigh (1 − v·h)⁵ at their own directions; the table keeps its
// average over the lobe too (fresnel), as Heitz et al. store it.
//
// Integrals over a light are taken in the cosine space, where D is the clamped cosine, on the
// light's points mapped by M⁻¹ once clipped to the surface's horizon, as GGX is (the LTC leaks a
// little below it). With the identity they are Lambert's integrals of n·l/π.
#pragma once

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

namespace nightcap::ltc {

using glm::dvec3;

// M⁻¹ as the table stores it: (m00, m02, m20, m22), m11 = 1.
struct InverseMatrix {
  double m00 = 1, m02 = 0, m20 = 0, m22 = 1;

  static InverseMatrix from_stored(const std::array<float, 4>& s) { return {s[0], s[1], s[2], s[3]}; }
  std::array<float, 4> stored() const { return {float(m00), float(m02), float(m20), float(m22)}; }

  double determinant() const { return m00 * m22 - m02 * m20; }
  // M⁻¹w: from the lobe's space to the cosine space.
  dvec3 to_cosine(const dvec3& w) const { return {m00 * w.x + m02 * w.z, w.y, m20 * w.x + m22 * w.z}; }
  // Mw: from the cosine space back to the lobe's space.
  dvec3 from_cosine(const dvec3& w) const {
    const double det = determinant();
    return {(m22 * w.x - m02 * w.z) / det, w.y, (m00 * w.z - m20 * w.x) / det};
  }
};

// The LTC's density at unit ω.
inline double density(const InverseMatrix& minv, const dvec3& omega) {
  const dvec3 q = minv.to_cosine(omega);
  const double length = glm::length(q);
  return std::max(q.z / length, 0.0) / std::numbers::pi * minv.determinant() / (length * length * length);
}

// ∫ D over the hemisphere above the surface: the clamped cosine's share of the half-space
// (Mq).z > 0, whose normal (−m20, 0, m00) leans β from the cosine's axis: (1 + cos β)/2, as a
// surface tilted by β sees of the sky.
inline double visible_mass(const InverseMatrix& minv) { return 0.5 * (1 + minv.m00 / std::hypot(minv.m00, minv.m20)); }

// The frame of a shading point: n = +z, v in the xz-plane with v.x ≥ 0.
struct Frame {
  dvec3 t, b, n;
  dvec3 to_local(const dvec3& w) const { return {glm::dot(t, w), glm::dot(b, w), glm::dot(n, w)}; }
};
Frame shading_frame(const dvec3& n, const dvec3& v);

// Table axes: column j is roughness r_j = r_min + (1 − r_min)·j/(N − 1) (α = r², as brdf.glsl
// is given it), row i is x_i = i/(N − 1) with cos θv = 1 − x_i², which spends rows where the
// lobe changes fastest, at grazing views. r_min keeps the narrowest lobe fittable; lookups clamp
// roughness to it.
inline constexpr double kMinRoughness = 0.02;

inline double table_roughness(int column, int size) {
  return kMinRoughness + (1 - kMinRoughness) * column / double(size - 1);
}
inline double table_cos_theta(int row, int size) {
  const double x = row / double(size - 1);
  return 1 - x * x;
}

// One entry: M⁻¹, and the magnitudes: GGX's ∫ D·V·n·l and ∫ D·V·n·l·(1 − v·h)⁵ over l (the
// height-correlated Smith V), each divided by the LTC's visible_mass. Lights are clipped to the
// surface's horizon, so what of D leaks below it (up to 1.4% of it, at moderate roughness and
// grazing views) would otherwise be lost: a light filling the hemisphere gives the albedo.
struct TableEntry {
  std::array<float, 4> inverse{1, 0, 0, 1};
  float norm = 0, fresnel = 0;
};

// A size×size table, row-major: entries[row·size + column].
struct Table {
  int size = 0;
  std::vector<TableEntry> entries;
  const TableEntry& at(int row, int column) const { return entries[size_t(row) * size + column]; }
};

// The table committed in ggx_table.h.
const Table& ggx_table();

// The lobe at a roughness and view: M⁻¹ and the magnitudes, interpolated bilinearly between
// entries as a texture sampler does between texel centres.
struct Lobe {
  InverseMatrix minv;
  double norm = 0, fresnel = 0;
  // The specular scale for Schlick's f0.
  double magnitude(double f0) const { return f0 * norm + (1 - f0) * fresnel; }
};
Lobe lookup(const Table& table, double roughness, double cos_theta_v);

// ∫ D(l)/d² ds over a line of points p1 + s·(p2 − p1)/|p2 − p1|, offsets from the shading
// point in its frame: the light a line of unit candela per metre sends through the lobe, each
// point weighted as a point light is; and the same with Schlick's weight (1 − v·h)⁵, v the view
// in the frame. A thin tube reflects its intensity × norm × (f0·x + (1 − f0)·y) of these (x, y).
//
// With q = M⁻¹p, D(l)/d² = D_o(q̂)·det M⁻¹·|Mq̂|/|q|². In the plane of the origin and the mapped
// line, q̂ = N cos φ + T sin φ (N toward the nearest point, at distance h; T along the line) and
// ds/|q|² = |MT|·dφ/h: the line is |MT|·det M⁻¹/h · ∫ D_o(q̂)·|Mq̂| dφ, a smooth integrand
// once the line is clipped to q.z ≥ 0, taken by `nodes`-point Gauss–Legendre over φ. Each node
// stands for the direction l = Mq̂/|Mq̂|, so Fresnel is weighed there exactly rather than as the
// lobe's average (the table's fresnel): at grazing views the average missed tubes on the mirror
// direction by up to 88% for f0 = 0.04.
inline constexpr int kLineNodes = 8;
glm::dvec2 line_integral(const InverseMatrix& minv, const dvec3& v, const dvec3& p1, const dvec3& p2,
                         int nodes = kLineNodes);

// The same for the clamped cosine itself (the identity matrix), in closed form: Lambert's
// ∫ max(n·l, 0)/π/d² ds.
double lambert_line_integral(const dvec3& p1, const dvec3& p2);

// ∫ D over a convex polygon (either winding) of offsets from the shading point: the solid-angle
// integral of the clamped cosine over the polygon clipped to the horizon, mapped, and clipped
// to q.z ≥ 0.
double polygon_integral(const InverseMatrix& minv, const std::vector<dvec3>& vertices);

// A sphere light as lighting shades it, per unit radiance (L = I/(π·radius²) for I candela): the
// coefficients (x, y) of f0 and (1 − f0), norm × ∫ D over the solid angle the sphere covers
// and the same weighted by (1 − v·h)⁵. The sphere is its silhouette, a disk facing the shading
// point, drawn as a regular polygon of kSphereSides with the disk's area and integrated in
// closed form; Fresnel is weighed at the polygon's mean direction (its vector form factor,
// mapped back): at views up to 80° the lobe's average (the table's fresnel) missed by up to 88%,
// this misses by up to 36% (the benchmark's ltc section). v is the view in the frame.
inline constexpr int kSphereSides = 8;
glm::dvec2 sphere_integral(const Lobe& lobe, const dvec3& v, const dvec3& centre, double radius);

// A tube light as lighting shades it, per candela per metre: the specular part as the
// coefficients of f0 and (1 − f0), the diffuse part without albedo·(1 − metallic). Positions
// are offsets from the shading point in world space. `radius` spreads the line evenly over the
// tube's apparent width (perpendicular to the tube and to the way to it) by the two-node
// Gauss–Legendre rule: two lines ±radius/√3 off the axis, half the intensity each.
struct TubeShade {
  glm::dvec2 specular{0.0};
  double diffuse = 0;
};
TubeShade shade_tube(const Table& table, const dvec3& n, const dvec3& v, double roughness, const dvec3& end1,
                     const dvec3& end2, double radius);

}  // namespace nightcap::ltc
