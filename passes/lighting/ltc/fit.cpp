#include "passes/lighting/ltc/fit.h"

#include <limits>

namespace nightcap::ltc {

namespace {

constexpr double kPi = std::numbers::pi;

// GGX D·V·n·l toward unit l, for roughness α and the view v = (sin θv, 0, cos θv) in the frame
// n = +z, and what the fit and the magnitudes sample it with.
class GgxLobe {
 public:
  GgxLobe(double alpha, double cos_theta_v);

  // D·V·n·l, 0 below the horizon.
  double value(const dvec3& l) const;
  // Schlick's weight of (1 − f0): (1 − v·h)⁵.
  double fresnel_weight(const dvec3& l) const;
  // A direction drawn from the distribution of visible normals (Heitz 2018), reflected about
  // the normal drawn; below the horizon for some draws. u in [0, 1)².
  dvec3 sample(double u1, double u2) const;
  // The density of sample()'s directions, per steradian.
  double pdf(const dvec3& l) const;

 private:
  double ndf(const dvec3& h) const;
  double alpha_, cos_theta_v_, g1_v_;
  dvec3 v_;
};

// Cell centres of a k×k grid on [0, 1)²: the same points on every call, so the fit's error is
// one fixed function of M⁻¹.
template <class F>
void for_each_cell(int k, const F& f) {
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) f((i + 0.5) / k, (j + 0.5) / k);
}

// The error of the fit for one entry, with what does not depend on M⁻¹ computed once: the lobe's
// own samples, their values and densities, and the cosine-space samples the LTC's are mapped from.
class FitProblem {
 public:
  FitProblem(const GgxLobe& lobe, double norm, int samples) : lobe_(lobe), norm_(norm) {
    for_each_cell(samples, [&](double u1, double u2) {
      const double r = std::sqrt(u1), phi = 2 * kPi * u2;
      cosine_samples_.push_back({r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(1 - u1, 0.0))});
      const dvec3 l = lobe.sample(u1, u2);
      lobe_samples_.push_back({l, lobe.value(l) / norm, lobe.pdf(l)});
    });
  }

  // ∫ |D_ltc − value/norm|³ by the balance heuristic over both sets of samples.
  double error(const InverseMatrix& minv) const {
    if (!(minv.determinant() > 0)) return std::numeric_limits<double>::infinity();
    double sum = 0;
    for (const dvec3& w : cosine_samples_) {
      const dvec3 l = glm::normalize(minv.from_cosine(w));
      sum += term(density(minv, l), lobe_.value(l) / norm_, lobe_.pdf(l));
    }
    for (const LobeSample& s : lobe_samples_) sum += term(density(minv, s.l), s.target, s.pdf);
    return sum / double(cosine_samples_.size());
  }

 private:
  static double term(double ltc, double target, double lobe_pdf) {
    const double e = std::abs(ltc - target);
    return e * e * e / (ltc + lobe_pdf);
  }

  struct LobeSample {
    dvec3 l;
    double target, pdf;
  };
  const GgxLobe& lobe_;
  double norm_;
  std::vector<dvec3> cosine_samples_;
  std::vector<LobeSample> lobe_samples_;
};

using Point = std::array<double, 4>;

