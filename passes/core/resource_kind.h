// What a resource holds, as the tools need to know it. A kind is a name that declarations use
// (ImageDecl, BufferDecl) and captures record, and a KindInfo that the code owning the kind
// registers: how `inspect` names a texel's values, how `export` and the report draw it, how `diff`
// measures it and how a capture compresses it. The captures, the comparison engine and the
// debugger ask the registry and never name a pass's kind, so a new kind of data (SH probes, fog
// froxels) is added beside the pass that writes it (docs/architecture.md, "Resource kinds").
#pragma once

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace nightcap {

class ResourceKind {
 public:
  constexpr explicit ResourceKind(std::string_view name) : name_(name) {}
  constexpr std::string_view name() const { return name_; }
  friend constexpr bool operator==(ResourceKind a, ResourceKind b) { return a.name_ == b.name_; }

 private:
  std::string_view name_;  // a literal, or the registry's copy of a name read from a capture
};

// One texel as the tools read it: per aspect (depth, then stencil) the channel values as
// format.h decodes them (UNORM in [0, 1], sRGB linearised, integers as their values), and the
// integer codes the format stores where it stores codes (empty for float formats, whose values
// are exact).
struct TexelValues {
  std::vector<double> raw;
  std::vector<uint64_t> codes;
};

// What a kind's decoding may need of the frame that wrote it.
struct KindFrame {
  double znear = 0.1;                            // metres: reversed-Z depth d is znear / distance
  uint32_t output_width = 1, output_height = 1;  // pixels of the frame's output
};

// What one texel draws as. Distances and motions are drawn relative to the whole image, so the
// picture scales them after reading every texel.
struct TexelPicture {
  enum class Scale {
    display,   // RGB in [0, 1], shown as it is (normals as colour, masks, tables)
    light,     // linear RGB in [0, 1], sRGB-encoded for display
    distance,  // value[0] > 0, on a log scale from the image's nearest (white) to its farthest
               // (black); 0: nothing there (black)
    motion,    // value[0..1] in pixels: hue from the direction, brightness from the length
               // against the image's longest
    relative,  // linear RGB ≥ 0 divided by the image's largest channel, sRGB-encoded (a table
               // whose values span any range)
  };
  Scale scale = Scale::display;
  std::array<double, 3> value{};
};

// How `diff` measures a kind where the output's contract does not say.
enum class KindMeasure {
  values,       // channel by channel, by the format (floats, UNORM codes, integers)
  unit_vector,  // channels 0..2 hold 0.5n + 0.5 of a unit vector: the angle between them
  depth,        // a depth: the relative difference ('depth' thresholds apply)
};

// How a capture compresses the kind's images, losslessly (captures/codec_choice.cpp has the
// measurements behind the default).
struct KindCompression {
  enum class Method { deflate, wavelet } method = Method::deflate;
  int level = 1;  // deflate's zlib level
};

// For kinds whose texels cover square tiles of the output instead of a scaled image (froxels):
// the writer's parameter that gives a tile's side in pixels, and the side where the writer
// recorded none.
struct OutputTiles {
  std::string parameter;
  uint32_t fallback = 1;
};

// For kinds whose texels index lists in a buffer of 32-bit entries (light clusters): which
// channels give a list's offset and length, the buffer, and what `inspect pixel` calls its
// entries.
struct TexelLists {
  uint32_t offset_channel = 0, count_channel = 1;
  std::string buffer, entries;
};

// For 3D kinds whose depth slices are ranges of view depth: the resource that gives a pixel's
// linear depth in metres, and the slice a depth falls in given the writer's parameters (none
// where the writer recorded too few of them).
struct DepthSlices {
  std::string linear_depth;
  std::function<std::optional<uint32_t>(double metres, double znear, const std::map<std::string, double>& writer_params,
                                        uint32_t slices)>
      slice_of;
};

// For 2D kinds a pass looks up by a world direction (cube maps are looked up by Vulkan's face
// selection instead): the buffer resource of the same frame whose record the lookup depends on,
// and the uv in [0, 1]² where a unit direction lands in a width × height image given that record
// (nullopt when the record does not say, e.g. empty).
struct DirectionLookup {
  std::string record;
  std::function<std::optional<std::array<double, 2>>(const std::array<double, 3>& direction,
                                                     std::span<const uint8_t> record, uint32_t width, uint32_t height)>
      uv_of;
};

// Layers that hold radiance by direction, two to a slot (the reflection probes' dual-paraboloid
// hemispheres): `inspect pixel` says which direction a texel stands for, and `inspect direction
// --slot S` finds the texel a direction of slot S is read at.
struct LayerDirections {
  // The direction at (u, v) in [0, 1]² of `layer`, and the layer and (u, v) of `direction` in `slot`.
  std::function<std::array<double, 3>(uint32_t layer, double u, double v)> direction_of;
  std::function<std::pair<uint32_t, std::array<double, 2>>(uint32_t slot, const std::array<double, 3>& direction)>
      texel_of;
};

// 3D kinds whose cells span blocks of slices (the GI volume: cell (x, y, z)'s texel k at slice
// z + k · depth / blocks): `inspect pixel X Y --slice Z` reads every texel of cell (X, Y, Z) and
// says what the cell holds, and the report draws slices of the first block.
struct SliceBlocks {
  uint32_t blocks = 1;
  // A buffer resource of the same frame the cell's meaning depends on ("" for none).
  std::string record;
  // The cell's values from its texels' channel values in block order, given `record`'s bytes
  // (empty where the frame holds none).
  std::function<void(const std::vector<std::vector<double>>& texels, std::span<const uint8_t> record,
                     nlohmann::ordered_json& out)>
      describe_cell;
};

struct KindInfo {
  ResourceKind kind{""};
  // `inspect pixel`: what a texel means, as named values in order ("normal", "linear_m", …);
  // unset: its raw values are what it holds.
  std::function<void(const TexelValues&, const KindFrame&, nlohmann::ordered_json&)> describe{};
  // `inspect export`, the report's pictures; unset: channels as they are, clamped to [0, 1].
  std::function<TexelPicture(const TexelValues&, const KindFrame&)> draw{};
  // The stencil aspect of a depth-stencil image: its texel's one value (the tag).
  std::function<std::array<uint8_t, 3>(uint32_t stencil)> draw_stencil{};
  // Its pictures show light: shrunk in linear light, not as codes.
  bool light = false;
  // Its texels lie over the frame's output, scaled or in tiles (false: tables, textures and maps
  // that a pass looks up by what it computes), so `inspect` reads them under a pixel.
  bool over_output = true;
  KindMeasure measure = KindMeasure::values;
  KindCompression compression{};
  std::optional<OutputTiles> tiles{};
  std::optional<TexelLists> lists{};
  std::optional<DepthSlices> slices{};
  std::optional<DirectionLookup> directions{};
  std::optional<LayerDirections> layer_directions{};
  std::optional<SliceBlocks> slice_blocks{};
};

// For kinds that store a vector meant to be a unit normal (before normalising): `inspect pixel`'s
// "normal" (null for the zero vector, which a cleared target holds) and "stored_length", and the
// picture 0.5n + 0.5 of the normalised vector (black for the zero vector).
void describe_stored_normal(const std::array<double, 3>& stored, nlohmann::ordered_json& out);
TexelPicture stored_normal_picture(const std::array<double, 3>& stored);

// Adds `info` under its kind's name; throws std::logic_error if the name is taken or empty.
// Owners register at static initialisation through KindRegistration, in the file of the pass that
// writes the kind; every binary links the whole of core (nightcap_core_whole, CMakeLists.txt), so
// every registration runs.
void register_kind(KindInfo info);
struct KindRegistration {
  explicit KindRegistration(KindInfo info) { register_kind(std::move(info)); }
};

// The registered kind of this name: a capture's manifest names kinds; nullopt if none is.
std::optional<ResourceKind> kind_by_name(std::string_view name);
// What `kind` is; throws std::logic_error for a kind declared but never registered.
const KindInfo& kind_info(ResourceKind kind);
// Every registered kind, in the order of their names.
std::vector<ResourceKind> registered_kinds();

// The kinds any pass may hold, which the core registers itself.
namespace kinds {
inline constexpr ResourceKind colour{"colour"};              // linear or display colour
inline constexpr ResourceKind hdr_colour{"hdr_colour"};      // unbounded radiance
inline constexpr ResourceKind mask{"mask"};                  // per-pixel 0/1 selection
inline constexpr ResourceKind linear_depth{"linear_depth"};  // view-space metres
inline constexpr ResourceKind lookup_table{"lookup_table"};  // a table a pass samples
inline constexpr ResourceKind texture{"texture"};            // scene-supplied texture
inline constexpr ResourceKind buffer{"buffer"};              // structured data
inline constexpr ResourceKind draw_list{"draw_list"};        // per-draw records consumed by a pass
}  // namespace kinds

}  // namespace nightcap
