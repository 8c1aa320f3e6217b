// `buffer`, `stats` and `export`: a buffer by its schema, statistics per channel, and values or
// pictures written to files.
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "inspect/command_runner.h"
#include "inspect/export.h"
#include "inspect/heatmap.h"
#include "inspect/stats.h"

namespace nightcap::inspect_cli {

void Runner::buffer(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 1, 1);
  const ResourceRecord& record = session_.resource(args.positional[0]);
  if (!record.is_buffer) throw InspectError(record.resource + " is an image: use `pixel` or `stats`");
  const std::vector<uint8_t>& raw = session_.load(record);
  const BufferSchema* schema = session_.schema_of(record);
  ojson j = {{"resource", record.resource}, {"bytes", record.buffer_size}, {"hash", record.hash}};
  const uint64_t count = schema ? buffer_elements(*schema, raw.size()) : raw.size() / 4;
  uint64_t first = 0, last = count;
  if (args.has("--element")) {
    first = option_index(args, "--element", 0);
    if (first >= count)
      throw InspectError(record.resource + " has " + std::to_string(count) + (schema ? " element(s)" : " word(s)") +
                         ": no " + std::to_string(first));
    last = first + 1;
  }
  ojson values = ojson::array();
  if (schema) {
    j["stride"] = schema->stride;
    j["elements"] = count;
    for (uint64_t e = first; e < last; ++e)
      values.push_back({{"element", e}, {"fields", decode_buffer_element(*schema, raw, e)}});
  } else {
    j["words_count"] = count;
    for (uint64_t w = first; w < last; ++w) {
      uint32_t word;
      float as_float;
      std::memcpy(&word, raw.data() + 4 * w, 4);
      std::memcpy(&as_float, raw.data() + 4 * w, 4);
      values.push_back(
          {{"word", w}, {"u32", word}, {"f32", std::isfinite(as_float) ? ojson(as_float) : ojson(nullptr)}});
    }
  }
  j[schema ? "values" : "words"] = values;
  if (json_) return emit(j);
  out_ << record.resource << " (" << record.buffer_size << " B, "
       << (schema ? std::to_string(count) + " elements of " + std::to_string(schema->stride) + " B"
                  : std::to_string(count) + " 32-bit words, no schema")
       << ")\n";
  for (const ojson& v : values) {
    if (schema) {
      out_ << "element " << v["element"] << ":\n";
      for (const auto& [field, value] : v["fields"].items()) out_ << "  " << field << ": " << brief(value) << "\n";
    } else {
      std::ostringstream hex;
      hex << std::hex << std::setw(8) << std::setfill('0') << v["u32"].get<uint32_t>();
      out_ << "word " << v["word"] << ": 0x" << hex.str() << " u32 " << v["u32"] << " f32 " << brief(v["f32"]) << "\n";
    }
  }
}

void Runner::stats(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 1, 1);
  const ResourceRecord& record = session_.resource(args.positional[0]);
  const FrameRecord& frame = session_.frame();
  const Subimage subimage = subimage_of(args);
  // The texels covering the output rectangle: from the first pixel's texel to the last one's.
  uint32_t x = 0, y = 0, w = frame.width, h = frame.height;
  if (args.has("--rect")) {
    const auto& r = args.options.at("--rect");
    x = parse_index("X", r[0]);
    y = parse_index("Y", r[1]);
    w = parse_index("W", r[2]);
    h = parse_index("H", r[3]);
    if (w == 0 || h == 0) throw InspectError("--rect: width and height must be at least 1");
  }
  if (uint64_t(x) + w > frame.width || uint64_t(y) + h > frame.height)
    throw InspectError("--rect " + std::to_string(x) + " " + std::to_string(y) + " " + std::to_string(w) + " " +
                       std::to_string(h) + " is outside the " + std::to_string(frame.width) + "x" +
                       std::to_string(frame.height) + " output");
  const TexelAddress first = texel_for_output_pixel(record, frame, x, y, subimage);
  const TexelAddress last = texel_for_output_pixel(record, frame, x + w - 1, y + h - 1, subimage);
  const TexelRect rect{first.x, first.y, last.x - first.x + 1, last.y - first.y + 1};
  const std::vector<ChannelStats> channels = image_stats(record, session_.load(record), subimage, rect);
  ojson list = ojson::array();
  for (const ChannelStats& c : channels)
    list.push_back({{"min", c.min},
                    {"max", c.max},
                    {"mean", c.mean},
                    {"finite", c.finite},
                    {"nan", c.nan},
                    {"inf", c.inf},
                    {"denormal", c.denormal},
                    {"histogram", c.histogram}});
  ojson j = {{"resource", record.resource},
             {"kind", record.kind.name()},
             {"format", format_info(record.format)->name},
             {"mip", subimage.mip},
             {"layer", subimage.layer},
             {"slice", subimage.slice},
             {"texels", {rect.x, rect.y, rect.width, rect.height}},
             {"channels", list}};
  if (json_) return emit(j);
  out_ << record.resource << " (" << j["format"].get<std::string>() << ") mip " << subimage.mip << " layer "
       << subimage.layer << (record.extent.depth > 1 ? " slice " + std::to_string(subimage.slice) : "") << ", texels "
       << rect.x << "," << rect.y << " " << rect.width << "x" << rect.height << "\n";
  for (size_t c = 0; c < channels.size(); ++c) {
    const ChannelStats& s = channels[c];
    out_ << "  channel " << c << ": min " << brief(s.min) << " max " << brief(s.max) << " mean " << brief(s.mean)
         << "; finite " << s.finite << " NaN " << s.nan << " Inf " << s.inf << " denormal " << s.denormal
         << "\n    histogram " << brief(list[c]["histogram"]) << "\n";
  }
}

