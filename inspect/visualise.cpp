#include "inspect/visualise.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <vector>

#include "inspect/decode.h"

namespace nightcap {

namespace {

uint8_t to_code(double v) { return uint8_t(std::lround(std::clamp(std::isnan(v) ? 0.0 : v, 0.0, 1.0) * 255.0)); }

// HSV with full saturation scaled by `amount`, hue in turns.
std::array<double, 3> wheel(double hue, double amount) {
  const double h = (hue - std::floor(hue)) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  std::array<double, 3> rgb{};
  switch (int(h) % 6) {
    case 0:
      rgb = {1, x, 0};
      break;
    case 1:
      rgb = {x, 1, 0};
      break;
    case 2:
      rgb = {0, 1, x};
      break;
    case 3:
      rgb = {0, x, 1};
      break;
    case 4:
      rgb = {x, 0, 1};
      break;
    default:
      rgb = {1, 0, x};
      break;
  }
  for (double& c : rgb) c *= amount;
  return rgb;
}

}  // namespace

uint8_t srgb_code(float x) {
  static const std::array<float, 256> first = [] {
    std::array<float, 256> t{};
    for (uint32_t code = 1; code < 256; ++code) {
      uint32_t low = 0, high = std::bit_cast<uint32_t>(1.0f);
      while (low < high) {
        const uint32_t middle = low + (high - low) / 2;
        if (to_code(linear_to_srgb(std::bit_cast<float>(middle))) >= code)
          high = middle;
        else
          low = middle + 1;
      }
      t[code] = std::bit_cast<float>(low);
    }
    return t;
  }();
  // The code at the start of each 1/4096 of [0, 1]; sRGB's steepest slope, 12.92 · 255 codes
  // per unit near 0, puts at most one more code's start inside such a step.
  static const std::array<uint8_t, 4096> at_step = [] {
    std::array<uint8_t, 4096> codes{};
    for (uint32_t step = 0; step < 4096; ++step)
      codes[step] =
          uint8_t(std::upper_bound(first.begin() + 1, first.end(), float(step) / 4096.0f) - (first.begin() + 1));
    return codes;
  }();
  const uint8_t code = at_step[std::min(4095u, uint32_t(x * 4096.0f))];
  return code < 255 && x >= first[code + 1] ? code + 1 : code;
}

std::array<uint8_t, 3> stencil_colour(uint32_t stencil) {
  const std::string name = stencil_class_name(stencil);
  std::array<uint8_t, 3> colour = name == "plain"     ? std::array<uint8_t, 3>{0, 0, 0}
                                  : name == "road"    ? std::array<uint8_t, 3>{110, 110, 110}
                                  : name == "body"    ? std::array<uint8_t, 3>{200, 150, 120}
                                  : name == "face"    ? std::array<uint8_t, 3>{240, 190, 160}
                                  : name == "vehicle" ? std::array<uint8_t, 3>{40, 90, 220}
                                  : name == "hair"    ? std::array<uint8_t, 3>{110, 70, 30}
                                  : name == "foliage" ? std::array<uint8_t, 3>{40, 170, 60}
                                                      : std::array<uint8_t, 3>{255, 0, 255};
  if (stencil & 0x02u)
    for (uint8_t& c : colour) c = uint8_t(std::min(255, c + 60));
  return colour;
}

Rgba8Image visualise(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                     const Subimage& subimage, VisualAspect aspect) {
  const FormatInfo format = *format_info(record.format);
  if (aspect == VisualAspect::stencil && !format.has_stencil) throw InspectError(record.resource + " has no stencil");
  const SubresourceReader reader(record, raw, subimage.mip, subimage.layer);
  Rgba8Image image;
  image.width = reader.width();
  image.height = reader.height();
  const uint64_t texels = uint64_t(image.width) * image.height;
  image.pixels.assign(texels * 4, 255);
  auto put = [&](uint64_t i, double r, double g, double b) {
    image.pixels[4 * i] = to_code(r);
    image.pixels[4 * i + 1] = to_code(g);
    image.pixels[4 * i + 2] = to_code(b);
  };
  // Depth and motion are drawn relative to their range in the image: kept per texel for a
  // second pass.
  std::vector<double> metres;                 // 0: nothing drawn
  std::vector<std::array<double, 2>> motion;  // pixels
  double nearest = INFINITY, farthest = 0, longest = 0;
  const bool depth = record.kind == ResourceKind::depth_stencil || record.kind == ResourceKind::linear_depth ||
                     record.kind == ResourceKind::depth_minmax;
  if (aspect != VisualAspect::stencil && depth) metres.assign(texels, 0.0);
  if (aspect != VisualAspect::stencil && record.kind == ResourceKind::motion) motion.resize(texels);

  TexelValues values;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const uint64_t i = uint64_t(y) * image.width + x;
      reader.read(x, y, subimage.slice, values);
      const std::vector<double>& v = values.raw;
      if (aspect == VisualAspect::stencil) {
        const auto colour = stencil_colour(uint32_t(values.codes.back()));
        std::copy(colour.begin(), colour.end(), image.pixels.begin() + 4 * i);
        continue;
      }
      switch (record.kind) {
        case ResourceKind::normal:
        case ResourceKind::packed_normal: {
          const std::array<double, 3> n = *stored_normal(record.kind, values);
          const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
          if (length == 0.0)
            put(i, 0, 0, 0);
          else
            put(i, 0.5 * n[0] / length + 0.5, 0.5 * n[1] / length + 0.5, 0.5 * n[2] / length + 0.5);
          break;
        }
        case ResourceKind::depth_stencil:
        case ResourceKind::linear_depth:
        case ResourceKind::depth_minmax: {
          // device depth, metres, or the pyramid's min
          const std::optional<double> m =
              record.kind == ResourceKind::depth_stencil ? linear_metres(v[0], frame) : std::optional<double>(v[0]);
          if (m && std::isfinite(*m) && *m > 0) {
            metres[i] = *m;
            nearest = std::min(nearest, *m);
            farthest = std::max(farthest, *m);
          }
          break;
        }
        case ResourceKind::stencil: {
          const auto colour = stencil_colour(uint32_t(values.codes.at(0)));
          std::copy(colour.begin(), colour.end(), image.pixels.begin() + 4 * i);
          break;
        }
        case ResourceKind::mask: {
          const double shown = values.codes.at(0) != 0 ? 1.0 : 0.0;
          put(i, shown, shown, shown);
          break;
        }
        case ResourceKind::motion:
          motion[i] = motion_pixels(v[0], v[1], frame);
          if (std::isfinite(motion[i][0]) && std::isfinite(motion[i][1]))
            longest = std::max(longest, std::hypot(motion[i][0], motion[i][1]));
          break;
        case ResourceKind::hdr_colour:
        case ResourceKind::colour:
          for (int c = 0; c < 3; ++c) {
            const double value = v[std::min<size_t>(c, v.size() - 1)];
            const double shown =
                record.kind == ResourceKind::hdr_colour ? (value > 0 ? value / (1.0 + value) : 0.0) : value;
            image.pixels[4 * i + c] = srgb_code(float(std::clamp(std::isnan(shown) ? 0.0 : shown, 0.0, 1.0)));
          }
          break;
        case ResourceKind::light_clusters: {  // the count, so a 1-light froxel shows
          const double count = double(values.codes.at(1));
          put(i, count / (count + 8), count / (count + 8), count / (count + 8));
          break;
        }
        case ResourceKind::material:
        case ResourceKind::lookup_table:
        case ResourceKind::texture:
        case ResourceKind::buffer:
        case ResourceKind::draw_list:
          put(i, v[0], v[std::min<size_t>(1, v.size() - 1)], v[std::min<size_t>(2, v.size() - 1)]);
          break;
      }
    }
  if (!metres.empty()) {
    const double range = farthest > nearest ? std::log(farthest / nearest) : 1.0;
    for (uint64_t i = 0; i < texels; ++i) {
      const double grey = metres[i] > 0 ? 1.0 - std::log(metres[i] / nearest) / range : 0.0;
      put(i, grey, grey, grey);
    }
  }
  if (!motion.empty())
    for (uint64_t i = 0; i < texels; ++i) {
      const double length = std::hypot(motion[i][0], motion[i][1]);
      const auto rgb = longest > 0 && std::isfinite(length)
                           ? wheel(std::atan2(motion[i][1], motion[i][0]) / (2 * M_PI), length / longest)
                           : std::array<double, 3>{0, 0, 0};
      put(i, rgb[0], rgb[1], rgb[2]);
    }
  return image;
}

}  // namespace nightcap