// Nelder–Mead (reflection 1, expansion 2, contraction ½, shrink ½) from `start` with an initial
// simplex of `step` along each axis, until every vertex is within 10⁻⁶ of a step of the best or
// the evaluations run out.
template <class F>
Point nelder_mead(const F& f, const Point& start, const Point& step, int& evaluations_left) {
  constexpr int n = 4;
  std::array<Point, n + 1> x;
  std::array<double, n + 1> fx;
  for (int i = 0; i <= n; ++i) {
    x[i] = start;
    if (i > 0) x[i][i - 1] += step[i - 1];
    fx[i] = f(x[i]);
    --evaluations_left;
  }
  auto along = [](const Point& from, const Point& to, double t) {
    Point p;
    for (int k = 0; k < n; ++k) p[k] = from[k] + t * (to[k] - from[k]);
    return p;
  };
  while (evaluations_left > 0) {
    std::array<int, n + 1> order;
    for (int i = 0; i <= n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](int a, int b) { return fx[a] < fx[b]; });
    const int best = order[0], worst = order[n], second_worst = order[n - 1];
    bool converged = true;
    for (int i = 0; i <= n; ++i)
      for (int k = 0; k < n; ++k) converged &= std::abs(x[i][k] - x[best][k]) <= 1e-6 * std::abs(step[k]);
    if (converged) break;
    Point centroid{};
    for (int i = 0; i <= n; ++i)
      if (i != worst)
        for (int k = 0; k < n; ++k) centroid[k] += x[i][k] / n;
    const Point reflected = along(centroid, x[worst], -1);
    const double f_reflected = f(reflected);
    --evaluations_left;
    if (f_reflected < fx[best]) {
      const Point expanded = along(centroid, x[worst], -2);
      const double f_expanded = f(expanded);
      --evaluations_left;
      if (f_expanded < f_reflected)
        x[worst] = expanded, fx[worst] = f_expanded;
      else
        x[worst] = reflected, fx[worst] = f_reflected;
      continue;
    }
    if (f_reflected < fx[second_worst]) {
      x[worst] = reflected, fx[worst] = f_reflected;
      continue;
    }
    const bool outside = f_reflected < fx[worst];
    const Point contracted = along(centroid, outside ? reflected : x[worst], 0.5);
    const double f_contracted = f(contracted);
    --evaluations_left;
    if (f_contracted < std::min(f_reflected, fx[worst])) {
      x[worst] = contracted, fx[worst] = f_contracted;
      continue;
    }
    for (int i = 0; i <= n; ++i) {
      if (i == best) continue;
      x[i] = along(x[best], x[i], 0.5);
      fx[i] = f(x[i]);
      --evaluations_left;
    }
  }
  return x[std::min_element(fx.begin(), fx.end()) - fx.begin()];
}

GgxLobe::GgxLobe(double alpha, double cos_theta_v)
    : alpha_(alpha),
      cos_theta_v_(cos_theta_v),
      g1_v_(2 * cos_theta_v /
            (cos_theta_v + std::sqrt(cos_theta_v * cos_theta_v * (1 - alpha * alpha) + alpha * alpha))),
      v_(std::sqrt(std::max(1 - cos_theta_v * cos_theta_v, 0.0)), 0, cos_theta_v) {}

double GgxLobe::ndf(const dvec3& h) const {
  // sin²θh + α²cos²θh: the form that keeps the peak's precision (brdf.glsl).
  const double k = h.x * h.x + h.y * h.y + h.z * h.z * alpha_ * alpha_;
  return alpha_ * alpha_ / (kPi * k * k);
}

double GgxLobe::value(const dvec3& l) const {
  if (l.z <= 0) return 0;
  const double a2 = alpha_ * alpha_, n_v = cos_theta_v_;
  const double visibility =
      0.5 / (l.z * std::sqrt(n_v * n_v * (1 - a2) + a2) + n_v * std::sqrt(l.z * l.z * (1 - a2) + a2));
  return ndf(glm::normalize(v_ + l)) * visibility * l.z;
}

double GgxLobe::fresnel_weight(const dvec3& l) const {
  return std::pow(1 - std::clamp(glm::dot(v_, glm::normalize(v_ + l)), 0.0, 1.0), 5.0);
}

dvec3 GgxLobe::sample(double u1, double u2) const {
  // The view in the hemisphere's configuration where the GGX microsurface is the unit one.
  const dvec3 vh = glm::normalize(dvec3(alpha_ * v_.x, alpha_ * v_.y, v_.z));
  const double across = std::sqrt(vh.x * vh.x + vh.y * vh.y);
  const dvec3 t1 = across > 0 ? dvec3(-vh.y, vh.x, 0) / across : dvec3(1, 0, 0);
  const dvec3 t2 = glm::cross(vh, t1);
  // A point of the unit disk, then of the part of it the view sees projected.
  const double r = std::sqrt(u1), phi = 2 * kPi * u2;
  const double p1 = r * std::cos(phi), s = 0.5 * (1 + vh.z);
  const double p2 = (1 - s) * std::sqrt(std::max(1 - p1 * p1, 0.0)) + s * r * std::sin(phi);
  const dvec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(1 - p1 * p1 - p2 * p2, 0.0)) * vh;
  const dvec3 h = glm::normalize(dvec3(alpha_ * nh.x, alpha_ * nh.y, std::max(nh.z, 0.0)));
  return 2 * glm::dot(v_, h) * h - v_;
}

