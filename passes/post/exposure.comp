#version 460
// exposure, in three phases of one pass (each a dispatch, ordered by the pass's storage barrier):
//   0: zero the histogram;
//   1: count every pixel of the lit image into kExposureBins bins of log2 luminance (integer
//      atomics: the counts, hence everything after them, do not depend on execution order);
//   2: one workgroup takes the histogram's mean log2 luminance, adapts the previous frame's
//      value toward it and writes exposure.value.
#include "../frame/types.glsl"
#include "exposure.glsl.h"

layout(local_size_x = kExposureGroupSide, local_size_y = kExposureGroupSide) in;

layout(std140, set = 0, binding = NC_BINDING(frame_constants)) uniform FrameBlock { GpuFrameConstants frame; };
layout(set = 0, binding = NC_BINDING(lit)) uniform sampler2D lit_map;
layout(set = 0, binding = NC_BINDING(exposure_value_previous)) uniform sampler2D previous_exposure;
layout(std430, set = 0, binding = NC_BINDING(exposure_histogram)) buffer Histogram { uint bins[kExposureBins]; };
layout(set = 0, binding = NC_BINDING(exposure_value), rgba32f) uniform writeonly image2D exposure_value;
layout(push_constant) uniform ExposureConstants { NC_BLOCK_MEMBERS(NC_EXPOSURE_CONSTANTS_FIELDS) };

shared uint local_bins[kExposureBins];
shared float weighted[kExposureBins];
shared uint counted[kExposureBins];

float luminance(vec3 c) { return dot(c, vec3(0.2126, 0.7152, 0.0722)); }

// -1 for a pixel that carries no luminance to measure (NaN).
int bin_of(vec3 colour) {
  float l = luminance(colour);
  if (isnan(l)) return -1;
  if (l <= exp2(log2_min)) return 0;
  if (isinf(l)) return int(kExposureBins) - 1;
  float t = (log2(l) - log2_min) / (log2_max - log2_min);
  return int(clamp(floor(t * float(kExposureBins)), 0.0, float(kExposureBins - 1u)));
}

void main() {
  uint lane = gl_LocalInvocationIndex;
  if (phase == 0u) {
    bins[lane] = 0u;
    return;
  }
  if (phase == 1u) {
    local_bins[lane] = 0u;
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    bool counted_here = uniform_pixels > 0u ? p == ivec2(0) : all(lessThan(p, textureSize(lit_map, 0)));
    if (counted_here) {
      int b = bin_of(texelFetch(lit_map, p, 0).rgb);
      if (b >= 0) atomicAdd(local_bins[b], max(uniform_pixels, 1u));
    }
    barrier();
    if (local_bins[lane] != 0u) atomicAdd(bins[lane], local_bins[lane]);
    return;
  }
  // Phase 2: a tree sum in a fixed order, so the result is the same on every run.
  float bin_width = (log2_max - log2_min) / float(kExposureBins);
  counted[lane] = bins[lane];
  weighted[lane] = float(bins[lane]) * (log2_min + (float(lane) + 0.5) * bin_width);
  barrier();
  for (uint stride = kExposureBins / 2u; stride > 0u; stride /= 2u) {
    if (lane < stride) {
      counted[lane] += counted[lane + stride];
      weighted[lane] += weighted[lane + stride];
    }
    barrier();
  }
  if (lane != 0u) return;
  vec4 previous = texelFetch(previous_exposure, ivec2(0), 0);
  bool has_history = previous.x > 0.0;  // the initial value (cleared) is 0
  if (counted[0] == 0u) {
    // Nothing measurable (every pixel NaN): keep the previous value, or leave exposure to the
    // manual setting (0) until something is.
    imageStore(exposure_value, ivec2(0), has_history ? previous : vec4(0.0));
    return;
  }
  float measured = weighted[0] / float(counted[0]);
  float keep = adapt_seconds > 0.0 ? exp(-frame.timing.y / adapt_seconds) : 0.0;
  float adapted = has_history ? mix(measured, previous.y, keep) : measured;
  // Krawczyk, Myszkowski and Seidel 2005: a dark scene keeps a low key and stays dark.
  float mean = exp2(adapted);
  float chosen_key = key > 0.0 ? key : 1.03 - 2.0 / (2.0 + log(mean + 1.0) / log(10.0));
  imageStore(exposure_value, ivec2(0), vec4(chosen_key / mean, adapted, measured, 0.0));
}