void Runner::export_files(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 1, 1);
  if (!args.has("-o")) throw InspectError("export: usage: " + spec.help.usage);
  const std::filesystem::path target = args.options.at("-o")[0];
  const ValuesExr values{args.has("--half"), !args.has("--uncompressed")};
  ojson files = ojson::array();
  if (args.has("--heatmap")) {
    if (target.extension() != ".png")
      throw InspectError("export --heatmap -o " + target.string() + ": expected a .png");
    const ResourceRecord& record = session_.resource(args.positional[0]);
    std::optional<uint32_t> slice;
    if (args.has("--slice")) slice = uint32_t(option_index(args, "--slice", 0));
    const ListHeatmap map = list_heatmap(record, session_.load(record), slice);
    const Rgba8Image image = heatmap_picture(map, output_tile_size(record, session_.frame()).value_or(1));
    write_png(target, image.pixels, image.width, image.height);
    if (json_) return emit({{"files", {target.string()}}, {"longest", map.longest}, {"mean", map.mean_nonempty}});
    out_ << "wrote " << target.string() << " (longest list " << map.longest << ", mean over tiles with a list "
         << map.mean_nonempty << ")\n";
    return;
  }
  if (args.has("--all")) {
    const PassRecord* pass = nullptr;
    for (const PassRecord& p : session_.frame().passes)
      if (p.name == args.positional[0]) pass = &p;
    if (!pass)
      throw InspectError("no pass '" + args.positional[0] + "' in frame " + std::to_string(session_.frame().index));
    std::error_code error;
    std::filesystem::create_directories(target, error);
    if (error) throw InspectError(target.string() + ": cannot create: " + error.message());
    for (const ResourceRecord& r : pass->outputs) {
      const std::vector<uint8_t>& raw = session_.load(r);
      if (r.is_buffer) {
        const std::filesystem::path file = target / (r.resource + ".bin");
        std::ofstream out(file, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(raw.data()), std::streamsize(raw.size()));
        if (!out) throw InspectError(file.string() + ": cannot write");
        files.push_back(file.string());
        continue;
      }
      write_values_exr(target / (r.resource + ".exr"), r, raw, {}, values);
      files.push_back((target / (r.resource + ".exr")).string());
      if (args.has("--no-pictures")) continue;
      write_picture(target / (r.resource + ".png"), r, raw, {}, VisualAspect::depth_or_colour);
      files.push_back((target / (r.resource + ".png")).string());
      if (format_info(r.format)->has_stencil) {
        write_picture(target / (r.resource + ".stencil.png"), r, raw, {}, VisualAspect::stencil);
        files.push_back((target / (r.resource + ".stencil.png")).string());
      }
    }
  } else {
    const ResourceRecord& record = session_.resource(args.positional[0]);
    if (record.is_buffer) throw InspectError(record.resource + " is a buffer: `export PASS --all` writes its bytes");
    const Subimage subimage = subimage_of(args);
    check_subimage(record, subimage);
    const std::string extension = target.extension().string();
    if (extension == ".exr" && !args.has("--stencil")) {
      write_values_exr(target, record, session_.load(record), subimage, values);
    } else if (extension == ".png") {
      write_picture(target, record, session_.load(record), subimage,
                    args.has("--stencil") ? VisualAspect::stencil : VisualAspect::depth_or_colour);
    } else {
      throw InspectError("export -o " + target.string() + ": expected a .exr file (values) or a .png (picture)" +
                         (args.has("--stencil") ? "; --stencil is a picture: .png" : ""));
    }
    files.push_back(target.string());
  }
  if (json_) return emit({{"files", files}});
  for (const ojson& f : files) out_ << "wrote " << f.get<std::string>() << "\n";
}

void Runner::write_picture(const std::filesystem::path& file, const ResourceRecord& record,
                           std::span<const uint8_t> raw, const Subimage& subimage, VisualAspect aspect) {
  const Rgba8Image image = visualise(record, raw, session_.frame(), subimage, aspect);
  write_png(file, image.pixels, image.width, image.height);
}

}  // namespace nightcap::inspect_cli
