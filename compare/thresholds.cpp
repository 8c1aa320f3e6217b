#include "compare/thresholds.h"

#include "compare/metrics.h"

#include <fnmatch.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace nightcap {

namespace {

const std::map<std::string, TexelMetric>& metrics_by_name() {
  static const std::map<std::string, TexelMetric> names = {{"exact", TexelMetric::exact}, {"abs", TexelMetric::abs},
                                                           {"rel", TexelMetric::rel},     {"angle", TexelMetric::angle},
                                                           {"depth", TexelMetric::depth}, {"codes", TexelMetric::codes},
                                                           {"flip", TexelMetric::flip}};
  return names;
}

std::string number(double v) {
  std::ostringstream s;
  s << std::setprecision(6) << v;
  return s.str();
}

// The error of one texel: the largest over its channels (normals: the angle between them).
double texel_error(TexelMetric metric, const FormatInfo& format, uint32_t aspect, const float* va, const float* vb,
                   uint32_t channels) {
  if (metric == TexelMetric::angle && aspect == 0) {
    if (std::isnan(va[0]) != std::isnan(vb[0])) return INFINITY;
    const double angle = stored_normal_angle_deg(va, vb);
    return std::isfinite(angle) ? angle : INFINITY;
  }
  double worst = 0.0;
  for (uint32_t c = 0; c < channels; ++c) {
    const bool nan_a = std::isnan(va[c]), nan_b = std::isnan(vb[c]);
    if (nan_a && nan_b) continue;
    if (va[c] == vb[c]) continue;
    if (nan_a || nan_b || std::isinf(va[c]) || std::isinf(vb[c]) || metric == TexelMetric::exact || aspect == 1)
      return INFINITY;  // a stencil is exact under every metric
    const double d = std::abs(double(va[c]) - double(vb[c]));
    double e = d;
    switch (metric) {
      case TexelMetric::rel:
        e = d / std::max(std::abs(double(va[c])), 1e-6);
        break;
      case TexelMetric::depth:
        e = va[c] == 0 || vb[c] == 0 ? INFINITY : std::abs(double(va[c]) / vb[c] - 1.0);
        break;
      case TexelMetric::codes:
        e = code_steps(format, c, va[c], vb[c]);
        break;
      default:
        break;
    }
    worst = std::max(worst, e);
  }
  return worst;
}

// Why `metric` cannot measure `r`, or "".
std::string unfit(TexelMetric metric, const ResourceRecord& r) {
  if (r.is_buffer) return metric == TexelMetric::exact ? "" : "a buffer is held to 'exact' only";
  const FormatInfo f = *format_info(r.format);
  const KindMeasure measure = kind_info(r.kind).measure;
  if (metric == TexelMetric::angle && (measure != KindMeasure::unit_vector || aspect_channels(f, 0) < 3))
    return "'angle' measures normals, and this is " + std::string(r.kind.name());
  if (metric == TexelMetric::depth && !f.is_depth && measure != KindMeasure::depth)
    return "'depth' measures depth, and this is " + std::string(r.kind.name());
  const bool unorm = f.encoding == ChannelEncoding::unorm8 || f.encoding == ChannelEncoding::srgb8 ||
                     f.encoding == ChannelEncoding::unorm16 || f.encoding == ChannelEncoding::packed_a2b10g10r10;
  if (metric == TexelMetric::codes && !unorm)
    return "'codes' measures UNORM formats, and this is " + std::string(f.name);
  if (metric == TexelMetric::flip && !displayed_colour(r))
    return "'flip' measures displayed (sRGB colour) images, and this is " + std::string(f.name);
  return "";
}

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw ThresholdError(path + ": " + problem);
}

}  // namespace

std::string metric_name(TexelMetric metric) {
  for (const auto& [name, m] : metrics_by_name())
    if (m == metric) return name;
  return "";
}

std::string ThresholdRule::description() const {
  std::string text = metric == TexelMetric::exact ? "exact" : metric_name(metric) + " <= " + number(limit);
  if (allowed > 0) text += ", " + number(100.0 * allowed) + "% of texels allowed over";
  if (!ignore.empty())
    text += ", " + std::to_string(ignore.size()) + " rectangle" + (ignore.size() > 1 ? "s" : "") + " ignored";
  return text;
}

const ThresholdRule* Thresholds::match(const std::string& pass, const ResourceRecord& output) const {
  const std::string name = pass + "/" + output.resource;
  for (const ThresholdRule& rule : rules)
    if (fnmatch(rule.match.c_str(), name.c_str(), 0) == 0 && unfit(rule.metric, output).empty()) return &rule;
  return nullptr;
}

