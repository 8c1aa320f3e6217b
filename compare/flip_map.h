// FLIP's error map as a picture a person reads: each pixel's error through the magma colour map,
// as the FLIP authors show theirs (black: no visible difference; light yellow: the largest).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "compare/diff.h"
#include "compare/flip.h"

namespace nightcap {

// sRGB codes of an error in [0, 1] (clamped): piecewise linear through magma's colours at 0, ¼,
// ½, ¾ and 1.
std::array<uint8_t, 3> magma(float error);
// RGBA8 pixels of `flip`'s error map, opaque.
std::vector<uint8_t> flip_map_rgba8(const FlipResult& flip);

// Writes the error map of every output of `diff` that has a FLIP result into `folder` (created
// if needed) as `f<frame>.<pass>.<resource>.flip.png`, each written beside its name and renamed
// into place, and names the file in that output's `flip_map`. Throws ImageError naming a file
// that cannot be written.
void write_flip_maps(CaptureDiff& diff, const std::filesystem::path& folder);

}  // namespace nightcap
