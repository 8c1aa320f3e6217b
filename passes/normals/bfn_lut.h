// The best-fit normal lookup table (Kaplanyan 2010), built in code.
//
// A unit normal n, divided by its largest absolute component, becomes w with one component
// ±1 and two minors |u| ≥ |v| in [0, 1]. The table maps (u, v) to the length t ∈ (0, 1] of the
// 8-bit vector round((t·w·0.5 + 0.5)·255) whose normalisation best matches n: the search runs
// over every major code, so each entry is the exact optimum for its direction.
#pragma once

#include <cstdint>
#include <vector>

namespace nightcap {

// size×size entries, row v, column u; u = column/(size-1), v = row/(size-1).
std::vector<uint8_t> build_bfn_lut(uint32_t size);

// The 8-bit code of one component as the pass computes it, and its decoded value.
uint8_t encode_unorm8(float signed_value);
float decode_signed8(uint8_t code);

}  // namespace nightcap