double GgxLobe::pdf(const dvec3& l) const {
  const dvec3 h = glm::normalize(v_ + l);
  if (h.z <= 0) return 0;
  // D_v(h)/(4 v·h) with D_v = G1(v)·v·h·D(h)/n·v.
  return g1_v_ * ndf(h) / (4 * cos_theta_v_);
}

}  // namespace

TableEntry fit_entry(double roughness, double cos_theta_v, const InverseMatrix& start, const FitSettings& settings) {
  const GgxLobe lobe(roughness * roughness, std::max(cos_theta_v, kMinFitCosTheta));
  double norm = 0, fresnel = 0;
  for_each_cell(settings.magnitude_samples, [&](double u1, double u2) {
    const dvec3 l = lobe.sample(u1, u2);
    const double pdf = lobe.pdf(l);
    if (pdf <= 0) return;
    const double weight = lobe.value(l) / pdf;
    norm += weight;
    fresnel += weight * lobe.fresnel_weight(l);
  });
  const double count = double(settings.magnitude_samples) * settings.magnitude_samples;
  norm /= count;
  fresnel /= count;

  const FitProblem problem(lobe, norm, settings.error_samples);
  auto error = [&](const Point& p) { return problem.error({p[0], p[1], p[2], p[3]}); };
  Point best{start.m00, start.m02, start.m20, start.m22};
  // Steps of a tenth of each element's size, the off-diagonal ones measured against the
  // diagonal of their row: each element's natural scale, whatever the roughness.
  const double row0 = std::abs(best[0]) + std::abs(best[1]), row2 = std::abs(best[2]) + std::abs(best[3]);
  const Point step{0.1 * std::max(std::abs(best[0]), 0.05 * row0), 0.1 * std::max(std::abs(best[1]), 0.05 * row0),
                   0.1 * std::max(std::abs(best[2]), 0.05 * row2), 0.1 * std::max(std::abs(best[3]), 0.05 * row2)};
  int evaluations_left = settings.max_evaluations;
  double best_error = error(best);
  // Restarts from the best vertex with a fresh simplex: a collapsed simplex can stall short of
  // the minimum, and a restart that improves nothing ends the fit.
  while (evaluations_left > 0) {
    const Point found = nelder_mead(error, best, step, evaluations_left);
    const double found_error = error(found);
    if (!(found_error < best_error * (1 - 1e-9))) break;
    best = found;
    best_error = found_error;
  }
  TableEntry entry;
  entry.inverse = InverseMatrix{best[0], best[1], best[2], best[3]}.stored();
  const double visible = visible_mass(InverseMatrix::from_stored(entry.inverse));
  entry.norm = float(norm / visible);
  entry.fresnel = float(fresnel / visible);
  return entry;
}

InverseMatrix fit_start(const Table& table, int row, int column) {
  if (row > 0) return InverseMatrix::from_stored(table.at(row - 1, column).inverse);
  if (column + 1 < table.size) return InverseMatrix::from_stored(table.at(0, column + 1).inverse);
  return {};
}

Table fit_table(const FitSettings& settings, const std::function<void(int, int)>& progress) {
  Table table;
  table.size = settings.size;
  table.entries.resize(size_t(settings.size) * settings.size);
  int done = 0;
  for (int column = settings.size - 1; column >= 0; --column)
    for (int row = 0; row < settings.size; ++row) {
      table.entries[size_t(row) * settings.size + column] =
          fit_entry(table_roughness(column, settings.size), table_cos_theta(row, settings.size),
                    fit_start(table, row, column), settings);
      if (progress) progress(++done, settings.size * settings.size);
    }
  return table;
}

}  // namespace nightcap::ltc
