// Thresholds kept as data (`nightcap diff --thresholds FILE`): rules matched by glob on
// "PASS/RESOURCE", each holding every texel to a limit on one metric while allowing a share of
// texels over it and leaving rectangles of the output out. A rule replaces the contract the
// capture recorded for the outputs it matches.
//
//   {"thresholds": [
//     {"match": "lighting.*/*", "metric": "rel", "limit": 0.01, "allowed": 0.001,
//      "ignore": [{"x": 0, "y": 0, "width": 64, "height": 32}]}
//   ]}
//
// An output is held to the first rule whose glob matches it and whose metric can measure it
// (`angle` normals, `depth` depth, `codes` UNORM formats, buffers `exact` only), so that "*" rules
// can follow specific ones; an output no rule fits keeps its recorded contract.
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "captures/capture.h"
#include "compare/decoded_image.h"

namespace nightcap {

// A thresholds file that cannot be used: the message names the file and the problem.
struct ThresholdError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// What one texel's error is, the largest over its channels; a NaN on one side only is an
// infinite error, NaN on both sides none.
enum class TexelMetric {
  exact,  // any difference (stencil included) is infinite
  abs,    // |b − a|
  rel,    // |b − a| / max(|a|, 1e-6): HDR colour
  angle,  // degrees between the decoded normals (normal and packed-normal kinds)
  depth,  // relative linear depth: reversed-Z device depth d is znear / distance, so |a / b − 1|
  codes,  // whole steps of a UNORM or sRGB encoding
  flip,   // LDR-FLIP's per-pixel error, in [0, 1], of displayed (sRGB colour) images
};
std::string metric_name(TexelMetric metric);

struct IgnoreRect {
  uint32_t x = 0, y = 0, width = 0, height = 0;  // output pixels
};

struct ThresholdRule {
  std::string match;  // glob (fnmatch) on "PASS/RESOURCE"
  TexelMetric metric = TexelMetric::abs;
  double limit = 0.0;
  double allowed = 0.0;  // share of the counted texels that may exceed the limit
  std::vector<IgnoreRect> ignore;
  // Where it came from, for every result held to it: "FILE rule N".
  std::string source;

  // One line: "rel <= 0.01, 0.1% of texels allowed over, 1 rectangle ignored".
  std::string description() const;
};

struct Thresholds {
  std::vector<ThresholdRule> rules;
  const ThresholdRule* match(const std::string& pass, const ResourceRecord& output) const;
};

// Throws ThresholdError naming `path` for unreadable files, malformed JSON, unknown keys or
// metrics, negative limits, shares outside [0, 1] and empty rectangles.
Thresholds read_thresholds(const std::string& path);

struct ThresholdCheck {
  bool holds = false;
  uint64_t counted = 0, over = 0;  // texels outside the ignored rectangles, and those over the limit
  double worst = 0.0;              // the largest texel error counted
  std::string problem;             // why the rule cannot measure this output (then it does not hold)
};

// Every texel of every subresource of two same-shaped images; a texel is ignored when the output
// pixel under its centre lies in one of the rule's rectangles. Buffers are compared by bytes.
// `flip_map`: flip_displayed(a, a_raw, b_raw).error where the caller has it already; the `flip`
// metric computes it otherwise.
ThresholdCheck check_threshold(const ThresholdRule& rule, const FrameRecord& frame, const ResourceRecord& a,
                               std::span<const uint8_t> a_raw, std::span<const uint8_t> b_raw,
                               std::span<const float> flip_map = {});
ThresholdCheck check_threshold(const ThresholdRule& rule, const FrameRecord& frame, const ResourcePair& pair,
                               std::span<const float> flip_map = {});

}  // namespace nightcap