Thresholds read_thresholds(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot read");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    fail(path, std::string("not JSON: ") + e.what());
  }
  if (!json.is_object() || json.size() != 1 || !json.contains("thresholds") || !json["thresholds"].is_array())
    fail(path, "expected {\"thresholds\": [rules]}");
  Thresholds thresholds;
  for (size_t i = 0; i < json["thresholds"].size(); ++i) {
    const nlohmann::json& entry = json["thresholds"][i];
    const std::string where = "rule " + std::to_string(i + 1);
    if (!entry.is_object()) fail(path, where + ": expected an object");
    for (const auto& [key, value] : entry.items())
      if (key != "match" && key != "metric" && key != "limit" && key != "allowed" && key != "ignore")
        fail(path, where + ": unknown key '" + key + "' (match, metric, limit, allowed, ignore)");
    ThresholdRule rule;
    rule.source = path + " " + where;
    if (!entry.contains("match") || !entry["match"].is_string() || entry["match"].get<std::string>().empty())
      fail(path, where + ": 'match' must be a glob on PASS/RESOURCE");
    rule.match = entry["match"];
    if (!entry.contains("metric") || !entry["metric"].is_string() ||
        !metrics_by_name().count(entry["metric"].get<std::string>()))
      fail(path, where + ": 'metric' must be one of exact, abs, rel, angle, depth, codes, flip");
    rule.metric = metrics_by_name().at(entry["metric"]);
    if (rule.metric != TexelMetric::exact) {
      if (!entry.contains("limit") || !entry["limit"].is_number() || !(entry["limit"].get<double>() >= 0) ||
          !std::isfinite(entry["limit"].get<double>()))
        fail(path, where + ": 'limit' must be a finite number >= 0");
      rule.limit = entry["limit"];
    } else if (entry.contains("limit")) {
      fail(path, where + ": 'exact' takes no limit");
    }
    if (entry.contains("allowed")) {
      if (!entry["allowed"].is_number() ||
          !(entry["allowed"].get<double>() >= 0 && entry["allowed"].get<double>() <= 1))
        fail(path, where + ": 'allowed' must be a share of texels in [0, 1]");
      rule.allowed = entry["allowed"];
    }
    if (entry.contains("ignore")) {
      if (!entry["ignore"].is_array()) fail(path, where + ": 'ignore' must be a list of rectangles");
      for (const nlohmann::json& r : entry["ignore"]) {
        IgnoreRect rect;
        const bool ok = r.is_object() && r.size() == 4 && std::all_of(r.begin(), r.end(), [](const nlohmann::json& v) {
                          return v.is_number_unsigned() && v.get<uint64_t>() <= kMaxImageSide;
                        });
        if (!ok || !r.contains("x") || !r.contains("y") || !r.contains("width") || !r.contains("height"))
          fail(path, where + ": a rectangle is {\"x\", \"y\", \"width\", \"height\"} in output pixels");
        rect = {r["x"], r["y"], r["width"], r["height"]};
        if (rect.width == 0 || rect.height == 0) fail(path, where + ": an ignored rectangle is empty");
        rule.ignore.push_back(rect);
      }
    }
    thresholds.rules.push_back(std::move(rule));
  }
  return thresholds;
}

ThresholdCheck check_threshold(const ThresholdRule& rule, const FrameRecord& frame, const ResourceRecord& a,
                               std::span<const uint8_t> a_raw, std::span<const uint8_t> b_raw,
                               std::span<const float> flip_map) {
  return check_threshold(rule, frame, ResourcePair(a, a_raw, a, b_raw), flip_map);
}

ThresholdCheck check_threshold(const ThresholdRule& rule, const FrameRecord& frame, const ResourcePair& pair,
                               std::span<const float> flip_map) {
  const ResourceRecord& a = pair.a;
  ThresholdCheck check;
  check.problem = unfit(rule.metric, a);
  if (!check.problem.empty()) return check;
  if (pair.a_raw.size() != pair.b_raw.size()) {
    check.problem = "the sizes differ";
    return check;
  }
  if (a.is_buffer) {
    check.counted = 1;
    check.over = pair.same_bytes() ? 0 : 1;
    check.worst = check.over ? INFINITY : 0.0;
    check.holds = check.over == 0;
    return check;
  }
  const FormatInfo f = *format_info(a.format);
  const ImageExtent& extent = a.extent;
  std::vector<float> computed_flip;  // the FLIP map of mip 0, layer 0, when the caller had none
  if (rule.metric == TexelMetric::flip && flip_map.empty()) {
    computed_flip = flip_displayed(pair).error;
    flip_map = computed_flip;
  }
  // Per texel the worst over aspects, so depth and stencil count as one texel.
  for (uint32_t mip = 0; mip < extent.mips; ++mip) {
    const uint32_t w = mip_size(extent.width, mip), h = mip_size(extent.height, mip), d = mip_size(extent.depth, mip);
    std::vector<bool> ignored(uint64_t(w) * h, false);
    for (const IgnoreRect& r : rule.ignore)
      for (uint32_t y = 0; y < h; ++y)
        for (uint32_t x = 0; x < w; ++x) {
          const double px = (x + 0.5) * frame.width / w, py = (y + 0.5) * frame.height / h;
          if (px >= r.x && px < double(r.x) + r.width && py >= r.y && py < double(r.y) + r.height)
            ignored[uint64_t(y) * w + x] = true;
        }
    for (uint32_t layer = 0; layer < extent.layers; ++layer) {
      std::vector<double> errors(uint64_t(w) * h * d, 0.0);
      if (rule.metric == TexelMetric::flip && mip == 0 && layer == 0)
        std::copy(flip_map.begin(), flip_map.end(), errors.begin());
      for (uint32_t aspect = 0; aspect < aspect_count(f) && rule.metric != TexelMetric::flip; ++aspect) {
        const uint32_t channels = aspect_channels(f, aspect);
        const std::span<const float> va = pair.a_values().subresource(aspect, mip, layer),
                                     vb = pair.b_values().subresource(aspect, mip, layer);
        for (uint64_t t = 0; t < errors.size(); ++t)
          errors[t] = std::max(errors[t], texel_error(rule.metric, f, aspect, va.data() + t * channels,
                                                      vb.data() + t * channels, channels));
      }
      for (uint64_t t = 0; t < errors.size(); ++t) {
        if (ignored[t % (uint64_t(w) * h)]) continue;
        ++check.counted;
        check.worst = std::max(check.worst, errors[t]);
        check.over += errors[t] > rule.limit;
      }
    }
  }
  check.holds = check.counted == 0 || double(check.over) <= rule.allowed * double(check.counted);
  return check;
}

}  // namespace nightcap
