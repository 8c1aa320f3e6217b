// `pixel`, `history` and `pick`: a texel decoded by its kind, a pixel through the frame, and the draw
// under a pixel.
#include <array>
#include <cstring>
#include <iomanip>

#include "inspect/command_runner.h"
#include "inspect/pixel_history.h"
#include "passes/scene/stencil_tags.h"

namespace nightcap::inspect_cli {

// One texel of one version: its hash, the raw channel values, the stored codes and what they mean.
ojson Runner::texel_json(const ResourceRecord& record, const FrameRecord& frame, const TexelAddress& texel) {
  const PixelReading reading = read_pixel(record, session_.load(record), frame, texel);
  ojson j = {{"hash", record.hash}, {"raw", reading.values.raw}};
  if (!reading.values.codes.empty()) j["codes"] = reading.values.codes;
  j["decoded"] = reading.decoded;
  if (const auto& layers = kind_info(record.kind).layer_directions) {
    const double u = (texel.x + 0.5) / mip_size(record.extent.width, texel.mip);
    const double v = (texel.y + 0.5) / mip_size(record.extent.height, texel.mip);
    j["decoded"]["slot"] = texel.layer / 2;
    j["decoded"]["hemisphere"] = texel.layer % 2 == 0 ? "upper" : "lower";
    j["decoded"]["direction"] = layers->direction_of(texel.layer, u, v);
  }
  return j;
}

ojson Runner::reading_json(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
                           const Subimage& subimage) {
  const TexelAddress texel = texel_for_output_pixel(record, frame, x, y, subimage);
  ojson j = {{"frame", frame.index},
             {"resource", record.resource},
             {"kind", record.kind.name()},
             {"format", format_info(record.format)->name},
             {"pixel", {x, y}},
             {"texel", {texel.x, texel.y}},
             {"mip", texel.mip},
             {"layer", texel.layer}};
  if (record.extent.depth > 1) j["slice"] = texel.slice;
  j.update(texel_json(record, frame, texel));
  return j;
}

void Runner::print_reading(const ojson& j) {
  out_ << j["resource"].get<std::string>() << " (" << j["kind"].get<std::string>() << ", "
       << j["format"].get<std::string>() << ") frame " << j["frame"] << " texel " << brief(j["texel"]) << " mip "
       << j["mip"] << " layer " << j["layer"] << (j.contains("slice") ? " slice " + j["slice"].dump() : "")
       << (j.contains("face") ? " (face " + j["face"].get<std::string>() + ")" : "")
       << (j.contains("uv") ? " uv " + brief(j["uv"]) : "") << "\n";
  out_ << "  raw: " << brief(j["raw"]) << "\n";
  if (j.contains("codes")) out_ << "  codes: " << brief(j["codes"]) << "\n";
  for (const auto& [name, value] : j["decoded"].items()) out_ << "  " << name << ": " << brief(value) << "\n";
}

// An image whose texels index lists (lights.clusters) under a pixel: the texel of its tile, in
// the depth slice where the kind's linear depth resource (depth.linear) puts the pixel or at
// --slice, and that texel's list from the kind's buffer (lights.cluster_indices).
void Runner::listed(const ResourceRecord& record, uint32_t x, uint32_t y, Subimage subimage, bool slice_given) {
  const FrameRecord& frame = session_.frame();
  const KindInfo& kind = kind_info(record.kind);
  const TexelLists& lists = *kind.lists;
  std::optional<double> depth;
  if (!slice_given && kind.slices) {
    const PassRecord* writer = writer_of(record, frame);
    if (!writer)
      throw InspectError(record.resource + ": no pass of frame " + std::to_string(frame.index) + " wrote this version");
    const ResourceRecord& linear = session_.resource(kind.slices->linear_depth);
    const PixelReading reading =
        read_pixel(linear, session_.load(linear), frame, texel_for_output_pixel(linear, frame, x, y, {}));
    depth = reading.values.raw.at(0);
    const std::optional<uint32_t> slice =
        kind.slices->slice_of(*depth, frame.camera.znear, writer->params, record.extent.depth);
    if (!slice)
      throw InspectError(record.resource + ": " + writer->name +
                         " recorded too few parameters to find a pixel's slice: use --slice");
    subimage.slice = *slice;
  }
  ojson j = reading_json(record, frame, x, y, subimage);
  const uint64_t offset = j["codes"][lists.offset_channel], count = j["codes"][lists.count_channel];
  const ResourceRecord& entries = session_.resource(lists.buffer);
  const std::vector<uint8_t>& bytes = session_.load(entries);
  if ((offset + count) * 4 > bytes.size())
    throw InspectError(record.resource + ": the list at " + std::to_string(offset) + " runs past " + entries.resource);
  std::vector<uint32_t> list(count);
  if (count) std::memcpy(list.data(), bytes.data() + offset * 4, count * 4);
  ojson& decoded = j["decoded"];
  decoded["froxel"] = {j["texel"][0], j["texel"][1], subimage.slice};
  if (depth) decoded["depth_m"] = *depth;
  decoded[lists.entries] = list;
  return json_ ? emit(j) : print_reading(j);
}

// A cell of a kind whose cells span blocks of slices (the GI volume): the texel at --slice Z of the
// first block, and what the kind reads in all the cell's texels together.
void Runner::cell(const ResourceRecord& record, uint32_t x, uint32_t y, const Subimage& subimage) {
  const FrameRecord& frame = session_.frame();
  const SliceBlocks& blocks = *kind_info(record.kind).slice_blocks;
  const uint32_t per_block = record.extent.depth / blocks.blocks;
  if (subimage.slice >= per_block)
    throw InspectError(record.resource + ": slice " + std::to_string(subimage.slice) + " is past its " +
                       std::to_string(per_block) + " cells along z (each cell spans " + std::to_string(blocks.blocks) +
                       " blocks of slices)");
  ojson j = reading_json(record, frame, x, y, subimage);
  const std::vector<uint8_t>& raw = session_.load(record);
  std::vector<std::vector<double>> texels;
  for (uint32_t k = 0; k < blocks.blocks; ++k) {
    Subimage block = subimage;
    block.slice = subimage.slice + k * per_block;
    texels.push_back(read_pixel(record, raw, frame, texel_for_output_pixel(record, frame, x, y, block)).values.raw);
  }
  const ResourceRecord* lookup = blocks.record.empty() ? nullptr : session_.resource_in_frame(frame, blocks.record);
  ojson decoded;
  blocks.describe_cell(texels, lookup ? std::span<const uint8_t>(session_.load(*lookup)) : std::span<const uint8_t>(),
                       decoded);
  j["decoded"] = decoded;
  return json_ ? emit(j) : print_reading(j);
}

std::string Runner::named_or_first_output(const Arguments& args, size_t position) {
  if (args.positional.size() > position) return args.positional[position];
  const PassRecord& p = session_.pass();
  if (p.outputs.empty()) throw InspectError(p.name + " has no output: name a resource");
  return p.outputs[0].resource;
}

void Runner::direction(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 3, 4);
  std::array<double, 3> d{};
  for (int i = 0; i < 3; ++i) {
    const std::string& text = args.positional[size_t(i)];
    size_t used = 0;
    try {
      d[size_t(i)] = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != text.size() || text.empty())
      throw InspectError(std::string("D") + "XYZ"[i] + " '" + text + "': expected a number");
  }
  const ResourceRecord& record = session_.resource(named_or_first_output(args, 3));
  const FrameRecord& frame = session_.frame();
  const uint32_t mip = option_index(args, "--mip", 0);
  ojson j = {{"frame", frame.index},
             {"resource", record.resource},
             {"kind", record.kind.name()},
             {"format", format_info(record.format)->name},
             {"direction", d}};
  TexelAddress texel;
  const KindInfo& info = kind_info(record.kind);
  if (info.layer_directions) {
    check_direction(d);
    if (!args.has("--slot")) throw InspectError(record.resource + " holds two layers a slot: name one with --slot S");
    const uint32_t slot = option_index(args, "--slot", 0);
    const auto [layer, uv] = info.layer_directions->texel_of(slot, d);
    check_subimage(record, {mip, layer, 0});
    const uint32_t width = mip_size(record.extent.width, mip), height = mip_size(record.extent.height, mip);
    texel.x = std::min(uint32_t(uv[0] * width), width - 1);
    texel.y = std::min(uint32_t(uv[1] * height), height - 1);
    texel.mip = mip;
    texel.layer = layer;
    j["slot"] = slot;
    j["uv"] = uv;
  } else if (record.cube) {
    texel = cube_texel(record, d, mip);
    static const char* const faces[] = {"+X", "-X", "+Y", "-Y", "+Z", "-Z"};
    j["face"] = faces[texel.layer];
  } else {
    // A table a pass looks up by direction, through a record of the same frame (sky.view).
    const KindInfo& kind = info;
    if (!kind.directions)
      throw InspectError(record.resource + " is neither a cube map nor a table looked up by direction: use `pixel`");
    check_subimage(record, {mip, 0, 0});
    check_direction(d);
    const std::string& by = kind.directions->record;
    const ResourceRecord* lookup = session_.resource_in_frame(frame, by);
    if (!lookup)
      throw InspectError(record.resource + ": frame " + std::to_string(frame.index) + " recorded no " + by +
                         " to look it up by");
    const uint32_t width = mip_size(record.extent.width, mip), height = mip_size(record.extent.height, mip);
    const std::optional<std::array<double, 2>> uv = kind.directions->uv_of(d, session_.load(*lookup), width, height);
    if (!uv)
      throw InspectError(record.resource + ": " + by + " holds no record in frame " + std::to_string(frame.index) +
                         " (no directional light lit a sky)");
    texel.x = std::min(uint32_t((*uv)[0] * width), width - 1);
    texel.y = std::min(uint32_t((*uv)[1] * height), height - 1);
    texel.mip = mip;
    j["uv"] = *uv;
  }
  j["texel"] = {texel.x, texel.y};
  j["mip"] = texel.mip;
  j["layer"] = texel.layer;
  j.update(texel_json(record, frame, texel));
  return json_ ? emit(j) : print_reading(j);
}

