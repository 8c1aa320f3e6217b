#include "compare/metrics.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iomanip>
#include <sstream>
#include <vector>

#include "compare/simd_kernels.h"

namespace nightcap {
namespace {

bool is_integer(const FormatInfo& f, uint32_t aspect) {
  using E = ChannelEncoding;
  return aspect == 1 || f.encoding == E::uint8 || f.encoding == E::uint16 || f.encoding == E::uint32;
}

// What a texel's channel must differ by to count in over_threshold_share, where it is fixed: any
// difference of an integer, one code of a UNORM format. Floats are held to 1e-3 relative (of
// values over 1; 1e-3 absolute below), where compare_resource reads them.
double fixed_threshold(const FormatInfo& f, uint32_t aspect) {
  if (is_integer(f, aspect)) return 0.0;
  if (f.encoding == ChannelEncoding::packed_a2b10g10r10) return 1.0 / 1023.0;
  return 1.0 / 255.0;
}

// Calls visit(element, field, component, a, b) for every schema component whose bytes differ
// (field null: a padding or trailing byte), in buffer order; stops when visit returns false.
template <typename Visit>
void each_difference(const BufferSchema& schema, std::span<const uint8_t> a, std::span<const uint8_t> b, Visit visit) {
  const uint64_t elements = a.size() / schema.stride;
  std::vector<bool> covered(schema.stride, false);
  for (const SchemaField& f : schema.fields)
    for (uint32_t i = 0; i < f.bytes(); ++i) covered[f.offset + i] = true;
  for (uint64_t e = 0; e < elements; ++e) {
    const uint64_t base = e * schema.stride;
    if (std::equal(a.begin() + base, a.begin() + base + schema.stride, b.begin() + base)) continue;
    for (const SchemaField& f : schema.fields) {
      const uint32_t size = f.bytes() / f.count;
      for (uint32_t c = 0; c < f.count; ++c) {
        const uint64_t at = base + f.offset + c * size;
        if (std::memcmp(a.data() + at, b.data() + at, size) == 0) continue;
        if (!visit(e, &f, c, read_component(a, schema.stride, e, f, c), read_component(b, schema.stride, e, f, c)))
          return;
      }
    }
    for (uint32_t i = 0; i < schema.stride; ++i)
      if (!covered[i] && a[base + i] != b[base + i] && !visit(e, nullptr, i, a[base + i], b[base + i])) return;
  }
  for (uint64_t i = elements * schema.stride; i < a.size(); ++i)
    if (a[i] != b[i] && !visit(elements, nullptr, uint32_t(i - elements * schema.stride), a[i], b[i])) return;
}

std::string describe_difference(uint64_t element, const SchemaField* field, uint32_t component, double a, double b) {
  std::ostringstream text;
  text << std::setprecision(9) << "element " << element << " "
       << (field ? component_name(*field, component) : "byte " + std::to_string(component) + " outside the fields")
       << ": " << a << " vs " << b;
  return text.str();
}

bool is_float_field(const SchemaField* field) {
  return field && (field->scalar == Scalar::f32 || field->scalar == Scalar::f64);
}

void compare_fields(const BufferSchema& schema, std::span<const uint8_t> a, std::span<const uint8_t> b,
                    ResourceComparison& r) {
  r.metric = "buffer fields";
  const uint64_t elements = (a.size() + schema.stride - 1) / schema.stride;
  uint64_t last_element = UINT64_MAX, float_values = 0;
  double sum = 0;
  for (uint64_t e = 0; e < a.size() / schema.stride; ++e)
    for (const SchemaField& f : schema.fields)
      for (uint32_t c = 0; c < f.count && is_float_field(&f); ++c) {
        const double va = read_component(a, schema.stride, e, f, c), vb = read_component(b, schema.stride, e, f, c);
        r.nan_a += std::isnan(va);
        r.nan_b += std::isnan(vb);
        r.inf_a += std::isinf(va);
        r.inf_b += std::isinf(vb);
        ++float_values;
      }
  each_difference(schema, a, b, [&](uint64_t e, const SchemaField* f, uint32_t c, double va, double vb) {
    if (std::isnan(va) && std::isnan(vb)) return true;  // NaN in the same place is agreement
    if (r.first_difference.empty()) r.first_difference = describe_difference(e, f, c, va, vb);
    if (e != last_element) ++r.differing;
    last_element = e;
    const double d = std::isfinite(va) && std::isfinite(vb) ? std::abs(va - vb) : INFINITY;
    r.max_abs = std::max(r.max_abs, d);
    if (is_float_field(f) && std::isfinite(d)) sum += d * d;
    return true;
  });
  r.over_threshold_share = elements ? double(r.differing) / elements : 0.0;
  r.rmse = float_values ? std::sqrt(sum / float_values) : 0.0;
  r.psnr = r.rmse > 0 ? 20.0 * std::log10(1.0 / r.rmse) : INFINITY;
}

void compare_buffers(std::span<const uint8_t> a, std::span<const uint8_t> b, ResourceComparison& r) {
  r.metric = "buffer words";
  const size_t words = a.size() / 4;
  double sum = 0;
  for (size_t i = 0; i < words; ++i) {
    uint32_t wa, wb;
    std::memcpy(&wa, a.data() + 4 * i, 4);
    std::memcpy(&wb, b.data() + 4 * i, 4);
    if (wa == wb) continue;
    ++r.differing;
    float fa, fb;
    std::memcpy(&fa, &wa, 4);
    std::memcpy(&fb, &wb, 4);
    const double d = std::isfinite(fa) && std::isfinite(fb) ? std::abs(double(fa) - fb) : INFINITY;
    r.max_abs = std::max(r.max_abs, d);
    sum += d * d;
  }
  for (size_t i = words * 4; i < a.size(); ++i) r.differing += a[i] != b[i];
  r.over_threshold_share = words ? double(r.differing) / words : 0.0;
  r.rmse = words ? std::sqrt(sum / words) : 0.0;
  r.psnr = r.rmse > 0 ? 20.0 * std::log10(1.0 / r.rmse) : INFINITY;
}

using metrics_kernels::ImageTally;

// Four values at a time, as doubles (compare/simd.h); a comparison of two gives all bits set in
// the lanes where it holds.
using simd::Doubles4;
using simd::Floats4;
using DoubleMasks = int64_t __attribute__((vector_size(32)));

// Four values of a and of b from `at`, as doubles.
#define NIGHTCAP_LOAD_FOUR(a, b, at, x, y)  \
  Floats4 x##_floats, y##_floats;           \
  std::memcpy(&x##_floats, (a) + (at), 16); \
  std::memcpy(&y##_floats, (b) + (at), 16); \
  const Doubles4 x = __builtin_convertvector(x##_floats, Doubles4), y = __builtin_convertvector(y##_floats, Doubles4)

// |b − a| = d, for a value a of magnitude ax, as a share of what a float contract allows it: 0
// where the values are equal, infinite where the bound is 0 and they are not. For a double and for
// lanes of them, returned through `departure`: by value, the paths' calling conventions would
// differ (GCC's -Wpsabi).
template <typename Values>
[[gnu::always_inline]] inline void float_departure(const ComparisonContract& contract, const Values& d,
                                                   const Values& ax, Values& departure) {
  const Values allowed = contract.absolute + contract.relative * ax;
  departure = d == 0 ? Values{} : allowed > 0 ? d / allowed : Values{} + INFINITY;
}

// A block of finite values, four at a time: the same sums and counts as tally_any, the sum of
// squares in four lanes added at the end; with `departs` (a float contract), also its largest
// departure into `worst` as worst_departure_finite measures it, in the same pass. False, `t` and
// `worst` untouched, where a value of either side is NaN or infinite (its difference then is
// too: d − d is not 0).
[[gnu::always_inline]] inline bool tally_finite_body(const float* a, const float* b, uint64_t texels, uint32_t channels,
                                                     bool relative, double fixed, const ComparisonContract* departs,
                                                     ImageTally& t, double& worst) {
  const uint64_t n = texels * channels;
  // Per value: differs, and over the threshold; a texel counts where any of its channels does.
  // An RGBA texel is one vector, whose lanes are summed at once.
  std::array<int8_t, ResourcePair::kBlockTexels * 4> differs, over;
  uint64_t rgba_differing = 0, rgba_over = 0;
  Doubles4 peak = Doubles4{} + t.peak, largest{}, squares{}, departure_largest{};
  DoubleMasks not_finite{};
  uint64_t i = 0;
  for (; i + 4 <= n; i += 4) {
    NIGHTCAP_LOAD_FOUR(a, b, i, x, y);
    const Doubles4 d = x > y ? x - y : y - x, ax = x < 0 ? -x : x;
    not_finite |= d - d != 0;
    if (relative) peak = ax > peak ? ax : peak;
    largest = d > largest ? d : largest;
    squares += d * d;
    if (departs) {
      Doubles4 departure;
      float_departure(*departs, d, ax, departure);
      departure_largest = departure > departure_largest ? departure : departure_largest;
    }
    const Doubles4 threshold = relative ? 1e-3 * (ax > 1.0 ? ax : Doubles4{} + 1.0) : Doubles4{} + fixed;
    const DoubleMasks is_over = d > threshold, is_different = d != 0;
    if (channels == 4) {
      rgba_differing += (is_different[0] | is_different[1] | is_different[2] | is_different[3]) != 0;
      rgba_over += (is_over[0] | is_over[1] | is_over[2] | is_over[3]) != 0;
      continue;
    }
    for (int lane = 0; lane < 4; ++lane) {
      differs[i + lane] = int8_t(is_different[lane]);
      over[i + lane] = int8_t(is_over[lane]);
    }
  }
  if ((not_finite[0] | not_finite[1] | not_finite[2] | not_finite[3]) != 0) return false;
  double peak_rest = 0.0, largest_rest = 0.0, squares_rest = 0.0, departure_rest = 0.0;
  for (; i < n; ++i) {
    const double x = a[i], d = std::abs(x - b[i]);
    if (!std::isfinite(d)) return false;
    if (relative) peak_rest = std::max(peak_rest, std::abs(x));
    largest_rest = std::max(largest_rest, d);
    squares_rest += d * d;
    if (departs) {
      double departure;
      float_departure(*departs, d, std::abs(x), departure);
      departure_rest = std::max(departure_rest, departure);
    }
    differs[i] = d != 0 ? -1 : 0;
    over[i] = d > (relative ? 1e-3 * std::max(1.0, std::abs(x)) : fixed) ? -1 : 0;
  }
  t.peak = std::max({t.peak, peak[0], peak[1], peak[2], peak[3], peak_rest});
  t.max_abs = std::max({t.max_abs, largest[0], largest[1], largest[2], largest[3], largest_rest});
  t.sum_squares += squares[0] + squares[1] + squares[2] + squares[3] + squares_rest;
  if (departs)
    worst = std::max({worst, departure_largest[0], departure_largest[1], departure_largest[2], departure_largest[3],
                      departure_rest});
  if (channels == 4) {
    t.differing += rgba_differing;
    t.over += rgba_over;
  } else
    for (uint64_t texel = 0; texel < texels; ++texel) {
      int8_t texel_differs = 0, texel_over = 0;
      for (uint32_t c = 0; c < channels; ++c) {
        texel_differs |= differs[texel * channels + c];
        texel_over |= over[texel * channels + c];
      }
      t.differing += texel_differs != 0;
      t.over += texel_over != 0;
    }
  t.values += n;
  t.texels += texels;
  return true;
}
using TallyFinitePaths = simd::Compiled<tally_finite_body, simd::Path::avx2>;
constexpr auto& tally_finite = TallyFinitePaths::dispatch;

// Any block, a texel at a time: NaN and infinity counted in `r` (NaN on both sides agrees, so
// does the same infinity), normals' angles summed where `angles`.
void tally_any(const float* a, const float* b, uint64_t texels, uint32_t channels, bool relative, double fixed,
               bool angles, ImageTally& t, ResourceComparison& r) {
  for (uint64_t texel = 0; texel < texels; ++texel) {
    const float* va = a + texel * channels;
    const float* vb = b + texel * channels;
    bool texel_over = false, texel_differs = false;
    for (uint32_t c = 0; c < channels; ++c) {
      const float x = va[c], y = vb[c];
      if (std::isfinite(x) && std::isfinite(y)) [[likely]] {
        const double d = std::abs(double(x) - y);
        if (relative) t.peak = std::max(t.peak, double(std::abs(x)));
        ++t.values;
        if (d == 0) continue;
        texel_differs = true;
        texel_over |= d > (relative ? 1e-3 * std::max(1.0, double(std::abs(x))) : fixed);
        t.max_abs = std::max(t.max_abs, d);
        t.sum_squares += d * d;
        continue;
      }
      const bool nan_a = std::isnan(x), nan_b = std::isnan(y);
      r.nan_a += nan_a;
      r.nan_b += nan_b;
      r.inf_a += std::isinf(x);
      r.inf_b += std::isinf(y);
      if (relative && std::isfinite(x)) t.peak = std::max(t.peak, double(std::abs(x)));
      if (nan_a && nan_b) continue;      // NaN in the same place is agreement, not a difference
      if (!nan_a && !nan_b && x == y) {  // the same infinity
        ++t.values;
        continue;
      }
      texel_differs = texel_over = true;
      r.max_abs = INFINITY;
      ++t.values;
    }
    if (angles) {
      const double angle = stored_normal_angle_deg(va, vb);
      if (std::isfinite(angle)) {
        r.angular_max_deg = std::max(r.angular_max_deg, angle);
        t.angle_sum += angle;
      }
    }
    t.differing += texel_differs;
    t.over += texel_over;
    ++t.texels;
  }
}

// The largest |b - a| / (absolute + relative |a|) of a float contract over a block (0 where the
// values are equal; infinite where the bound is 0 and they are not) into `worst`; false, `worst`
// untouched, where a value is NaN or infinite.
[[gnu::always_inline]] inline bool worst_departure_finite_body(const float* a, const float* b, uint64_t n,
                                                               const ComparisonContract& contract, double& worst) {
  Doubles4 largest{};
  DoubleMasks not_finite{};
  uint64_t i = 0;
  for (; i + 4 <= n; i += 4) {
    NIGHTCAP_LOAD_FOUR(a, b, i, x, y);
    const Doubles4 d = x > y ? x - y : y - x, ax = x < 0 ? -x : x;
    not_finite |= d - d != 0;
    Doubles4 departure;
    float_departure(contract, d, ax, departure);
    largest = departure > largest ? departure : largest;
  }
  if ((not_finite[0] | not_finite[1] | not_finite[2] | not_finite[3]) != 0) return false;
  double rest = 0.0;
  for (; i < n; ++i) {
    const double d = std::abs(double(a[i]) - b[i]);
    if (!std::isfinite(d)) return false;
    double departure;
    float_departure(contract, d, std::abs(double(a[i])), departure);
    rest = std::max(rest, departure);
  }
  worst = std::max({worst, largest[0], largest[1], largest[2], largest[3], rest});
  return true;
}
using WorstDepartureFinitePaths = simd::Compiled<worst_departure_finite_body, simd::Path::avx2>;
constexpr auto& worst_departure_finite = WorstDepartureFinitePaths::dispatch;

// The largest |a[i] − b[i]| of two byte arrays, thirty-two at a time (compare/simd.h).
[[gnu::always_inline]] inline uint8_t largest_byte_difference_body(const uint8_t* a, const uint8_t* b, size_t n) {
  using Bytes32 = uint8_t __attribute__((vector_size(32)));
  Bytes32 largest{};
  size_t i = 0;
  for (; i + sizeof(Bytes32) <= n; i += sizeof(Bytes32)) {
    Bytes32 x, y;
    std::memcpy(&x, a + i, sizeof x);
    std::memcpy(&y, b + i, sizeof y);
    const Bytes32 difference = x > y ? x - y : y - x;
    largest = difference > largest ? difference : largest;
  }
  uint8_t result = 0;
  for (size_t lane = 0; lane < sizeof(Bytes32); ++lane) result = std::max(result, largest[lane]);
  for (; i < n; ++i) result = std::max(result, uint8_t(a[i] > b[i] ? a[i] - b[i] : b[i] - a[i]));
  return result;
}
using LargestByteDifferencePaths = simd::Compiled<largest_byte_difference_body, simd::Path::avx2>;
constexpr auto& largest_byte_difference = LargestByteDifferencePaths::dispatch;

}  // namespace

metrics_kernels::Functions metrics_kernels::compiled_for(simd::Path path) {
  return {TallyFinitePaths::on(path), WorstDepartureFinitePaths::on(path), LargestByteDifferencePaths::on(path)};
}

double stored_normal_angle_deg(const float* a, const float* b) {
  const glm::dvec3 na = glm::dvec3(a[0], a[1], a[2]) * 2.0 - 1.0, nb = glm::dvec3(b[0], b[1], b[2]) * 2.0 - 1.0;
  return glm::degrees(std::atan2(glm::length(glm::cross(na, nb)), glm::dot(na, nb)));
}

double code_steps(const FormatInfo& format, uint32_t channel, float a, float b) {
  const bool srgb = format.encoding == ChannelEncoding::srgb8 && channel < 3;
  const double ea = srgb ? linear_to_srgb(a) : a, eb = srgb ? linear_to_srgb(b) : b;
  return std::round(std::abs(ea - eb) * code_scale(format));
}

ResourceComparison compare_resource(const ResourceRecord& a, std::span<const uint8_t> a_raw, const ResourceRecord& b,
                                    std::span<const uint8_t> b_raw) {
  return compare_resource(ResourcePair(a, a_raw, b, b_raw));
}

bool displayed_colour(const ResourceRecord& r) {
  return !r.is_buffer && r.kind == kinds::colour && format_info(r.format)->encoding == ChannelEncoding::srgb8 &&
         format_info(r.format)->channels >= 3;
}

FlipResult flip_displayed(const ResourceRecord& a, std::span<const uint8_t> a_raw, std::span<const uint8_t> b_raw) {
  return flip_displayed(ResourcePair(a, a_raw, a, b_raw));
}

FlipResult flip_displayed(const ResourcePair& pair, const FlipOptions& options) {
  // sRGB codes decode to linear values, what FLIP takes, a row at a time as it reads them (no
  // decoded copy of either image); alpha is ignored. Codes decode to finite values.
  const ImageExtent& extent = pair.a.extent;
  const FormatInfo format = *format_info(pair.a.format);
  const uint64_t row_bytes = uint64_t(extent.width) * format.texel_bytes;
  auto rows = [&](std::span<const uint8_t> raw) {
    return FlipRows{extent.width, extent.height, format.channels, [&format, raw, row_bytes](uint32_t y, float* out) {
                      decode_values(format, 0, raw.subspan(y * row_bytes, row_bytes), out);
                    }};
  };
  return flip_ldr(rows(pair.a_raw), rows(pair.b_raw), options);
}

ContractCheck check_contract(const ComparisonContract& contract, const ResourceRecord& a,
                             std::span<const uint8_t> a_raw, const ResourceRecord& b, std::span<const uint8_t> b_raw) {
  const ResourcePair pair(a, a_raw, b, b_raw);
  return check_contract(contract, pair, compare_resource(pair));
}

namespace {

using Kind = ComparisonContract::Kind;

// The largest departure of a block of decoded values from a float, codes or depth contract into
// `worst`.
void depart_block(const ComparisonContract& contract, const FormatInfo& f, uint32_t aspect, const float* va,
                  const float* vb, uint64_t texels, double& worst) {
  const uint32_t channels = aspect_channels(f, aspect);
  const uint64_t n = texels * channels;
  if (aspect == 0 && contract.kind == Kind::float_values && worst_departure_finite(va, vb, n, contract, worst)) return;
  for (uint64_t i = 0; i < n; ++i) {
    if (va[i] == vb[i] || (std::isnan(va[i]) && std::isnan(vb[i]))) continue;  // departs by 0
    const double d = std::abs(double(va[i]) - double(vb[i]));
    double departure;
    if (aspect == 1)  // stencil: exact under every contract
      departure = INFINITY;
    else if (contract.kind == Kind::unorm_codes)
      departure = code_steps(f, uint32_t(i % channels), va[i], vb[i]);
    else if (contract.kind == Kind::linear_depth)
      departure = va[i] != 0 ? d / std::abs(double(va[i])) : INFINITY;
    else
      float_departure(contract, d, std::abs(double(va[i])), departure);
    if (std::isnan(departure)) departure = INFINITY;
    worst = std::max(worst, departure);
  }
}

// Whether check_contract measures an image by its decoded values, block by block: a float, codes
// (wider than a byte) or depth contract.
bool departs_by_blocks(const ComparisonContract& contract, const ResourceRecord& a) {
  if (a.is_buffer) return false;
  const ChannelEncoding e = format_info(a.format)->encoding;
  return contract.kind == Kind::float_values || contract.kind == Kind::linear_depth ||
         (contract.kind == Kind::unorm_codes && e != ChannelEncoding::unorm8 && e != ChannelEncoding::srgb8);
}

// compare_resource, and where `departs` is given (a contract that measures values: departs_by_blocks)
// its largest departure into `worst`, from the same decoded blocks and, for a float contract over
// finite values, in the same pass.
ResourceComparison compare_with(const ResourcePair& pair, const ComparisonContract* departs, double& worst) {
  const ResourceRecord& a = pair.a;
  ResourceComparison r;
  r.identical = pair.same_bytes();
  if (!pair.same_shape()) {
    r.comparable = false;
    r.note = "format or size differs";
    r.max_abs = INFINITY;
    r.psnr = 0;
    r.over_threshold_share = 1.0;
    return r;
  }
  if (a.is_buffer) {
    if (a.schema)
      compare_fields(*a.schema, pair.a_raw, pair.b_raw, r);
    else
      compare_buffers(pair.a_raw, pair.b_raw, r);
    return r;
  }
  const FormatInfo f = *format_info(a.format);
  // A vector needs three channels: a kind that claims one in fewer is measured by its values.
  const bool normal = kind_info(a.kind).measure == KindMeasure::unit_vector && aspect_channels(f, 0) >= 3;
  r.metric = normal             ? "angle"
             : f.has_stencil    ? "depth + stencil"
             : is_integer(f, 0) ? "integer (exact)"
             : is_float(f)      ? "float"
                                : "unorm";
  ImageTally tally;
  tally.peak = is_float(f) ? 1e-6 : 1.0;
  for (uint32_t aspect = 0; aspect < aspect_count(f); ++aspect) {
    const uint32_t channels = aspect_channels(f, aspect);
    const bool relative = is_float(f) && aspect == 0, angles = normal && aspect == 0;
    const double fixed = fixed_threshold(f, aspect);
    const ComparisonContract* fused = departs && aspect == 0 && departs->kind == Kind::float_values ? departs : nullptr;
    pair.for_each_block(aspect, [&](const float* va, const float* vb, uint64_t texels) {
      const bool tallied = !angles && tally_finite(va, vb, texels, channels, relative, fixed, fused, tally, worst);
      if (!tallied) tally_any(va, vb, texels, channels, relative, fixed, angles, tally, r);
      if (departs && !(tallied && fused)) depart_block(*departs, f, aspect, va, vb, texels, worst);
    });
  }
  r.max_abs = std::max(r.max_abs, tally.max_abs);
  r.differing = tally.differing;
  r.rmse = tally.values ? std::sqrt(tally.sum_squares / tally.values) : 0.0;
  r.psnr = r.rmse > 0 ? 20.0 * std::log10(tally.peak / r.rmse) : INFINITY;
  r.over_threshold_share = tally.texels ? double(tally.over) / tally.texels : 0.0;
  r.angular_mean_deg = normal && tally.texels ? tally.angle_sum / tally.texels : 0.0;
  return r;
}

// check_contract, with the worst departure already measured where `walked_worst` is given.
ContractCheck check_contract_with(const ComparisonContract& contract, const ResourcePair& pair,
                                  const ResourceComparison& shape, const double* walked_worst) {
  const ResourceRecord& a = pair.a;
  const std::span<const uint8_t> a_raw = pair.a_raw, b_raw = pair.b_raw;
  ContractCheck check;
  const bool same_bytes = pair.same_bytes();
  if (!shape.comparable) {
    check.measure = shape.note;
    check.worst = INFINITY;
    return check;
  }
  switch (contract.kind) {
    case Kind::exact:
      check.measure = "differing values";
      check.worst = double(shape.differing);
      break;
    case Kind::set: {
      check.measure = "words not matched";
      std::vector<uint32_t> wa(a_raw.size() / 4), wb(b_raw.size() / 4);
      std::memcpy(wa.data(), a_raw.data(), wa.size() * 4);
      std::memcpy(wb.data(), b_raw.data(), wb.size() * 4);
      std::sort(wa.begin(), wa.end());
      std::sort(wb.begin(), wb.end());
      for (size_t i = 0; i < wa.size(); ++i) check.worst += wa[i] != wb[i];
      break;
    }
    case Kind::angle:
      check.measure = "degrees";
      check.bound = contract.absolute;
      check.worst = shape.nan_a + shape.nan_b > 0 ? INFINITY : shape.angular_max_deg;
      break;
    case Kind::float_values:
    case Kind::unorm_codes:
    case Kind::linear_depth: {
      if (a.is_buffer) {
        if (!a.schema || contract.kind != Kind::float_values) {
          check.measure = a.schema ? "a buffer holds no codes or depths" : "a buffer without a schema is words";
          check.worst = INFINITY;
          break;
        }
        check.measure = "multiples of the bound";
        check.bound = 1.0;
        each_difference(*a.schema, a_raw, b_raw, [&](uint64_t, const SchemaField* f, uint32_t, double va, double vb) {
          double departure = INFINITY;  // integers and padding: exact
          if (is_float_field(f) && !(std::isnan(va) && std::isnan(vb))) {
            float_departure(contract, std::abs(va - vb), std::abs(va), departure);
            if (std::isnan(departure)) departure = INFINITY;
          } else if (is_float_field(f))
            departure = 0.0;  // NaN in both: agreement
          check.worst = std::max(check.worst, departure);
          return std::isfinite(check.worst);
        });
        break;
      }
      const FormatInfo f = *format_info(a.format);
      check.measure = contract.kind == Kind::unorm_codes    ? "codes"
                      : contract.kind == Kind::linear_depth ? "relative depth"
                                                            : "multiples of the bound";
      check.bound = contract.kind == Kind::unorm_codes    ? contract.absolute
                    : contract.kind == Kind::linear_depth ? contract.relative
                                                          : 1.0;
      if (contract.kind == Kind::unorm_codes &&
          (f.encoding == ChannelEncoding::unorm8 || f.encoding == ChannelEncoding::srgb8)) {
        // One byte per channel: the stored codes are what the contract counts.
        check.worst = largest_byte_difference(a_raw.data(), b_raw.data(), std::min(a_raw.size(), b_raw.size()));
        break;
      }
      if (walked_worst) {
        check.worst = *walked_worst;
        break;
      }
      for (uint32_t aspect = 0; aspect < aspect_count(f); ++aspect)
        pair.for_each_block(aspect, [&](const float* va, const float* vb, uint64_t texels) {
          depart_block(contract, f, aspect, va, vb, texels, check.worst);
        });
      break;
    }
  }
  check.holds = same_bytes || (contract.kind != Kind::exact && check.worst <= check.bound);
  return check;
}

}  // namespace

ResourceComparison compare_resource(const ResourcePair& pair) {
  double unused = 0.0;
  return compare_with(pair, nullptr, unused);
}

ContractCheck check_contract(const ComparisonContract& contract, const ResourcePair& pair,
                             const ResourceComparison& shape) {
  return check_contract_with(contract, pair, shape, nullptr);
}

MeasuredResource measure_resource(const ComparisonContract& contract, const ResourcePair& pair) {
  MeasuredResource m;
  if (!departs_by_blocks(contract, pair.a) || !pair.same_shape()) {
    m.comparison = compare_resource(pair);
    m.contract = check_contract(contract, pair, m.comparison);
    return m;
  }
  double worst = 0.0;
  m.comparison = compare_with(pair, &contract, worst);
  m.contract = check_contract_with(contract, pair, m.comparison, &worst);
  return m;
}

}  // namespace nightcap
