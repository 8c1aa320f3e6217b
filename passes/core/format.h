// Formats nightcap records, and what each holds. The table is the single place that knows
// texel sizes, channel layouts and how a format's raw bytes decode to numbers.
#pragma once

#include <vulkan/vulkan.h>

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace nightcap {

// How one channel's bits are stored in a texel.
enum class ChannelEncoding {
  unorm8,
  srgb8,
  uint8,
  unorm16,
  uint16,
  sfloat16,
  sfloat32,
  uint32,
  packed_a2b10g10r10,  // one 32-bit word: r 10, g 10, b 10, a 2 (unorm)
  packed_b10g11r11,    // one 32-bit word: r 11, g 11, b 10 unsigned floats
  depth32_stencil8,    // two aspects: float depth plane, then uint8 stencil plane
};

struct FormatInfo {
  VkFormat vk;
  std::string_view name;  // Vulkan name without VK_FORMAT_
  ChannelEncoding encoding;
  uint32_t channels;     // logical channels (depth+stencil counts as 2)
  uint32_t texel_bytes;  // bytes per texel in the raw layout of one aspect (depth: 4)
  bool is_depth = false;
  bool has_stencil = false;
};

// Whether its channels are floating point and colour (SFLOAT, UFLOAT; not depth): the formats
// that can hold a NaN.
bool is_float_colour(const FormatInfo& format);
// Whether it decodes to floating point: the float colour formats, D32_SFLOAT and
// D32_SFLOAT_S8_UINT (whose stencil aspect is an integer).
bool is_float(const FormatInfo& format);
// One texel of a float colour format whose every channel is a quiet NaN, as raw bytes.
std::vector<uint8_t> quiet_nan_texel(const FormatInfo& format);

// Every image format a resource may have; nullopt for anything else.
std::optional<FormatInfo> format_info(VkFormat format);
std::optional<FormatInfo> format_by_name(std::string_view name);
const std::vector<FormatInfo>& all_formats();

// Raw image layout used everywhere (GPU readback, capture blobs, replay uploads):
// aspect-major (depth plane before stencil plane), then mip, then layer, then z slice, then
// rows of tightly packed texels.
struct ImageExtent {
  uint32_t width = 1, height = 1, depth = 1, mips = 1, layers = 1;
  bool operator==(const ImageExtent&) const = default;
};
uint32_t mip_size(uint32_t base, uint32_t mip);
uint64_t raw_image_bytes(const FormatInfo& format, const ImageExtent& extent);
// Byte offset of (aspect, mip, layer) in the raw layout; aspect 1 is stencil.
uint64_t raw_subresource_offset(const FormatInfo& format, const ImageExtent& extent, uint32_t aspect, uint32_t mip,
                                uint32_t layer);
uint64_t raw_subresource_bytes(const FormatInfo& format, const ImageExtent& extent, uint32_t aspect, uint32_t mip);

// Decodes texel `index` of one aspect to floats: UNORM to [0,1], sRGB to linear, integers and
// stencil as their values, packed formats unpacked. Writes `channels` values (stencil: 1).
void decode_texel(const FormatInfo& format, uint32_t aspect, std::span<const uint8_t> plane, uint64_t index,
                  float* out);
uint32_t aspect_channels(const FormatInfo& format, uint32_t aspect);
uint32_t aspect_texel_bytes(const FormatInfo& format, uint32_t aspect);
uint32_t aspect_count(const FormatInfo& format);

// Codes per unit of a UNORM (or sRGB-encoded) colour channel: what one step of the format is
// worth (the 2-bit alpha of A2B10G10R10 aside).
double code_scale(const FormatInfo& format);

float half_to_float(uint16_t h);
uint16_t float_to_half(float f);
// What passes/frame/half.glsl's nearest_half stores, as a float: the half nearest to `f` (ties
// to even), at most 65504.
float half_rounded(float f);
float srgb_to_linear(float c);
float linear_to_srgb(float c);

}  // namespace nightcap
