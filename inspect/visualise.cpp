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

TexelPicture picture_of(const KindInfo& kind, const TexelValues& values, const KindFrame& frame) {
  if (kind.draw) return kind.draw(values, frame);
  const std::vector<double>& v = values.raw;
  return {TexelPicture::Scale::display,
          {v[0], v[std::min<size_t>(1, v.size() - 1)], v[std::min<size_t>(2, v.size() - 1)]}};
}

bool drawn_distance(double d) { return std::isfinite(d) && d > 0; }

}  // namespace

std::optional<DistanceRange> distance_range(const ResourceRecord& record, std::span<const uint8_t> raw,
                                            const FrameRecord& frame, const Subimage& subimage) {
  const SubresourceReader reader(record, raw, subimage.mip, subimage.layer);
  const KindInfo& kind = kind_info(record.kind);
  const KindFrame kind_frame_of_record = kind_frame(frame);
  DistanceRange range{INFINITY, 0};
  TexelValues values;
  for (uint32_t y = 0; y < reader.height(); ++y)
    for (uint32_t x = 0; x < reader.width(); ++x) {
      reader.read(x, y, subimage.slice, values);
      const TexelPicture picture = picture_of(kind, values, kind_frame_of_record);
      // A kind draws all its texels on one scale: the first tells whether it is a distance.
      if (picture.scale != TexelPicture::Scale::distance) return std::nullopt;
      if (!drawn_distance(picture.value[0])) continue;
      range.nearest = std::min(range.nearest, picture.value[0]);
      range.farthest = std::max(range.farthest, picture.value[0]);
    }
  if (range.farthest == 0) return std::nullopt;
  return range;
}

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

Rgba8Image visualise(const ResourceRecord& record, std::span<const uint8_t> raw, const FrameRecord& frame,
                     const Subimage& subimage, VisualAspect aspect, const std::optional<DistanceRange>& shown) {
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
  // Distances and motion are drawn relative to their range in the image: kept per texel for a
  // second pass.
  std::vector<double> distances;              // 0: nothing there
  std::vector<std::array<double, 2>> motion;  // pixels
  std::vector<std::array<double, 3>> relative;
  double nearest = INFINITY, farthest = 0, longest = 0, largest = 0;
  const KindInfo& kind = kind_info(record.kind);
  const KindFrame kind_frame_of_record = kind_frame(frame);
  using Scale = TexelPicture::Scale;

  TexelValues values;
  for (uint32_t y = 0; y < image.height; ++y)
    for (uint32_t x = 0; x < image.width; ++x) {
      const uint64_t i = uint64_t(y) * image.width + x;
      reader.read(x, y, subimage.slice, values);
      if (aspect == VisualAspect::stencil) {
        const uint32_t tag = uint32_t(values.codes.back());
        const std::array<uint8_t, 3> colour = kind.draw_stencil
                                                  ? kind.draw_stencil(tag)
                                                  : std::array<uint8_t, 3>{uint8_t(tag), uint8_t(tag), uint8_t(tag)};
        std::copy(colour.begin(), colour.end(), image.pixels.begin() + 4 * i);
        continue;
      }
      const TexelPicture picture = picture_of(kind, values, kind_frame_of_record);
      const std::array<double, 3>& p = picture.value;
      switch (picture.scale) {
        case Scale::display:
          put(i, p[0], p[1], p[2]);
          break;
        case Scale::light:
          for (int c = 0; c < 3; ++c)
            image.pixels[4 * i + c] = srgb_code(float(std::clamp(std::isnan(p[c]) ? 0.0 : p[c], 0.0, 1.0)));
          break;
        case Scale::distance:
          if (distances.empty()) distances.assign(texels, 0.0);
          if (drawn_distance(p[0])) {
            distances[i] = p[0];
            nearest = std::min(nearest, p[0]);
            farthest = std::max(farthest, p[0]);
          }
          break;
        case Scale::motion:
          if (motion.empty()) motion.resize(texels);
          motion[i] = {p[0], p[1]};
          if (std::isfinite(p[0]) && std::isfinite(p[1])) longest = std::max(longest, std::hypot(p[0], p[1]));
          break;
        case Scale::relative:
          if (relative.empty()) relative.resize(texels);
          relative[i] = p;
          for (double c : p)
            if (std::isfinite(c)) largest = std::max(largest, c);
          break;
      }
    }
  if (!distances.empty()) {
    if (shown) {
      nearest = shown->nearest;
      farthest = shown->farthest;
    }
    const double range = farthest > nearest ? std::log(farthest / nearest) : 1.0;
    for (uint64_t i = 0; i < texels; ++i) {
      const double grey = distances[i] > 0 ? 1.0 - std::log(distances[i] / nearest) / range : 0.0;
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
  if (!relative.empty())
    for (uint64_t i = 0; i < texels; ++i)
      for (int c = 0; c < 3; ++c) {
        const double x = relative[i][c];
        image.pixels[4 * i + c] =
            srgb_code(float(largest > 0 && std::isfinite(x) ? std::clamp(x / largest, 0.0, 1.0) : 0.0));
      }
  return image;
}

}  // namespace nightcap
