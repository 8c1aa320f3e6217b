#include "inspect/pixel_history.h"

#include <cmath>

namespace nightcap {

namespace {

bool screen_space(const ResourceRecord& r, const FrameRecord& frame) {
  if (r.is_buffer) return false;
  for (uint32_t shift = 0; shift <= 4; ++shift) {
    auto matches = [&](uint32_t size, uint32_t output) {
      const uint32_t down = std::max(1u, output >> shift), up = std::max(1u, (output + (1u << shift) - 1) >> shift);
      return size == down || size == up;
    };
    if (matches(r.extent.width, frame.width) && matches(r.extent.height, frame.height)) return true;
  }
  return false;
}

bool same_value(const TexelValues& a, const TexelValues& b) {
  if (a.codes != b.codes || a.raw.size() != b.raw.size()) return false;
  for (size_t c = 0; c < a.raw.size(); ++c)
    if (!(a.raw[c] == b.raw[c] || (std::isnan(a.raw[c]) && std::isnan(b.raw[c]))) ||
        std::signbit(a.raw[c]) != std::signbit(b.raw[c]))
      return false;
  return true;
}

const ResourceRecord* version_before(const FrameRecord& frame, size_t pass_index, const std::string& resource) {
  for (const ResourceRecord& in : frame.passes[pass_index].inputs)
    if (in.resource == resource) return &in;
  for (size_t i = pass_index; i-- > 0;)
    for (const ResourceRecord& out : frame.passes[i].outputs)
      if (out.resource == resource) return &out;
  return nullptr;
}

}  // namespace

std::vector<PixelWrite> pixel_history(InspectSession& session, uint32_t x, uint32_t y, const std::string& only) {
  const FrameRecord& frame = session.frame();
  if (x >= frame.width || y >= frame.height)
    throw InspectError("pixel (" + std::to_string(x) + ", " + std::to_string(y) + ") is outside the " +
                       std::to_string(frame.width) + "x" + std::to_string(frame.height) + " output");
  std::vector<PixelWrite> writes;
  bool written = false;
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    for (const ResourceRecord& out : frame.passes[i].outputs) {
      if (!only.empty() && out.resource != only) continue;
      written |= !only.empty();
      if (!screen_space(out, frame)) continue;
      const ResourceRecord* before = version_before(frame, i, out.resource);
      // A pass that updates some mips of a pyramid shows those that changed, or one unchanged
      // entry; a first version shows every mip.
      const size_t first = writes.size();
      for (uint32_t mip = 0; mip < out.extent.mips; ++mip) {
        PixelWrite write{i, before, &out, texel_for_output_pixel(out, frame, x, y, {mip, 0, 0}), true};
        if (before && before->hash == out.hash)
          write.changed = false;
        else if (before)
          write.changed = !same_value(read_texel(*before, session.load(*before), write.texel),
                                      read_texel(out, session.load(out), write.texel));
        if (write.changed) writes.push_back(write);
      }
      if (writes.size() == first)
        writes.push_back({i, before, &out, texel_for_output_pixel(out, frame, x, y, {}), false});
    }
  }
  if (!only.empty() && !written)
    throw InspectError("no pass of frame " + std::to_string(frame.index) + " writes '" + only + "'");
  return writes;
}

}  // namespace nightcap