void Runner::pixel(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 2, 3);
  const uint32_t x = parse_index("X", args.positional[0]), y = parse_index("Y", args.positional[1]);
  const Subimage subimage = subimage_of(args);
  const std::string name = named_or_first_output(args, 2);
  const ResourceRecord& record = session_.resource(name);
  if (!args.has("--frames")) {
    if (kind_info(record.kind).lists) return listed(record, x, y, subimage, args.has("--slice"));
    if (kind_info(record.kind).slice_blocks) return cell(record, x, y, subimage);
    const ojson j = reading_json(record, session_.frame(), x, y, subimage);
    return json_ ? emit(j) : print_reading(j);
  }
  ojson frames = ojson::array();
  for (const FrameRecord& frame : session_.capture().manifest().frames) {
    const ResourceRecord* version = session_.resource_in_frame(frame, name);
    if (!version) {
      frames.push_back({{"frame", frame.index}, {"missing", "no " + name + " at " + session_.pass().name}});
      continue;
    }
    frames.push_back(reading_json(*version, frame, x, y, subimage));
  }
  if (json_) return emit({{"resource", name}, {"pixel", {x, y}}, {"frames", frames}});
  for (const ojson& f : frames) {
    if (f.contains("missing")) {
      out_ << "frame " << f["frame"] << ": " << f["missing"].get<std::string>() << "\n";
      continue;
    }
    print_reading(f);
  }
}

