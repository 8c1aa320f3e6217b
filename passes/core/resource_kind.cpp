#include "passes/core/resource_kind.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace nightcap {
namespace {

double rec709_luminance(double r, double g, double b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

nlohmann::ordered_json first_three(const std::vector<double>& v) {
  return std::vector<double>(v.begin(), v.begin() + std::min<size_t>(3, v.size()));
}

// Channel c of a texel, the last channel standing in for missing ones (one channel: grey).
double channel(const std::vector<double>& v, size_t c) { return v[std::min(c, v.size() - 1)]; }

std::vector<KindInfo> core_kinds() {
  std::vector<KindInfo> core;
  core.push_back(
      {.kind = kinds::colour,
       .describe =
           [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
             out["rgb_linear"] = first_three(t.raw);
             if (t.raw.size() > 3) out["alpha"] = t.raw[3];
           },
       .draw =
           [](const TexelValues& t, const KindFrame&) {
             return TexelPicture{TexelPicture::Scale::light, {channel(t.raw, 0), channel(t.raw, 1), channel(t.raw, 2)}};
           },
       .light = true});
  core.push_back({.kind = kinds::hdr_colour,
                  .describe =
                      [](const TexelValues& t, const KindFrame&, nlohmann::ordered_json& out) {
                        out["rgb"] = first_three(t.raw);
                        if (t.raw.size() >= 3) out["luminance"] = rec709_luminance(t.raw[0], t.raw[1], t.raw[2]);
                      },
                  // Reinhard x / (1 + x) per channel
                  .draw =
                      [](const TexelValues& t, const KindFrame&) {
                        TexelPicture picture{TexelPicture::Scale::light, {}};
                        for (size_t c = 0; c < 3; ++c) {
                          const double x = channel(t.raw, c);
                          picture.value[c] = x > 0 ? x / (1.0 + x) : 0.0;
                        }
                        return picture;
                      },
                  .light = true});
  core.push_back({.kind = kinds::mask,
                  .describe = [](const TexelValues& t, const KindFrame&,
                                 nlohmann::ordered_json& out) { out["masked"] = t.codes.at(0) != 0; },
                  .draw =
                      [](const TexelValues& t, const KindFrame&) {
                        const double shown = t.codes.at(0) != 0 ? 1.0 : 0.0;
                        return TexelPicture{TexelPicture::Scale::display, {shown, shown, shown}};
                      }});
  core.push_back({.kind = kinds::linear_depth,
                  .describe = [](const TexelValues& t, const KindFrame&,
                                 nlohmann::ordered_json& out) { out["linear_m"] = t.raw[0]; },
                  // The sky (nothing drawn) is a far finite depth, 1e6 m by default (depth.convert's
                  // sky_depth), clamped at half precision to its largest finite value: drawn as
                  // nothing there, so that it does not squeeze the surfaces into one grey.
                  .draw =
                      [](const TexelValues& t, const KindFrame&) {
                        const double shown = t.raw[0] < 65504.0 ? t.raw[0] : 0.0;
                        return TexelPicture{TexelPicture::Scale::distance, {shown, 0, 0}};
                      },
                  .measure = KindMeasure::depth});
  // Their raw values are what they hold; none lies over the output.
  for (ResourceKind kind : {kinds::lookup_table, kinds::texture, kinds::buffer, kinds::draw_list})
    core.push_back({.kind = kind, .over_output = false});
  return core;
}

std::map<std::string, KindInfo, std::less<>>& registry() {
  static std::map<std::string, KindInfo, std::less<>> kinds = [] {
    std::map<std::string, KindInfo, std::less<>> core;
    for (KindInfo& info : core_kinds()) core.emplace(std::string(info.kind.name()), std::move(info));
    return core;
  }();
  return kinds;
}

}  // namespace

void describe_stored_normal(const std::array<double, 3>& n, nlohmann::ordered_json& out) {
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  out["normal"] = length == 0.0 ? nlohmann::ordered_json(nullptr)
                                : nlohmann::ordered_json{n[0] / length, n[1] / length, n[2] / length};
  out["stored_length"] = length;
}

TexelPicture stored_normal_picture(const std::array<double, 3>& n) {
  const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (length == 0.0) return TexelPicture{};
  return TexelPicture{TexelPicture::Scale::display,
                      {0.5 * n[0] / length + 0.5, 0.5 * n[1] / length + 0.5, 0.5 * n[2] / length + 0.5}};
}

void register_kind(KindInfo info) {
  const std::string name(info.kind.name());
  if (name.empty()) throw std::logic_error("a resource kind needs a name");
  if (!registry().emplace(name, std::move(info)).second)
    throw std::logic_error("resource kind '" + name + "' is registered twice");
}

std::optional<ResourceKind> kind_by_name(std::string_view name) {
  const auto it = registry().find(name);
  if (it == registry().end()) return std::nullopt;
  return it->second.kind;
}

const KindInfo& kind_info(ResourceKind kind) {
  const auto it = registry().find(kind.name());
  if (it == registry().end())
    throw std::logic_error("resource kind '" + std::string(kind.name()) +
                           "' is declared but not registered (passes/core/resource_kind.h)");
  return it->second;
}

std::vector<ResourceKind> registered_kinds() {
  std::vector<ResourceKind> all;
  for (const auto& [name, info] : registry()) all.push_back(info.kind);
  return all;
}

}  // namespace nightcap
