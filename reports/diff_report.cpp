#include "reports/diff_report.h"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <mutex>
#include <sstream>
#include <tuple>

#include "compare/decoded_image.h"
#include "compare/flip_map.h"
#include "inspect/visualise.h"
#include "passes/core/hash.h"
#include "reports/assets.h"
#include "reports/html.h"
#include "reports/thumbnails.h"

namespace nightcap {
namespace {

namespace fs = std::filesystem;

// The pictures of an output of the diff: an image whose two versions differ in bytes and have
// the same shape.
struct Pictured {
  // Names its files, images/<id>.<view>.png and data/<id>.js: the first 16 hex digits of the
  // content hash of its frame, pass and resource, so the names are the same from run to run
  // (outputs are measured in parallel) and nothing of a name from the capture is in a path.
  std::string id;
  struct Size {
    uint32_t width = 0, height = 0;
  } thumbnail, large;
  uint32_t step = 1;  // the large view takes every step-th texel of each row and column
  double difference_max = 0.0;
  bool first_subresource_only = false;  // the image has more mips, layers or slices than pictured
};

// Every `step`-th texel of every `step`-th row: each pixel of the large view is one texel, so
// the values read out under the pointer are the ones it shows.
Rgba8Image take_texels(const Rgba8Image& picture, uint32_t step) {
  Rgba8Image out;
  out.width = (picture.width + step - 1) / step;
  out.height = (picture.height + step - 1) / step;
  out.pixels.resize(size_t(out.width) * out.height * 4);
  for (uint32_t y = 0; y < out.height; ++y)
    for (uint32_t x = 0; x < out.width; ++x)
      std::copy_n(&picture.pixels[(size_t(y * step) * picture.width + x * step) * 4], 4,
                  &out.pixels[(size_t(y) * out.width + x) * 4]);
  return out;
}

std::string base64(std::span<const uint8_t> bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t n = uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? uint32_t(bytes[i + 1]) << 8 : 0) |
                       (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    text += kDigits[n >> 18];
    text += kDigits[(n >> 12) & 63];
    text += i + 1 < bytes.size() ? kDigits[(n >> 6) & 63] : '=';
    text += i + 2 < bytes.size() ? kDigits[n & 63] : '=';
  }
  return text;
}

// The values of the large view's texels, zlib-compressed (the page inflates them with the
// browser's DecompressionStream("deflate")): as halves (IEEE binary16, little-endian) where
// `half` says they are exact or near enough to read (half-float formats, 8-bit codes), else
// float32.
std::string packed_values(std::span<const float> values, uint32_t width, uint32_t height, uint32_t channels,
                          uint32_t step, bool half) {
  std::vector<uint8_t> taken;
  for (uint32_t y = 0; y < height; y += step)
    for (uint32_t x = 0; x < width; x += step)
      for (uint32_t c = 0; c < channels; ++c) {
        const float v = values[(size_t(y) * width + x) * channels + c];
        if (half) {
          const uint16_t h = float_to_half(v);
          taken.insert(taken.end(), {uint8_t(h & 0xff), uint8_t(h >> 8)});
        } else {
          uint8_t bytes[4];
          std::memcpy(bytes, &v, 4);
          taken.insert(taken.end(), bytes, bytes + 4);
        }
      }
  uLongf size = compressBound(uLong(taken.size()));
  std::vector<uint8_t> packed(size);
  if (compress2(packed.data(), &size, taken.data(), uLong(taken.size()), Z_BEST_SPEED) != Z_OK)
    throw std::runtime_error("zlib could not compress the values of the large view");
  packed.resize(size);
  return base64(packed);
}

// The thumbnail and the large view of one picture.
void write_views(const fs::path& folder, const std::string& stem, const Rgba8Image& picture, bool light, Pictured& p,
                 const DiffReportOptions& options) {
  const Rgba8Image small = shrink(picture, options.thumbnail_side, light);
  write_png(folder / ("images/" + stem + ".png"), small.pixels, small.width, small.height);
  const Rgba8Image large = take_texels(picture, p.step);
  write_png(folder / ("images/" + stem + ".large.png"), large.pixels, large.width, large.height);
  p.thumbnail = {small.width, small.height};
  p.large = {large.width, large.height};
}

// |B − A| per texel (the largest over the channels), on a square-root scale from black (equal)
// to white (the largest difference in the image), so that small differences stay visible;
// where one side is NaN or infinite and the other is not, magenta.
Rgba8Image difference_picture(std::span<const float> a, std::span<const float> b, uint32_t width, uint32_t height,
                              uint32_t channels, double& largest) {
  std::vector<float> difference(size_t(width) * height, 0.0f);
  largest = 0.0;
  for (size_t t = 0; t < difference.size(); ++t) {
    float d = 0.0f;
    for (uint32_t c = 0; c < channels; ++c) {
      const float x = a[t * channels + c], y = b[t * channels + c];
      if (x == y || (std::isnan(x) && std::isnan(y))) continue;
      d = std::isfinite(x) && std::isfinite(y) ? std::max(d, std::abs(y - x)) : INFINITY;
    }
    difference[t] = d;
    if (std::isfinite(d)) largest = std::max(largest, double(d));
  }
  Rgba8Image picture{width, height, std::vector<uint8_t>(difference.size() * 4, 255)};
  for (size_t t = 0; t < difference.size(); ++t) {
    uint8_t* rgba = &picture.pixels[t * 4];
    if (std::isinf(difference[t])) {
      rgba[0] = 255, rgba[1] = 0, rgba[2] = 255;
      continue;
    }
    const uint8_t grey = largest > 0 ? uint8_t(std::lround(255.0 * std::sqrt(difference[t] / largest))) : 0;
    rgba[0] = rgba[1] = rgba[2] = grey;
  }
  return picture;
}

void draw(const FrameRecord& frame_a, const OutputDiff& o, const ResourcePair& pair, Pictured& p,
          const fs::path& folder, const DiffReportOptions& options) {
  const ResourceRecord &a = pair.a, &b = pair.b;
  const uint32_t width = a.extent.width, height = a.extent.height;
  p.step = std::max(1u, (std::max(width, height) + options.large_side - 1) / options.large_side);
  p.first_subresource_only = a.extent.mips > 1 || a.extent.layers > 1 || a.extent.depth > 1;
  const bool light = kind_info(a.kind).light;
  const std::string& id = p.id;
  write_views(folder, id + ".a", visualise(a, pair.a_raw, frame_a, {}, VisualAspect::depth_or_colour), light, p,
              options);
  write_views(folder, id + ".b", visualise(b, pair.b_raw, frame_a, {}, VisualAspect::depth_or_colour), light, p,
              options);
  const FormatInfo format = *format_info(a.format);
  const uint32_t channels = aspect_channels(format, 0);
  const std::span<const float> va = pair.a_values().subresource(0, 0, 0), vb = pair.b_values().subresource(0, 0, 0);
  write_views(folder, id + ".difference", difference_picture(va, vb, width, height, channels, p.difference_max), false,
              p, options);
  if (o.flip) {
    const std::vector<uint8_t> map = flip_map_rgba8(*o.flip);
    write_views(folder, id + ".flip", {width, height, map}, true, p, options);
  }
  const bool half = format.encoding == ChannelEncoding::sfloat16 || format.encoding == ChannelEncoding::unorm8 ||
                    format.encoding == ChannelEncoding::srgb8 || format.encoding == ChannelEncoding::packed_b10g11r11;
  nlohmann::json data = {{"width", p.large.width},
                         {"height", p.large.height},
                         {"step", p.step},
                         {"channels", channels},
                         {"half", half},
                         {"a", packed_values(va, width, height, channels, p.step, half)},
                         {"b", packed_values(vb, width, height, channels, p.step, half)}};
  write_file(folder / ("data/" + id + ".js"), "nightcapReport.values(\"" + id + "\", " + data.dump() + ");\n");
}

std::string metrics_line(const ResourceComparison& c) {
  std::ostringstream text;
  text << c.metric << " · max abs " << format_number(c.max_abs) << " · RMSE " << format_number(c.rmse) << " · PSNR "
       << format_number(c.psnr) << " dB · " << format_number(100.0 * c.over_threshold_share, 3)
       << " % of texels over threshold · NaN " << c.nan_a << "/" << c.nan_b << " · Inf " << c.inf_a << "/" << c.inf_b;
  if (c.metric == "angle")
    text << " · angle max " << format_number(c.angular_max_deg) << "°, mean " << format_number(c.angular_mean_deg)
         << "°";
  return text.str();
}

// One picture of an output: its thumbnail, opened large on a click.
void view(std::ostream& html, const Pictured& p, const std::string& name, const std::string& caption) {
  const std::string stem = "images/" + p.id + "." + name;
  html << "<figure class=\"view\"><img src=\"" << stem << ".png\" width=\"" << p.thumbnail.width << "\" height=\""
       << p.thumbnail.height << "\" data-output=\"" << p.id << "\" data-view=\"" << name << "\" alt=\""
       << escape_markup(caption) << "\"><figcaption>" << caption << "</figcaption></figure>\n";
}

void output_card(std::ostream& html, const std::string& pass, const OutputDiff& o, const Pictured* p, bool golden) {
  html << "<section class=\"output" << (o.beyond ? " beyond" : " within") << "\" data-output-name=\""
       << escape_markup(pass + "/" + o.resource) << "\">\n<h4>" << escape_markup(pass) << " / "
       << escape_markup(o.resource) << " <span class=\"verdict\">" << (o.beyond ? "beyond" : "within")
       << "</span></h4>\n";
  if (o.only_in_one)
    html << "<p>" << (golden ? (o.missing == "output" ? "output missing" : "golden missing") : "only in one capture")
         << "</p>\n";
  else if (!o.comparison.comparable)
    html << "<p>not comparable: " << escape_markup(o.comparison.note) << "</p>\n";
  else
    html << "<p class=\"metrics\">" << escape_markup(metrics_line(o.comparison)) << "</p>\n";
  if (!o.held_to.empty()) html << "<p class=\"held-to\">held to " << escape_markup(o.held_to) << "</p>\n";
  if (o.flip)
    html << "<p class=\"flip\">FLIP mean " << format_number(o.flip->mean) << ", max " << format_number(o.flip->max)
         << ", " << format_number(100.0 * o.flip->over_threshold_share, 3) << " % of pixels over 0.1</p>\n";
  if (!o.comparison.first_difference.empty())
    html << "<p>first difference: " << escape_markup(o.comparison.first_difference) << "</p>\n";
  if (p) {
    if (p->first_subresource_only)
      html << "<p class=\"metrics\">pictured: mip 0, layer 0, slice 0; the metrics cover every subresource</p>\n";
    html << "<div class=\"views\">\n"
         << "<figure class=\"view swap\"><div class=\"stack\"><img src=\"images/" << p->id << ".b.png\" width=\""
         << p->thumbnail.width << "\" height=\"" << p->thumbnail.height << "\" data-output=\"" << p->id
         << "\" data-view=\"b\" alt=\"new\"><img class=\"reference\" src=\"images/" << p->id << ".a.png\" width=\""
         << p->thumbnail.width << "\" height=\"" << p->thumbnail.height << "\" data-output=\"" << p->id
         << "\" data-view=\"a\" alt=\"reference\"></div><figcaption>new (B); the reference while the pointer is "
            "over it</figcaption></figure>\n";
    view(html, *p, "a", "reference (A)");
    view(html, *p, "difference",
         "|B − A|, square-root scale, white = " + escape_markup(format_number(p->difference_max)));
    if (o.flip) view(html, *p, "flip", "FLIP error (magma: black none, yellow 1)");
    html << "</div>\n";
  }
  html << "</section>\n";
}

}  // namespace

