// Comparison of two versions of one resource with a metric that fits what it holds.
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "captures/capture.h"
#include "compare/decoded_image.h"
#include "compare/flip.h"

namespace nightcap {

struct ResourceComparison {
  bool identical = false;  // same bytes
  bool comparable = true;  // same format and size
  // "float", "unorm", "integer (exact)", "angle", "depth + stencil", "buffer fields" (decoded by
  // the recorded schema), "buffer words" (no schema)
  std::string metric;
  std::string note;  // why not comparable
  double max_abs = 0.0;
  double rmse = 0.0;
  double psnr = INFINITY;             // dB; infinite when identical
  double over_threshold_share = 0.0;  // share of texels with any channel over the threshold
  uint64_t differing = 0;             // texels (or words) that differ at all
  uint64_t nan_a = 0, nan_b = 0, inf_a = 0, inf_b = 0;
  double angular_max_deg = 0.0, angular_mean_deg = 0.0;  // normals only
  // Buffers with a schema: where they first differ, e.g. "element 3 model[13]: 1.5 vs 1.25".
  std::string first_difference;
};

// `a` and `b` are raw bytes of the records' resources (format.h's raw layout). Buffers are
// decoded by a's schema where it has one (`differing` then counts elements), else as words.
ResourceComparison compare_resource(const ResourceRecord& a, std::span<const uint8_t> a_raw, const ResourceRecord& b,
                                    std::span<const uint8_t> b_raw);
ResourceComparison compare_resource(const ResourcePair& pair);

// Degrees between two stored normals (0.5n + 0.5: both normal kinds read so as UNORM values);
// NaN where either is not a direction.
double stored_normal_angle_deg(const float* a, const float* b);
// Whole steps of `format`'s encoding between decoded values `a` and `b` of `channel`: sRGB colour
// channels compare as the codes they were stored as.
double code_steps(const FormatInfo& format, uint32_t channel, float a, float b);

// Displayed colour: an sRGB-encoded image of the colour kind (the frame's final picture), which
// FLIP measures as an observer would see it.
bool displayed_colour(const ResourceRecord& r);
// LDR-FLIP between mip 0, layer 0 of two displayed-colour images of the same shape, `a` the
// reference; the error map is per texel of that subimage.
FlipResult flip_displayed(const ResourceRecord& a, std::span<const uint8_t> a_raw, std::span<const uint8_t> b_raw);
FlipResult flip_displayed(const ResourcePair& pair, const FlipOptions& options = {});

// How far `b` is from `a` in the terms of a's comparison contract.
struct ContractCheck {
  bool holds = false;
  // The largest departure, in the contract's unit (bytes for exact, the value for float, codes,
  // degrees, relative depth, words for sets), and the bound it was held to. A buffer is held to
  // a float contract field by field through its schema: float fields within the bound, integer
  // fields and padding exactly.
  double worst = 0.0, bound = 0.0;
  std::string measure;  // what `worst` counts, e.g. "degrees"
};
ContractCheck check_contract(const ComparisonContract& contract, const ResourceRecord& a,
                             std::span<const uint8_t> a_raw, const ResourceRecord& b, std::span<const uint8_t> b_raw);
// The same, reusing compare_resource(pair) that the caller already has.
ContractCheck check_contract(const ComparisonContract& contract, const ResourcePair& pair,
                             const ResourceComparison& shape);

// compare_resource(pair) and check_contract against `contract`, from one decoding of the pair's
// values where the contract measures them (the diff's common case: each image is read once).
struct MeasuredResource {
  ResourceComparison comparison;
  ContractCheck contract;
};
MeasuredResource measure_resource(const ComparisonContract& contract, const ResourcePair& pair);

}  // namespace nightcap
