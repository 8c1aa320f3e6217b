#include "inspect/visualise.h"

#include <algorithm>
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
  const uint32_t mip = subimage.mip;
  const FormatInfo format = *format_info(record.format);
  if (aspect == VisualAspect::stencil && !format.has_stencil) throw InspectError(record.resource + " has no stencil");
  Rgba8Image image;
  image.width = mip_size(record.extent.width, mip);
  image.height = mip_size(record.extent.height, mip);
  const uint64_t texels = uint64_t(image.width) * image.height;
  image.pixels.assign(texels * 4, 255);
  std::vector<TexelValues> values(texels);
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x)
      values[uint64_t(y) * image.width + x] = read_texel(record, raw, {x, y, mip, subimage.layer, subimage.slice});
  auto put = [&](uint64_t i, double r, double g, double b) {
    image.pixels[4 * i] = to_code(r);
    image.pixels[4 * i + 1] = to_code(g);
    image.pixels[4 * i + 2] = to_code(b);
  };

  if (aspect == VisualAspect::stencil) {
    for (uint64_t i = 0; i < texels; ++i) {
      const auto colour = stencil_colour(uint32_t(values[i].codes.back()));
      std::copy(colour.begin(), colour.end(), image.pixels.begin() + 4 * i);
    }
    return image;
  }
  switch (record.kind) {
    case ResourceKind::normal:
    case ResourceKind::packed_normal:
      for (uint64_t i = 0; i < texels; ++i) {
        const std::array<double, 3> n = *stored_normal(record.kind, values[i]);
        const double length = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (length == 0.0)
          put(i, 0, 0, 0);
        else
          put(i, 0.5 * n[0] / length + 0.5, 0.5 * n[1] / length + 0.5, 0.5 * n[2] / length + 0.5);
      }
      return image;
    case ResourceKind::depth_stencil:
    case ResourceKind::linear_depth:
    case ResourceKind::depth_minmax: {
      std::vector<double> metres(texels, 0.0);  // 0: nothing drawn
      for (uint64_t i = 0; i < texels; ++i) {
        const double v = values[i].raw[0];  // device depth, metres, or the pyramid's min
        const std::optional<double> m =
            record.kind == ResourceKind::depth_stencil ? linear_metres(v, frame) : std::optional<double>(v);
        if (m && std::isfinite(*m) && *m > 0) metres[i] = *m;
      }
      double nearest = INFINITY, farthest = 0;
      for (double m : metres)
        if (m > 0) nearest = std::min(nearest, m), farthest = std::max(farthest, m);
      const double range = farthest > nearest ? std::log(farthest / nearest) : 1.0;
      for (uint64_t i = 0; i < texels; ++i) {
        const double grey = metres[i] > 0 ? 1.0 - std::log(metres[i] / nearest) / range : 0.0;
        put(i, grey, grey, grey);
      }
      return image;
    }
    case ResourceKind::motion: {
      double longest = 0;
      std::vector<std::array<double, 2>> motion(texels);
      for (uint64_t i = 0; i < texels; ++i) {
        motion[i] = motion_pixels(values[i].raw[0], values[i].raw[1], frame);
        if (std::isfinite(motion[i][0]) && std::isfinite(motion[i][1]))
          longest = std::max(longest, std::hypot(motion[i][0], motion[i][1]));
      }
      for (uint64_t i = 0; i < texels; ++i) {
        const double length = std::hypot(motion[i][0], motion[i][1]);
        const auto rgb = longest > 0 && std::isfinite(length)
                             ? wheel(std::atan2(motion[i][1], motion[i][0]) / (2 * M_PI), length / longest)
                             : std::array<double, 3>{0, 0, 0};
        put(i, rgb[0], rgb[1], rgb[2]);
      }
      return image;
    }
    case ResourceKind::hdr_colour:
    case ResourceKind::colour:
      for (uint64_t i = 0; i < texels; ++i) {
        const std::vector<double>& v = values[i].raw;
        double rgb[3];
        for (int c = 0; c < 3; ++c) {
          const double x = v[std::min<size_t>(c, v.size() - 1)];
          const double shown = record.kind == ResourceKind::hdr_colour ? (x > 0 ? x / (1.0 + x) : 0.0) : x;
          rgb[c] = linear_to_srgb(float(std::clamp(std::isnan(shown) ? 0.0 : shown, 0.0, 1.0)));
        }
        put(i, rgb[0], rgb[1], rgb[2]);
      }
      return image;
    case ResourceKind::material:
    case ResourceKind::lookup_table:
    case ResourceKind::texture:
    case ResourceKind::buffer:
    case ResourceKind::draw_list:
      for (uint64_t i = 0; i < texels; ++i) {
        const std::vector<double>& v = values[i].raw;
        put(i, v[0], v[std::min<size_t>(1, v.size() - 1)], v[std::min<size_t>(2, v.size() - 1)]);
      }
      return image;
  }
  return image;
}

}  // namespace nightcap