CaptureDiff write_diff_report(const Capture& a, const Capture& b, DiffOptions diff_options, const fs::path& folder,
                              const DiffReportOptions& options) {
  start_report_folder(folder);
  fs::create_directories(folder / "images");
  fs::create_directories(folder / "data");

  // Pictures are drawn as the diff measures each output, from the versions it has loaded.
  using Key = std::tuple<uint32_t, std::string, std::string>;  // frame, pass, resource
  std::map<Key, Pictured> pictured;
  std::mutex pictured_mutex;
  diff_options.on_measured = [&](const FrameRecord& frame_a, const std::string& pass, const OutputDiff& o,
                                 const ResourcePair& pair) {
    if (!o.comparison.comparable || pair.a.is_buffer || !pair.same_shape()) return;
    const std::string key = std::to_string(frame_a.index) + '\0' + pass + '\0' + o.resource;
    const std::string id = content_hash({reinterpret_cast<const uint8_t*>(key.data()), key.size()}).substr(0, 16);
    Pictured* p;
    {
      const std::lock_guard lock(pictured_mutex);
      p = &pictured[{frame_a.index, pass, o.resource}];
      p->id = id;
    }
    draw(frame_a, o, pair, *p, folder, options);
  };
  const CaptureDiff diff = diff_captures(a, b, diff_options);
  write_file(folder / "report.css", report_stylesheet());
  write_file(folder / "report.js", report_script());

  const std::string name_a = diff.golden ? "golden" : a.folder().filename().string();
  const std::string name_b = b.folder().filename().string();
  size_t within = 0, beyond = 0;
  for (const FrameDiff& f : diff.frames)
    for (const PassDiff& p : f.passes)
      for (const OutputDiff& o : p.outputs) (o.beyond ? beyond : within) += 1;
  std::ostringstream html;
  html << page_start("nightcap diff: " + name_a + " → " + name_b, true) << "<header>\n<h1>Diff of <span class=\"name\">"
       << escape_markup(name_a) << "</span> (reference, A) and <span class=\"name\">" << escape_markup(name_b)
       << "</span> (new, B)</h1>\n<p class=\"first-divergence\">";
  if (diff.first_divergence)
    html << "First divergence: <a href=\"#f" << diff.first_divergence->first << "-"
         << escape_markup(diff.first_divergence->second) << "\">" << escape_markup(diff.first_divergence->second)
         << "</a>, frame " << diff.first_divergence->first;
  else
    html << (diff.identical ? "The captures are identical." : "No pass diverged on its own.");
  html << "</p>\n<p class=\"summary\">" << within << " outputs within what they were held to, " << beyond
       << " beyond</p>\n";
  for (const std::string& note : diff.notes) html << "<p class=\"note\">" << escape_markup(note) << "</p>\n";
  html << "</header>\n<main>\n";
  for (const FrameDiff& f : diff.frames) {
    html << "<section class=\"frame\"><h2>Frame " << f.index << "</h2>\n<table class=\"passes\"><tr><th>pass</th>"
         << "<th>status</th><th>outputs beyond</th></tr>\n";
    for (const PassDiff& p : f.passes) {
      size_t over = 0;
      for (const OutputDiff& o : p.outputs) over += o.beyond;
      html << "<tr class=\"" << status_name(p.status, diff.golden) << "\"><td>" << escape_markup(p.name) << "</td><td>"
           << status_name(p.status, diff.golden) << "</td><td>" << over << " of " << p.outputs.size() << "</td></tr>\n";
    }
    html << "</table>\n";
    for (const PassDiff& p : f.passes) {
      const bool differs =
          std::any_of(p.outputs.begin(), p.outputs.end(), [](const OutputDiff& o) { return !o.comparison.identical; });
      html << "<section class=\"pass\" id=\"f" << f.index << "-" << escape_markup(p.name) << "\" data-pass=\""
           << escape_markup(p.name) << "\"><h3>" << escape_markup(p.name) << " <span class=\"status\">"
           << status_name(p.status, diff.golden) << "</span></h3>\n";
      if (p.isolation) html << "<p>" << escape_markup(isolation_summary(*p.isolation)) << "</p>\n";
      if (!differs) html << "<p class=\"status\">every output identical</p>\n";
      for (const OutputDiff& o : p.outputs) {
        if (o.comparison.identical) continue;
        const auto it = pictured.find({f.index, p.name, o.resource});
        output_card(html, p.name, o, it == pictured.end() ? nullptr : &it->second, diff.golden);
      }
      html << "</section>\n";
    }
    html << "</section>\n";
  }
  html << "</main>\n<div id=\"viewer\" hidden></div>\n</body>\n</html>\n";
  publish_page(folder, html.str());
  return diff;
}

}  // namespace nightcap
