#include "passes/lighting/ltc/ltc.h"

#include "passes/lighting/ltc/ggx_table.h"

namespace nightcap::ltc {

namespace {

constexpr double kPi = std::numbers::pi;

// Gauss–Legendre rules on [-1, 1] with 1 to kMaxNodes nodes, found by Newton's method on the
// Legendre polynomials.
constexpr int kMaxNodes = 64;
struct Rule {
  std::vector<double> x, w;
};

const Rule& gauss_legendre(int nodes) {
  static const std::array<Rule, kMaxNodes + 1> rules = [] {
    std::array<Rule, kMaxNodes + 1> all;
    for (int n = 1; n <= kMaxNodes; ++n) {
      for (int i = 0; i < n; ++i) {
        double x = std::cos(kPi * (i + 0.75) / (n + 0.5)), derivative = 1;
        for (int iteration = 0; iteration < 100; ++iteration) {
          double p0 = 1, p1 = x;
          for (int k = 2; k <= n; ++k) {
            const double p2 = ((2 * k - 1) * x * p1 - (k - 1) * p0) / k;
            p0 = p1;
            p1 = p2;
          }
          derivative = n * (x * p1 - p0) / (x * x - 1);
          const double step = p1 / derivative;
          x -= step;
          if (std::abs(step) < 1e-16) break;
        }
        all[n].x.push_back(x);
        all[n].w.push_back(2 / ((1 - x * x) * derivative * derivative));
      }
    }
    return all;
  }();
  return rules[std::clamp(nodes, 1, kMaxNodes)];
}

// The part of segment [a, b] with z ≥ 0; false when there is none.
bool clip_to_upper(dvec3& a, dvec3& b) {
  if (a.z < 0 && b.z < 0) return false;
  if (a.z < 0) a = b + (a - b) * (b.z / (b.z - a.z));
  if (b.z < 0) b = a + (b - a) * (a.z / (a.z - b.z));
  return true;
}

// Sutherland–Hodgman against z ≥ 0: a convex polygon gains at most one vertex.
std::vector<dvec3> clip_to_upper(const std::vector<dvec3>& polygon) {
  std::vector<dvec3> clipped;
  for (size_t i = 0; i < polygon.size(); ++i) {
    const dvec3& a = polygon[i];
    const dvec3& b = polygon[(i + 1) % polygon.size()];
    if (a.z >= 0) clipped.push_back(a);
    if ((a.z < 0) != (b.z < 0)) clipped.push_back(a + (b - a) * (a.z / (a.z - b.z)));
  }
  return clipped;
}

// The plane of the origin and the line through a and b: unit `toward` the nearest point at
// `distance`, unit `along` the line, and the angles of a and b seen from the origin.
struct LinePlane {
  dvec3 toward, along;
  double distance, phi_a, phi_b;
};

bool line_plane(const dvec3& a, const dvec3& b, LinePlane& plane) {
  const double length = glm::length(b - a);
  if (length == 0) return false;
  plane.along = (b - a) / length;
  const double ta = glm::dot(a, plane.along);
  const dvec3 foot = a - plane.along * ta;
  plane.distance = glm::length(foot);
  // A line through the shading point lights it from no direction.
  if (plane.distance == 0) return false;
  plane.toward = foot / plane.distance;
  plane.phi_a = std::atan2(ta, plane.distance);
  plane.phi_b = std::atan2(ta + length, plane.distance);
  return true;
}

}  // namespace

Frame shading_frame(const dvec3& n, const dvec3& v) {
  dvec3 t = v - n * glm::dot(n, v);
  const double length = glm::length(t);
  // At normal incidence any tangent will do: the lobe is symmetric about n.
  if (length > 1e-12)
    t /= length;
  else
    t = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  return {t, glm::cross(n, t), n};
}

Lobe lookup(const Table& table, double roughness, double cos_theta_v) {
  const int n = table.size;
  const double u = std::clamp((roughness - kMinRoughness) / (1 - kMinRoughness), 0.0, 1.0) * (n - 1);
  const double v = std::sqrt(std::clamp(1 - cos_theta_v, 0.0, 1.0)) * (n - 1);
  const int c0 = std::min(int(u), n - 2), r0 = std::min(int(v), n - 2);
  const double fu = u - c0, fv = v - r0;
  std::array<double, 6> sum{};
  for (int dr = 0; dr < 2; ++dr)
    for (int dc = 0; dc < 2; ++dc) {
      const double w = (dr ? fv : 1 - fv) * (dc ? fu : 1 - fu);
      const TableEntry& e = table.at(r0 + dr, c0 + dc);
      for (int k = 0; k < 4; ++k) sum[k] += w * e.inverse[k];
      sum[4] += w * e.norm;
      sum[5] += w * e.fresnel;
    }
  return {{sum[0], sum[1], sum[2], sum[3]}, sum[4], sum[5]};
}

glm::dvec2 line_integral(const InverseMatrix& minv, const dvec3& v, const dvec3& p1, const dvec3& p2, int nodes) {
  // Below the surface's horizon first: the LTC's mass there belongs to no light.
  dvec3 a = p1, b = p2;
  if (!clip_to_upper(a, b)) return glm::dvec2(0.0);
  a = minv.to_cosine(a);
  b = minv.to_cosine(b);
  LinePlane plane;
  if (!clip_to_upper(a, b) || !line_plane(a, b, plane)) return glm::dvec2(0.0);
  const dvec3 mn = minv.from_cosine(plane.toward), mt = minv.from_cosine(plane.along);
  const double nn = glm::dot(mn, mn), nt = glm::dot(mn, mt), tt = glm::dot(mt, mt);
  const double middle = 0.5 * (plane.phi_a + plane.phi_b), half = 0.5 * (plane.phi_b - plane.phi_a);
  const Rule& rule = gauss_legendre(nodes);
  glm::dvec2 sum(0.0);
  for (size_t k = 0; k < rule.x.size(); ++k) {
    const double phi = middle + half * rule.x[k], c = std::cos(phi), s = std::sin(phi);
    const double cosine = std::max(plane.toward.z * c + plane.along.z * s, 0.0);
    // |Mq̂| for q̂ = N cos φ + T sin φ, and the direction Mq̂ it stands for.
    const dvec3 m = mn * c + mt * s;
    const double length = std::sqrt(nn * c * c + 2 * nt * c * s + tt * s * s);
    const double weight = rule.w[k] * cosine * length;
    const double v_h = glm::dot(v, glm::normalize(v + m / length));
    sum += weight * glm::dvec2(1, std::pow(1 - std::clamp(v_h, 0.0, 1.0), 5.0));
  }
  return sum * (std::sqrt(tt) * minv.determinant() / plane.distance * half / kPi);
}

double lambert_line_integral(const dvec3& p1, const dvec3& p2) {
  dvec3 a = p1, b = p2;
  LinePlane plane;
  if (!clip_to_upper(a, b) || !line_plane(a, b, plane)) return 0;
  const double integral = plane.toward.z * (std::sin(plane.phi_b) - std::sin(plane.phi_a)) -
                          plane.along.z * (std::cos(plane.phi_b) - std::cos(plane.phi_a));
  return std::max(integral, 0.0) / (kPi * plane.distance);
}

namespace {

// The vector form factor of a convex polygon clipped to the horizon, mapped and clipped to
// q.z ≥ 0: Σ θ·ĉ/2π over its edges (c = a × b of their unit ends, θ the angle between them),
// turned to q.z ≥ 0 whatever the winding. Its z is ∫ D_o over the polygon; its direction is the
// polygon's mean direction in the cosine space.
dvec3 form_factor(const InverseMatrix& minv, const std::vector<dvec3>& vertices) {
  // Below the surface's horizon first (the LTC's mass there belongs to no light), then below
  // the cosine's.
  std::vector<dvec3> clipped = clip_to_upper(vertices);
  for (dvec3& p : clipped) p = minv.to_cosine(p);
  clipped = clip_to_upper(clipped);
  dvec3 sum(0.0);
  for (size_t i = 0; i < clipped.size(); ++i) {
    const dvec3 a = glm::normalize(clipped[i]), b = glm::normalize(clipped[(i + 1) % clipped.size()]);
    const dvec3 c = glm::cross(a, b);
    const double sine = glm::length(c);
    // atan2 keeps the angle of nearly parallel edges, which acos of their dot product loses.
    if (sine > 0) sum += std::atan2(sine, glm::dot(a, b)) / sine * c;
  }
  return (sum.z < 0 ? -sum : sum) / (2 * kPi);
}

}  // namespace

double polygon_integral(const InverseMatrix& minv, const std::vector<dvec3>& vertices) {
  return form_factor(minv, vertices).z;
}

glm::dvec2 sphere_integral(const Lobe& lobe, const dvec3& v, const dvec3& centre, double radius) {
  const double distance = glm::length(centre);
  // From inside the sphere, light comes from everywhere: all of D above the horizon, and the
  // lobe's own average Fresnel.
  if (distance <= radius) return visible_mass(lobe.minv) * glm::dvec2(lobe.norm, lobe.fresnel);
  const dvec3 axis = centre / distance;
  const dvec3 e1 = glm::normalize(glm::cross(axis, std::abs(axis.x) < 0.9 ? dvec3(1, 0, 0) : dvec3(0, 1, 0)));
  const dvec3 e2 = glm::cross(axis, e1);
  // The disk through the centre that covers the sphere's cap, then the regular polygon of its area.
  const double disk = radius * distance / std::sqrt(distance * distance - radius * radius);
  const double polygon = disk * std::sqrt(2 * kPi / (kSphereSides * std::sin(2 * kPi / kSphereSides)));
  std::vector<dvec3> vertices;
  for (int k = 0; k < kSphereSides; ++k) {
    const double angle = 2 * kPi * k / kSphereSides;
    vertices.push_back(centre + polygon * (std::cos(angle) * e1 + std::sin(angle) * e2));
  }
  const dvec3 f = form_factor(lobe.minv, vertices);
  if (f.z <= 0) return glm::dvec2(0.0);
  const dvec3 l = glm::normalize(lobe.minv.from_cosine(f));
  const double v_h = std::clamp(glm::dot(v, glm::normalize(v + l)), 0.0, 1.0);
  return lobe.norm * f.z * glm::dvec2(1, std::pow(1 - v_h, 5.0));
}

TubeShade shade_tube(const Table& table, const dvec3& n, const dvec3& v, double roughness, const dvec3& end1,
                     const dvec3& end2, double radius) {
  const Frame frame = shading_frame(n, v);
  const Lobe lobe = lookup(table, roughness, std::clamp(glm::dot(n, v), 0.0, 1.0));
  std::vector<std::pair<dvec3, dvec3>> lines;
  const dvec3 across = glm::cross(end2 - end1, 0.5 * (end1 + end2));
  if (radius > 0 && glm::length(across) > 0) {
    const dvec3 offset = glm::normalize(across) * (radius / std::sqrt(3.0));
    lines = {{end1 + offset, end2 + offset}, {end1 - offset, end2 - offset}};
  } else {
    lines = {{end1, end2}};
  }
  const dvec3 v_local = frame.to_local(v);
  TubeShade shade;
  for (const auto& [a, b] : lines) {
    const dvec3 p1 = frame.to_local(a), p2 = frame.to_local(b);
    shade.specular += lobe.norm * line_integral(lobe.minv, v_local, p1, p2) / double(lines.size());
    shade.diffuse += lambert_line_integral(p1, p2) / double(lines.size());
  }
  return shade;
}

const Table& ggx_table() {
  static const Table table = [] {
    Table t;
    t.size = kGgxTableSize;
    for (int i = 0; i < kGgxTableSize * kGgxTableSize; ++i) {
      TableEntry e;
      for (int k = 0; k < 4; ++k) e.inverse[k] = kGgxInverse[4 * i + k];
      e.norm = kGgxMagnitude[2 * i];
      e.fresnel = kGgxMagnitude[2 * i + 1];
      t.entries.push_back(e);
    }
    return t;
  }();
  return table;
}

}  // namespace nightcap::ltc
