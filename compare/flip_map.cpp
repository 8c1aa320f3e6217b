#include "compare/flip_map.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "images/images.h"

namespace nightcap {
namespace {

// matplotlib's magma at 0, 0.25, 0.5, 0.75 and 1, in sRGB codes.
constexpr uint8_t kMagma[5][3] = {{0, 0, 4}, {81, 18, 124}, {183, 55, 121}, {252, 137, 97}, {252, 253, 191}};

// A file name part from a pass or resource name: what is not a letter, digit, '.', '_' or '-'
// becomes '_', so that no name leaves the folder.
std::string file_part(const std::string& name) {
  std::string out = name;
  for (char& c : out)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '-')) c = '_';
  return out;
}

}  // namespace

std::array<uint8_t, 3> magma(float error) {
  const float at = std::clamp(std::isnan(error) ? 1.0f : error, 0.0f, 1.0f) * 4.0f;
  const int low = std::min(int(at), 3);
  const float t = at - float(low);
  std::array<uint8_t, 3> rgb;
  for (int c = 0; c < 3; ++c)
    rgb[c] = uint8_t(std::lround(kMagma[low][c] + t * (float(kMagma[low + 1][c]) - float(kMagma[low][c]))));
  return rgb;
}

std::vector<uint8_t> flip_map_rgba8(const FlipResult& flip) {
  std::vector<uint8_t> rgba(flip.error.size() * 4);
  for (size_t i = 0; i < flip.error.size(); ++i) {
    const std::array<uint8_t, 3> rgb = magma(flip.error[i]);
    std::copy(rgb.begin(), rgb.end(), rgba.begin() + 4 * i);
    rgba[4 * i + 3] = 255;
  }
  return rgba;
}

void write_flip_maps(CaptureDiff& diff, const std::filesystem::path& folder) {
  std::error_code error;
  std::filesystem::create_directories(folder, error);
  if (error) throw ImageError(folder.string() + ": cannot create the folder: " + error.message());
  for (FrameDiff& frame : diff.frames)
    for (PassDiff& pass : frame.passes)
      for (OutputDiff& output : pass.outputs) {
        if (!output.flip) continue;
        const std::string name =
            "f" + std::to_string(frame.index) + "." + file_part(pass.name) + "." + file_part(output.resource);
        const std::filesystem::path file = folder / (name + ".flip.png"), partial = folder / (name + ".partial.png");
        write_png(partial, flip_map_rgba8(*output.flip), output.flip->width, output.flip->height);
        std::filesystem::rename(partial, file, error);
        if (error) throw ImageError(file.string() + ": cannot rename into place: " + error.message());
        output.flip_map = file;
      }
}

}  // namespace nightcap