void Runner::history(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 2, 3);
  const uint32_t x = parse_index("X", args.positional[0]), y = parse_index("Y", args.positional[1]);
  const std::string only = args.positional.size() == 3 ? args.positional[2] : "";
  const FrameRecord& frame = session_.frame();
  const std::vector<PixelWrite> writes = pixel_history(session_, x, y, only);
  ojson list = ojson::array();
  for (const PixelWrite& w : writes) {
    const PassRecord& pass = frame.passes[w.pass_index];
    ojson j = {{"pass", pass.name},
               {"ran", pass.ran},
               {"resource", w.after->resource},
               {"format", format_info(w.after->format)->name},
               {"mip", w.texel.mip},
               {"texel", {w.texel.x, w.texel.y}},
               {"status", !w.before   ? "first"
                          : w.changed ? "changed"
                                      : "unchanged"}};
    j["before"] = w.before ? texel_json(*w.before, frame, w.texel) : ojson(nullptr);
    j["after"] = texel_json(*w.after, frame, w.texel);
    list.push_back(j);
  }
  if (json_) return emit({{"frame", frame.index}, {"pixel", {x, y}}, {"granularity", "pass"}, {"writes", list}});
  out_ << "pixel " << x << "," << y << " through frame " << frame.index
       << " (one step per pass: the capture records passes, not draws)\n";
  auto values = [](const ojson& r) {
    std::string text;
    for (const auto& [name, value] : r["decoded"].items())
      text += (text.empty() ? "" : ", ") + name + " " + brief(value);
    return text.empty() ? brief(r["raw"]) : text;
  };
  for (const ojson& w : list) {
    std::string where = w["resource"].get<std::string>();
    if (w["mip"].get<uint32_t>() > 0) where += " mip " + std::to_string(w["mip"].get<uint32_t>());
    out_ << "  " << std::left << std::setw(20) << w["pass"].get<std::string>() << std::setw(24) << where;
    const std::string status = w["status"].get<std::string>();
    if (status == "unchanged") {
      out_ << "unchanged: " << values(w["after"]) << "\n";
    } else if (status == "first") {
      out_ << (w["ran"].get<bool>() ? "first write: " : "cleared (pass skipped): ") << values(w["after"]) << "\n";
    } else {
      out_ << "changed\n"
           << std::string(46, ' ') << "before: " << values(w["before"]) << "\n"
           << std::string(46, ' ') << "after:  " << values(w["after"]) << "\n";
    }
  }
}

