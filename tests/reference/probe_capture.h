// A reflection probe's capture for the tests and the benchmark of probes.convert: a street-like
// environment at night, as probes.light would leave it (a cube of RGBA16F faces with their mip
// chain of 2×2 means), its level 0 decoded for the references of ibl_reference.h, and the
// inputs that run probes.convert on it alone.
#pragma once

#include <glm/glm.hpp>
#include <glm/gtc/packing.hpp>

#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "passes/core/format.h"
#include "passes/core/isolated.h"
#include "passes/frame/gpu_types.h"
#include "passes/probes/paraboloid.glsl.h"
#include "passes/probes/plan.h"
#include "tests/reference/ibl_reference.h"

namespace nightcap::reference {

// The format of probes.faces and probes.array.
inline constexpr VkFormat kHalf4 = VK_FORMAT_R16G16B16A16_SFLOAT;

// A street at night seen from its middle: a blue sky above, a dark ground below and, between,
// eight columns of four rows of bright windows around the horizon.
inline dvec3 environment(const dvec3& d) {
  if (d.y < -0.05) return dvec3(0.05, 0.045, 0.04);
  const double azimuth = std::atan2(d.z, d.x) / (2 * std::numbers::pi) + 0.5;
  const bool window = d.y < 0.6 && std::fmod(azimuth * 8.0, 1.0) < 0.35 && std::fmod((d.y + 0.05) * 6.0, 1.0) < 0.45;
  const dvec3 sky = dvec3(0.1, 0.15, 0.3) * (0.3 + std::max(d.y, 0.0));
  return window ? sky + dvec3(4.0, 3.0, 1.8) : sky;
}

inline uint32_t full_mips(uint32_t side) { return uint32_t(std::bit_width(side)); }

inline void put_half4(std::vector<uint8_t>& bytes, uint64_t offset, const dvec3& c) {
  const uint16_t h[4] = {glm::packHalf1x16(float(c.x)), glm::packHalf1x16(float(c.y)), glm::packHalf1x16(float(c.z)),
                         glm::packHalf1x16(1.0f)};
  std::memcpy(bytes.data() + offset, h, sizeof h);
}

inline dvec3 half4_at(const std::vector<uint8_t>& bytes, uint64_t offset) {
  uint16_t h[4];
  std::memcpy(h, bytes.data() + offset, sizeof h);
  return {glm::unpackHalf1x16(h[0]), glm::unpackHalf1x16(h[1]), glm::unpackHalf1x16(h[2])};
}

// A capture as probes.light leaves it: one cube of `side` texels a face, level 0 the environment at
// each texel's centre, each later level the mean of the 2×2 texels above it.
struct ProbeCapture {
  ImageExtent extent;
  std::vector<uint8_t> bytes;
  reference::CubeLevel level0;
};

inline ProbeCapture synthetic_capture(uint32_t side) {
  ProbeCapture c;
  c.extent = ImageExtent{side, side, 1, full_mips(side), 6};
  const FormatInfo f = *format_info(kHalf4);
  c.bytes.assign(raw_image_bytes(f, c.extent), 0);
  c.level0.side = side;
  c.level0.texels.resize(6 * side * side);
  std::vector<dvec3> above;
  for (uint32_t mip = 0; mip < c.extent.mips; ++mip) {
    const uint32_t level_side = mip_size(side, mip);
    std::vector<dvec3> level(6 * level_side * level_side);
    for (uint32_t face = 0; face < 6; ++face)
      for (uint32_t y = 0; y < level_side; ++y)
        for (uint32_t x = 0; x < level_side; ++x) {
          dvec3 v;
          if (mip == 0) {
            v = environment(reference::texel_direction(face, x, y, level_side));
          } else {
            const uint32_t s2 = level_side * 2;
            auto at = [&](uint32_t xx, uint32_t yy) { return above[(face * s2 + yy) * s2 + xx]; };
            v = 0.25 * (at(2 * x, 2 * y) + at(2 * x + 1, 2 * y) + at(2 * x, 2 * y + 1) + at(2 * x + 1, 2 * y + 1));
          }
          // Stored as half floats, and read back so the references see what the GPU reads.
          put_half4(c.bytes, raw_subresource_offset(f, c.extent, 0, mip, face) + (uint64_t(y) * level_side + x) * 8, v);
          level[(face * level_side + y) * level_side + x] =
              half4_at(c.bytes, raw_subresource_offset(f, c.extent, 0, mip, face) + (uint64_t(y) * level_side + x) * 8);
        }
    if (mip == 0) c.level0.texels = level;
    above = std::move(level);
  }
  return c;
}

// Cube `cube` of a frame's probes.faces (`extent`: the cube array's), as probes.light left it.
inline ProbeCapture capture_of(const std::vector<uint8_t>& faces, const ImageExtent& extent, uint32_t cube) {
  ProbeCapture c;
  c.extent = ImageExtent{extent.width, extent.height, 1, extent.mips, 6};
  const FormatInfo f = *format_info(kHalf4);
  c.bytes.assign(raw_image_bytes(f, c.extent), 0);
  for (uint32_t mip = 0; mip < extent.mips; ++mip) {
    const uint64_t from = raw_subresource_offset(f, extent, 0, mip, 6 * cube);
    const uint64_t bytes = raw_subresource_offset(f, extent, 0, mip, 6 * cube + 6) - from;
    std::memcpy(c.bytes.data() + raw_subresource_offset(f, c.extent, 0, mip, 0), faces.data() + from, bytes);
  }
  const uint32_t side = extent.width;
  c.level0.side = side;
  c.level0.texels.resize(6 * side * side);
  for (uint32_t i = 0; i < 6 * side * side; ++i) c.level0.texels[i] = half4_at(c.bytes, uint64_t(i) * 8);
  return c;
}

// probes.convert's inputs for `capture` alone, into `slot` of an array of `array_side` texels
// that held `before` everywhere: the capture as the first of two cubes of probes.faces (a cube
// array, as the frame's), the plan capturing it, six views (read only for the skip).
inline std::map<std::string, IsolatedInput> convert_inputs(const ProbeCapture& capture, uint32_t slot,
                                                           uint32_t array_side, const dvec3& before) {
  const FormatInfo f = *format_info(kHalf4);
  auto image_input = [](ResourceKind kind, const ImageExtent& extent, std::vector<uint8_t> bytes) {
    IsolatedInput input;
    input.desc.format = kHalf4;
    input.desc.kind = kind;
    input.desc.extent = extent;
    input.bytes = std::make_shared<const std::vector<uint8_t>>(std::move(bytes));
    return input;
  };
  ImageExtent two_cubes = capture.extent;
  two_cubes.layers = 12;
  std::vector<uint8_t> faces(raw_image_bytes(f, two_cubes), 0);
  for (uint32_t mip = 0; mip < two_cubes.mips; ++mip) {
    const uint64_t from = raw_subresource_offset(f, capture.extent, 0, mip, 0);
    const uint64_t bytes = raw_subresource_offset(f, capture.extent, 0, mip, 6) - from;
    std::memcpy(faces.data() + raw_subresource_offset(f, two_cubes, 0, mip, 0), capture.bytes.data() + from, bytes);
  }
  IsolatedInput cubes = image_input(kinds::hdr_colour, two_cubes, std::move(faces));
  cubes.desc.cube = true;
  const ImageExtent array_extent{array_side, array_side, 1, kProbeArrayMips, 2 * kProbeSlots};
  std::vector<uint8_t> held(raw_image_bytes(f, array_extent));
  for (size_t offset = 0; offset < held.size(); offset += 8) put_half4(held, offset, before);
  ProbePlan plan{};
  std::fill(std::begin(plan.slot_probe), std::end(plan.slot_probe), kNoProbe);
  plan.captured = 1;
  plan.capture_slot[0] = slot;
  plan.slot_probe[slot] = 0;
  plan.slot_state[slot] = uint32_t(ProbeSlotState::captured_reset);
  const std::vector<GpuView> views(6);
  return {{"probes.plan", record_input(plan)},
          {"probes.views", records_input(std::span<const GpuView>(views))},
          {"probes.faces", cubes},
          {"probes.array", image_input(*kind_by_name("probe_paraboloid"), array_extent, std::move(held))}};
}

}  // namespace nightcap::reference