void Runner::pick_draw(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 2, 2);
  const uint32_t x = parse_index("X", args.positional[0]), y = parse_index("Y", args.positional[1]);
  const FrameRecord& frame = session_.frame();
  if (x >= frame.width || y >= frame.height)
    throw InspectError("pixel " + std::to_string(x) + "," + std::to_string(y) + " is outside the " +
                       std::to_string(frame.width) + "x" + std::to_string(frame.height) + " output");
  auto ids = draw_ids_.find(frame.index);
  if (ids == draw_ids_.end())
    ids = draw_ids_.emplace(frame.index, render_draw_ids(session_.gpu(), session_.capture(), frame)).first;
  const std::optional<Pick> found = pick(ids->second, session_.capture(), frame, x, y);
  ojson j = {{"frame", frame.index}, {"pixel", {x, y}}, {"covered", found.has_value()}};
  if (!found) {
    if (json_) return emit(j);
    out_ << "pixel " << x << "," << y << ": no draw of " << kPickedPass << " covers it (sky)\n";
    return;
  }
  const GpuDraw& draw = found->record;
  const GpuMaterial& m = found->material;
  auto vec = [](const auto& v, int n) {
    ojson a = ojson::array();
    for (int k = 0; k < n; ++k) a.push_back(v[k]);
    return a;
  };
  static const char* const alpha_modes[] = {"opaque", "mask", "blend"};
  const uint32_t alpha_mode = uint32_t(m.extra.z);
  const uint32_t flags = uint32_t(m.extra.w);
  j["draw"] = found->draw;
  j["instance"] = draw.instance;
  j["mesh"] = {{"first_index", draw.first_index},
               {"index_count", draw.index_count},
               {"triangles", draw.index_count / 3},
               {"vertex_offset", draw.vertex_offset}};
  j["position_camera_relative"] = {draw.model[3][0], draw.model[3][1], draw.model[3][2]};
  j["mirrored"] = draw.mirrored != 0;
  j["stencil"] = {
      {"value", draw.stencil}, {"class", stencil_class_name(draw.stencil)}, {"flags", stencil_flags(draw.stencil)}};
  ojson textures = ojson::object();
  const int32_t slots[] = {m.textures.x, m.textures.y, m.textures.z, m.textures.w, m.textures2.x};
  const char* const slot_names[] = {"base_color", "metallic_roughness", "normal", "occlusion", "emissive"};
  for (int k = 0; k < 5; ++k) textures[slot_names[k]] = slots[k] >= 0 ? ojson(slots[k]) : ojson(nullptr);
  j["material"] = {{"index", draw.material},
                   {"base_color", vec(m.base_color, 4)},
                   {"emissive", vec(m.emissive, 3)},
                   {"metallic", m.pbr.x},
                   {"roughness", m.pbr.y},
                   {"alpha_mode", alpha_mode < 3 ? alpha_modes[alpha_mode] : "unknown"},
                   {"unlit", (flags & 1) != 0},
                   {"double_sided", (flags & 2) != 0},
                   {"textures", textures}};
  if (alpha_mode == 1) j["material"]["alpha_cutoff"] = m.pbr.z;
  if (json_) return emit(j);
  out_ << "pixel " << x << "," << y << ": draw " << found->draw << " of " << kPickedPass << "\n"
       << "  instance " << draw.instance << ", at " << brief(j["position_camera_relative"])
       << " m from the camera (world axes)" << (draw.mirrored ? ", mirrored" : "") << "\n"
       << "  mesh: indices " << draw.first_index << ".." << draw.first_index + draw.index_count - 1 << " ("
       << draw.index_count / 3 << " triangles), vertex offset " << draw.vertex_offset << "\n"
       << "  material " << draw.material << ": base colour " << brief(j["material"]["base_color"]) << ", metallic "
       << brief(j["material"]["metallic"]) << ", roughness " << brief(j["material"]["roughness"]) << ", "
       << j["material"]["alpha_mode"].get<std::string>() << ((flags & 1) ? ", unlit" : "")
       << ((flags & 2) ? ", double-sided" : "") << "\n"
       << "  stencil: " << j["stencil"]["class"].get<std::string>();
  for (const ojson& flag : j["stencil"]["flags"]) out_ << " +" << flag.get<std::string>();
  out_ << "\n";
}

}  // namespace nightcap::inspect_cli
