#include "inspect/commands.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <optional>
#include <sstream>

#include "inspect/disassemble.h"
#include "inspect/export.h"
#include "inspect/heatmap.h"
#include "inspect/nan_origin.h"
#include "inspect/pixel_history.h"
#include "inspect/stats.h"
#include "inspect/visualise.h"
#include "passes/assembly/frame_passes.h"
#include "passes/assembly/renderer.h"
#include "passes/scene/stencil_tags.h"
#include "replay/replay.h"

namespace nightcap {

namespace {

using ojson = nlohmann::ordered_json;

// A command's words after its name: positionals, and options with the number of values each
// takes (`--json` and `--frames` none, `--mip` one, `--rect` four).
struct Arguments {
  std::vector<std::string> positional;
  std::map<std::string, std::vector<std::string>> options;

  bool has(const std::string& option) const { return options.count(option) > 0; }
};

struct CommandSpec {
  InspectCommandHelp help;
  std::map<std::string, int> options;  // besides --json, which every command takes
};

const std::vector<CommandSpec>& specs() {
  static const std::vector<CommandSpec> table = {
      {{"passes", "passes", "the frame's passes: ran or why skipped, GPU/CPU time, outputs; '>' marks the current"},
       {}},
      {{"goto", "goto PASS", "make PASS the current pass"}, {}},
      {{"next", "next", "go to the next pass"}, {}},
      {{"prev", "prev", "go to the previous pass"}, {}},
      {{"frame", "frame [K]", "show the current frame, or go to recorded frame K (keeping the pass)"}, {}},
      {{"info", "info",
        "what the current pass read and wrote: kind, format, size, hash, and each output's comparison contract"},
       {}},
      {{"pipeline", "pipeline", "the pipeline and sampler state the current pass bound"}, {}},
      {{"shader", "shader [PATH]",
        "the current pass's shaders (or the one whose path ends in PATH): recorded GLSL and SPIR-V disassembly"},
       {}},
      {{"pixel", "pixel X Y [RESOURCE] [--mip M] [--layer L] [--slice Z] [--frames]",
        "the texel under output pixel (X, Y) decoded by what RESOURCE holds (default: the current pass's first "
        "output), with its raw values; --slice: the depth slice of a 3D image; --frames: the same pixel in every "
        "recorded frame. lights.clusters: the froxel the pixel falls in at its depth.linear (or --slice) and that "
        "froxel's list of frame.lights indices"},
       {{"--mip", 1}, {"--layer", 1}, {"--slice", 1}, {"--frames", 0}}},
      {{"history", "history X Y [RESOURCE]",
        "output pixel (X, Y) through the frame: each pass that wrote a screen-space resource (depth and stencil "
        "included; every mip of a pyramid), in order, with the texel before and after, and 'unchanged' where the pass "
        "wrote the resource but left that texel as it was. The capture records passes, not draws: a pass is one "
        "step, however many of its draws touched the pixel"},
       {}},
      {{"pick", "pick X Y",
        "the draw that covers output pixel (X, Y): its instance, mesh (index range) and material, found by running "
        "gbuffer.opaque again from its recorded inputs with one more target, the draw index (once per frame)"},
       {}},
      {{"buffer", "buffer RESOURCE [--element N]",
        "a buffer decoded field by field by the schema its pass declared, else as 32-bit words"},
       {{"--element", 1}}},
      {{"stats", "stats RESOURCE [--mip M] [--layer L] [--slice Z] [--rect X Y W H]",
        "per channel: min, max, mean of the finite values, a 16-bin histogram, NaN, Inf and denormal counts; "
        "--rect in output pixels"},
       {{"--mip", 1}, {"--layer", 1}, {"--slice", 1}, {"--rect", 4}}},
      {{"export",
        "export RESOURCE [--mip M] [--layer L] [--slice Z] [--stencil] [--half] [--uncompressed] -o FILE.exr|FILE.png; "
        "export CLUSTERS --heatmap [--slice Z] -o FILE.png; "
        "export PASS --all [--no-pictures] [--half] [--uncompressed] -o DIR",
        "FILE.exr: the values as float channels; FILE.png: a picture for its kind (normals as colour, depth "
        "linearised, motion on a colour wheel, HDR tonemapped; --stencil: stencil classes as a palette). --all: "
        "every output of PASS into DIR, images as RESOURCE.exr and RESOURCE.png (and RESOURCE.stencil.png), "
        "buffers as their raw bytes, RESOURCE.bin. --heatmap: a light-cluster image (lights.clusters) as the "
        "length of each tile's longest list over its slices (or of slice Z), one block of the cluster tile's size "
        "per tile so it lies over the frame, from dark blue (1 light) to white (the longest); --json adds the "
        "longest and the mean over tiles with a list. EXR channels are FLOAT and ZIP-compressed unless --half (HALF, "
        "as "
        "RenderDoc writes them) or --uncompressed; --no-pictures: --all writes no PNG"},
       {{"--mip", 1},
        {"--layer", 1},
        {"--slice", 1},
        {"--stencil", 0},
        {"--all", 0},
        {"--no-pictures", 0},
        {"--half", 0},
        {"--uncompressed", 0},
        {"--heatmap", 0},
        {"-o", 1}}},
      {{"replay", "replay [--set PARAM=VALUE]... [--shader FILE]",
        "run the current pass again from its recorded inputs on the session's device (inspect --device), with its "
        "parameter PARAM or its shader of FILE's stage (.vert/.frag/.comp) replaced, and compare each output with "
        "the recorded one: the bytes, and the output's comparison contract"},
       {{"--set", 1}, {"--shader", 1}}},
      {{"nan", "nan [--this-frame] [--limit N]",
        "where NaNs and Infs were born: walks every recorded frame's passes in order (--this-frame: only the "
        "current frame's) and names each pass that wrote a NaN or an Inf into a float output (colour, float depth, "
        "buffer fields their schema declares f32/f64) while every input it read, the version it modified among "
        "them, held finite values (passes that carry one on are not named), and each version no searched pass "
        "wrote that holds one, where it is first read; with how many, the first N (default 8) texels at their "
        "output pixels and there the values of every image input of the pass (mip 0, layer 0), or the first N "
        "buffer elements and fields. It checks each pass's outputs: the capture records per pass, not per draw"},
       {{"--this-frame", 0}, {"--limit", 1}}},
      {{"help", "help [COMMAND]", "the commands, or one command's usage"}, {}},
      {{"quit", "quit", "end the session"}, {}},
  };
  return table;
}

const CommandSpec* spec_of(const std::string& name) {
  for (const CommandSpec& spec : specs())
    if (spec.help.name == name) return &spec;
  return nullptr;
}

Arguments parse_arguments(const CommandSpec& spec, const std::vector<std::string>& words) {
  Arguments args;
  for (size_t i = 1; i < words.size(); ++i) {
    const std::string& word = words[i];
    if (word.size() < 2 || word[0] != '-') {
      args.positional.push_back(word);
      continue;
    }
    int count = 0;
    if (word != "--json") {
      const auto found = spec.options.find(word);
      if (found == spec.options.end()) throw InspectError(spec.help.name + ": unknown option " + word);
      count = found->second;
    }
    if (i + count >= words.size())
      throw InspectError(spec.help.name + ": " + word + " takes " + std::to_string(count) + " value(s)");
    std::vector<std::string>& values = args.options[word];
    for (int k = 0; k < count; ++k) values.push_back(words[++i]);
  }
  return args;
}

uint32_t parse_index(const std::string& what, const std::string& text) {
  if (text.empty() || text.size() > 9 || text.find_first_not_of("0123456789") != std::string::npos)
    throw InspectError(what + " '" + text + "': expected a whole number");
  return uint32_t(std::stoul(text));
}

uint32_t option_index(const Arguments& args, const std::string& option, uint32_t fallback) {
  return args.has(option) ? parse_index(option, args.options.at(option)[0]) : fallback;
}

Subimage subimage_of(const Arguments& args) {
  return {option_index(args, "--mip", 0), option_index(args, "--layer", 0), option_index(args, "--slice", 0)};
}

void expect_positionals(const CommandSpec& spec, const Arguments& args, size_t min, size_t max) {
  if (args.positional.size() < min || args.positional.size() > max)
    throw InspectError(spec.help.name + ": usage: " + spec.help.usage);
}

std::string format_ms(const std::optional<double>& value) {
  if (!value) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << *value;
  return s.str();
}

std::string shape(const ResourceRecord& r) {
  if (r.is_buffer) return std::to_string(r.buffer_size) + " B";
  std::string text = std::string(format_info(r.format)->name) + " " + std::to_string(r.extent.width) + "x" +
                     std::to_string(r.extent.height);
  if (r.extent.depth > 1) text += "x" + std::to_string(r.extent.depth);
  if (r.extent.mips > 1) text += " mips " + std::to_string(r.extent.mips);
  if (r.extent.layers > 1) text += " layers " + std::to_string(r.extent.layers);
  return text;
}

ojson resource_json(const ResourceRecord& r, bool output) {
  ojson j = {{"resource", r.resource}, {"kind", r.kind.name()}};
  if (r.is_buffer) {
    j["format"] = "BUFFER";
    j["bytes"] = r.buffer_size;
  } else {
    j["format"] = format_info(r.format)->name;
    j["width"] = r.extent.width;
    j["height"] = r.extent.height;
    j["depth"] = r.extent.depth;
    j["mips"] = r.extent.mips;
    j["layers"] = r.extent.layers;
    j["bytes"] = r.raw_bytes();
  }
  j["hash"] = r.hash;
  if (output) {
    j["contract"] = {{"kind", contract_kind_name(r.contract.kind)},
                     {"description", contract_description(r.contract)},
                     {"reason", r.contract.reason}};
    if (r.schema) j["schema"] = to_json(*r.schema);
  }
  return j;
}

// A JSON value on one line for people: numbers with 6 significant digits, arrays in brackets.
std::string brief(const ojson& value) {
  if (value.is_number_float()) {
    std::ostringstream s;
    s << std::setprecision(6) << value.get<double>();
    return s.str();
  }
  if (value.is_array()) {
    std::string text = "(";
    for (size_t i = 0; i < value.size(); ++i) text += (i ? ", " : "") + brief(value[i]);
    return text + ")";
  }
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

// JSON has no NaN or Inf: those are named.
ojson number_or_name(double value) {
  if (std::isnan(value)) return "NaN";
  if (std::isinf(value)) return value > 0 ? "+Inf" : "-Inf";
  return value;
}

// Flattened "a.b.c: value" lines, for pipeline and sampler state.
void print_flat(std::ostream& out, const nlohmann::json& value, const std::string& prefix) {
  if (value.is_object()) {
    for (const auto& [key, item] : value.items()) print_flat(out, item, prefix.empty() ? key : prefix + "." + key);
  } else if (value.is_array() && !value.empty() && (value[0].is_object() || value[0].is_array())) {
    for (size_t i = 0; i < value.size(); ++i) print_flat(out, value[i], prefix + "[" + std::to_string(i) + "]");
  } else {
    out << "  " << prefix << ": " << (value.is_string() ? value.get<std::string>() : value.dump()) << "\n";
  }
}

class Runner {
 public:
  Runner(InspectSession& session, std::ostream& out, bool json, bool& finished,
         std::map<uint32_t, DrawIdImage>& draw_ids)
      : session_(session), out_(out), json_(json), finished_(finished), draw_ids_(draw_ids) {}

  void run(const CommandSpec& spec, const Arguments& args) {
    static const std::map<std::string, void (Runner::*)(const CommandSpec&, const Arguments&)> handlers = {
        {"passes", &Runner::passes},     {"goto", &Runner::go},        {"next", &Runner::go},
        {"prev", &Runner::go},           {"frame", &Runner::frame},    {"info", &Runner::info},
        {"pipeline", &Runner::pipeline}, {"shader", &Runner::shader},  {"pixel", &Runner::pixel},
        {"buffer", &Runner::buffer},     {"stats", &Runner::stats},    {"export", &Runner::export_files},
        {"history", &Runner::history},   {"pick", &Runner::pick_draw}, {"replay", &Runner::replay},
        {"nan", &Runner::nan_origin},    {"help", &Runner::help},      {"quit", &Runner::quit}};
    (this->*handlers.at(spec.help.name))(spec, args);
  }

 private:
  void emit(const ojson& j) { out_ << j.dump() << "\n"; }

  ojson where() const {
    return {{"frame", session_.frame().index}, {"pass", session_.pass().name}, {"index", session_.pass_index()}};
  }

  void passes(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    const FrameRecord& frame = session_.frame();
    ojson list = ojson::array();
    for (const PassRecord& p : frame.passes) {
      ojson pass = {{"name", p.name}, {"status", p.ran ? "ran" : "skipped"}};
      if (!p.ran) pass["reason"] = p.reason;
      pass["gpu_ms"] = p.gpu_ms ? ojson(*p.gpu_ms) : ojson(nullptr);
      pass["cpu_ms"] = p.cpu_ms;
      ojson outputs = ojson::array();
      for (const ResourceRecord& r : p.outputs) outputs.push_back(r.resource);
      pass["outputs"] = outputs;
      list.push_back(pass);
    }
    if (json_) return emit({{"frame", frame.index}, {"current", session_.pass().name}, {"passes", list}});
    out_ << "frame " << frame.index << "\n";
    for (size_t i = 0; i < frame.passes.size(); ++i) {
      const PassRecord& p = frame.passes[i];
      out_ << (i == session_.pass_index() ? "> " : "  ") << std::left << std::setw(20) << p.name << std::setw(9)
           << (p.ran ? "ran" : "skipped") << std::right << std::setw(10) << format_ms(p.gpu_ms) << std::setw(10)
           << format_ms(p.cpu_ms) << "  ";
      if (!p.ran) out_ << "(" << p.reason << ") ";
      for (const ResourceRecord& r : p.outputs) out_ << r.resource << " ";
      out_ << "\n";
    }
  }

  void go(const CommandSpec& spec, const Arguments& args) {
    if (spec.help.name == "goto") {
      expect_positionals(spec, args, 1, 1);
      session_.go_to_pass(args.positional[0]);
    } else {
      expect_positionals(spec, args, 0, 0);
      spec.help.name == "next" ? session_.next_pass() : session_.previous_pass();
    }
    show_current();
  }

  void show_current() {
    const PassRecord& p = session_.pass();
    if (json_) return emit(where());
    out_ << "frame " << session_.frame().index << ", pass " << session_.pass_index() + 1 << "/"
         << session_.frame().passes.size() << ": " << p.name << (p.ran ? "" : " (skipped: " + p.reason + ")") << "\n";
  }

  void frame(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 1);
    if (!args.positional.empty()) session_.go_to_frame(parse_index("frame", args.positional[0]));
    const FrameRecord& f = session_.frame();
    ojson frames = ojson::array();
    for (const FrameRecord& r : session_.capture().manifest().frames) frames.push_back(r.index);
    if (json_) {
      ojson j = where();
      j["time"] = f.time;
      j["camera_cut"] = f.camera_cut;
      j["width"] = f.width;
      j["height"] = f.height;
      j["recorded_frames"] = frames;
      return emit(j);
    }
    out_ << "frame " << f.index << " of recorded " << brief(frames) << ", " << f.width << "x" << f.height << " at "
         << f.time << " s" << (f.camera_cut ? ", camera cut" : "") << "; pass " << session_.pass().name << "\n";
  }

  void info(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    const PassRecord& p = session_.pass();
    ojson j = where();
    j["status"] = p.ran ? "ran" : "skipped";
    if (!p.ran) j["reason"] = p.reason;
    j["gpu_ms"] = p.gpu_ms ? ojson(*p.gpu_ms) : ojson(nullptr);
    j["cpu_ms"] = p.cpu_ms;
    j["params"] = p.params;
    j["inputs"] = ojson::array();
    j["outputs"] = ojson::array();
    for (const ResourceRecord& r : p.inputs) j["inputs"].push_back(resource_json(r, false));
    for (const ResourceRecord& r : p.outputs) j["outputs"].push_back(resource_json(r, true));
    if (json_) return emit(j);
    show_current();
    out_ << "  gpu " << format_ms(p.gpu_ms) << " ms, cpu " << format_ms(p.cpu_ms) << " ms\n";
    for (const auto& [name, value] : p.params) {
      out_ << "  param " << name << " = " << value;
      for (const ParamDecl& type : p.param_types)
        if (type.name == name)
          out_ << " (" << type_name(type.type) << (type.group.empty() ? "" : ", set as " + type.group + "." + name)
               << ")";
      out_ << "\n";
    }
    out_ << "  reads:\n";
    for (const ResourceRecord& r : p.inputs)
      out_ << "    " << std::left << std::setw(26) << r.resource << r.kind.name() << ", " << shape(r) << ", "
           << r.hash.substr(0, 12) << "\n";
    out_ << "  writes:\n";
    for (const ResourceRecord& r : p.outputs) {
      out_ << "    " << std::left << std::setw(26) << r.resource << r.kind.name() << ", " << shape(r) << ", "
           << r.hash.substr(0, 12) << "\n"
           << "      contract: " << contract_description(r.contract)
           << (r.contract.reason.empty() ? "" : " (" + r.contract.reason + ")") << "\n";
      if (r.schema) out_ << "      schema: " << to_json(*r.schema).dump() << "\n";
    }
  }

  void pipeline(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    const PassRecord& p = session_.pass();
    if (json_) {
      ojson j = where();
      j["pipelines"] = ojson::parse(p.pipelines.dump());
      j["samplers"] = ojson::parse(p.samplers.dump());
      return emit(j);
    }
    show_current();
    if (p.pipelines.empty()) out_ << "  no pipeline recorded (" << (p.ran ? "a CPU pass" : "skipped") << ")\n";
    for (size_t i = 0; i < p.pipelines.size(); ++i) {
      out_ << "pipeline " << i << ":\n";
      print_flat(out_, p.pipelines[i], "");
    }
    for (size_t i = 0; i < p.samplers.size(); ++i) {
      out_ << "sampler " << i << ":\n";
      print_flat(out_, p.samplers[i], "");
    }
  }

  void shader(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 1);
    const PassRecord& p = session_.pass();
    const std::string wanted = args.positional.empty() ? "" : args.positional[0];
    ojson list = ojson::array();
    for (const ShaderRecord& s : p.shaders) {
      if (!wanted.empty() &&
          (s.path.size() < wanted.size() || s.path.compare(s.path.size() - wanted.size(), wanted.size(), wanted) != 0))
        continue;
      const std::vector<uint32_t> words = session_.capture().load_shader(s);
      list.push_back({{"path", s.path},
                      {"hash", s.hash},
                      {"glsl", session_.capture().load_shader_source(s)},
                      {"spirv", disassemble_spirv(words)}});
    }
    if (list.empty())
      throw InspectError(p.name + " has no shader" + (wanted.empty() ? "" : " ending in '" + wanted + "'") +
                         (p.shaders.empty() ? " (a CPU or skipped pass)" : ""));
    if (json_) {
      ojson j = where();
      j["shaders"] = list;
      return emit(j);
    }
    for (const ojson& s : list)
      out_ << "// " << s["path"].get<std::string>() << ": GLSL\n"
           << s["glsl"].get<std::string>() << "\n// " << s["path"].get<std::string>() << ": SPIR-V\n"
           << s["spirv"].get<std::string>();
  }

  // One texel of one version: its hash, the raw channel values, the stored codes and what they mean.
  ojson texel_json(const ResourceRecord& record, const FrameRecord& frame, const TexelAddress& texel) {
    const PixelReading reading = read_pixel(record, session_.load(record), frame, texel);
    ojson j = {{"hash", record.hash}, {"raw", reading.values.raw}};
    if (!reading.values.codes.empty()) j["codes"] = reading.values.codes;
    j["decoded"] = reading.decoded;
    return j;
  }

  ojson reading_json(const ResourceRecord& record, const FrameRecord& frame, uint32_t x, uint32_t y,
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

  void print_reading(const ojson& j) {
    out_ << j["resource"].get<std::string>() << " (" << j["kind"].get<std::string>() << ", "
         << j["format"].get<std::string>() << ") frame " << j["frame"] << " texel " << brief(j["texel"]) << " mip "
         << j["mip"] << " layer " << j["layer"] << (j.contains("slice") ? " slice " + j["slice"].dump() : "") << "\n";
    out_ << "  raw: " << brief(j["raw"]) << "\n";
    if (j.contains("codes")) out_ << "  codes: " << brief(j["codes"]) << "\n";
    for (const auto& [name, value] : j["decoded"].items()) out_ << "  " << name << ": " << brief(value) << "\n";
  }

  // An image whose texels index lists (lights.clusters) under a pixel: the texel of its tile, in
  // the depth slice where the kind's linear depth resource (depth.linear) puts the pixel or at
  // --slice, and that texel's list from the kind's buffer (lights.cluster_indices).
  void listed(const ResourceRecord& record, uint32_t x, uint32_t y, Subimage subimage, bool slice_given) {
    const FrameRecord& frame = session_.frame();
    const KindInfo& kind = kind_info(record.kind);
    const TexelLists& lists = *kind.lists;
    std::optional<double> depth;
    if (!slice_given && kind.slices) {
      const PassRecord* writer = writer_of(record, frame);
      if (!writer)
        throw InspectError(record.resource + ": no pass of frame " + std::to_string(frame.index) +
                           " wrote this version");
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
      throw InspectError(record.resource + ": the list at " + std::to_string(offset) + " runs past " +
                         entries.resource);
    std::vector<uint32_t> list(count);
    if (count) std::memcpy(list.data(), bytes.data() + offset * 4, count * 4);
    ojson& decoded = j["decoded"];
    decoded["froxel"] = {j["texel"][0], j["texel"][1], subimage.slice};
    if (depth) decoded["depth_m"] = *depth;
    decoded[lists.entries] = list;
    return json_ ? emit(j) : print_reading(j);
  }

  void pixel(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 2, 3);
    const uint32_t x = parse_index("X", args.positional[0]), y = parse_index("Y", args.positional[1]);
    const Subimage subimage = subimage_of(args);
    std::string name;
    if (args.positional.size() == 3) {
      name = args.positional[2];
    } else {
      const PassRecord& p = session_.pass();
      if (p.outputs.empty()) throw InspectError(p.name + " has no output: name a resource");
      name = p.outputs[0].resource;
    }
    const ResourceRecord& record = session_.resource(name);
    if (!args.has("--frames")) {
      if (kind_info(record.kind).lists) return listed(record, x, y, subimage, args.has("--slice"));
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

  void history(const CommandSpec& spec, const Arguments& args) {
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

  void pick_draw(const CommandSpec& spec, const Arguments& args) {
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

  void buffer(const CommandSpec& spec, const Arguments& args) {
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
        out_ << "word " << v["word"] << ": 0x" << hex.str() << " u32 " << v["u32"] << " f32 " << brief(v["f32"])
             << "\n";
      }
    }
  }

  void stats(const CommandSpec& spec, const Arguments& args) {
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

  void export_files(const CommandSpec& spec, const Arguments& args) {
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

  void nan_origin(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    const std::vector<FrameRecord>& frames = session_.capture().manifest().frames;
    const std::optional<size_t> only_frame =
        args.has("--this-frame") ? std::optional(session_.frame_position()) : std::nullopt;
    const Capture& capture = session_.capture();
    const std::vector<NanOrigin> origins = find_nan_origins(
        frames, only_frame, [&](const ResourceRecord& r) { return capture.load(r); }, option_index(args, "--limit", 8));
    ojson searched = ojson::array();
    for (size_t f = only_frame.value_or(0); f < (only_frame ? *only_frame + 1 : frames.size()); ++f)
      searched.push_back(frames[f].index);
    ojson listed = ojson::array();
    for (const NanOrigin& origin : origins) listed.push_back(origin_json(frames[origin.frame_position], origin));
    const ojson first = listed.empty() ? ojson(nullptr) : listed[0];
    if (json_) return emit({{"frames", searched}, {"origin", first}, {"origins", listed}});

    const std::string scope = searched.size() == 1 ? "frame " + searched[0].dump()
                                                   : "frames " + searched[0].dump() + "-" + searched.back().dump();
    if (listed.empty()) {
      out_ << scope << ": no pass wrote a NaN or an Inf\n";
      return;
    }
    out_ << scope << ": " << listed.size() << " origin(s) of a NaN or an Inf\n";
    for (const ojson& o : listed) {
      const std::string where = "frame " + o["frame"].dump() + ", " + o["pass"].get<std::string>() + " (pass " +
                                std::to_string(o["index"].get<size_t>() + 1) + "/" + o["passes"].dump() + ")";
      if (o["how"] == "born")
        out_ << (&o == &listed[0] ? "the first NaN or Inf was written by " : "then one was written by ") << where
             << "\n";
      else
        out_ << (&o == &listed[0] ? "the first NaN or Inf came in with an input no searched pass wrote, read by "
                                  : "then one came in with an input no searched pass wrote, read by ")
             << where << "\n";
      for (const ojson& resource : o["resources"]) print_non_finite(resource);
    }
  }

  ojson origin_json(const FrameRecord& frame, const NanOrigin& origin) {
    const PassRecord& pass = frame.passes[origin.pass_index];
    ojson resources = ojson::array();
    for (const NonFiniteValues& found : origin.resources) {
      const ResourceRecord& r = *found.resource;
      ojson j = {{"resource", r.resource}, {"count", found.count}};
      if (r.is_buffer) {
        ojson fields = ojson::array();
        for (const NonFiniteField& f : found.fields)
          fields.push_back({{"element", f.element}, {"field", f.field}, {"value", number_or_name(f.value)}});
        j["format"] = "buffer";
        j["fields"] = fields;
        resources.push_back(j);
        continue;
      }
      ojson texels = ojson::array();
      for (const NonFiniteTexel& t : found.texels) {
        ojson values = ojson::array(), inputs = ojson::array();
        for (double v : t.values) values.push_back(number_or_name(v));
        for (const ResourceRecord& in : pass.inputs)
          if (!in.is_buffer && kind_info(in.kind).over_output)
            inputs.push_back(reading_json(in, frame, t.pixel_x, t.pixel_y, {}));
        ojson texel = {{"pixel", {t.pixel_x, t.pixel_y}}, {"texel", {t.x, t.y}}, {"mip", t.mip}, {"layer", t.layer}};
        if (r.extent.depth > 1) texel["slice"] = t.slice;
        texel["values"] = values;
        texel["inputs"] = inputs;
        texels.push_back(texel);
      }
      j["format"] = format_info(r.format)->name;
      j["texels"] = texels;
      resources.push_back(j);
    }
    return {{"how", origin.how == NanOrigin::How::born ? "born" : "came_in"},
            {"frame", frame.index},
            {"pass", pass.name},
            {"index", origin.pass_index},
            {"passes", frame.passes.size()},
            {"resources", resources}};
  }

  void print_non_finite(const ojson& resource) {
    const bool buffer = resource.contains("fields");
    out_ << "  " << resource["resource"].get<std::string>() << " (" << resource["format"].get<std::string>()
         << "): " << resource["count"] << (buffer ? " field value(s)\n" : " texel(s)\n");
    if (buffer) {
      for (const ojson& f : resource["fields"])
        out_ << "    element " << f["element"] << " " << f["field"].get<std::string>() << ": " << brief(f["value"])
             << "\n";
      return;
    }
    for (const ojson& texel : resource["texels"]) {
      out_ << "    pixel " << brief(texel["pixel"]) << " texel " << brief(texel["texel"]) << " mip " << texel["mip"]
           << " layer " << texel["layer"] << (texel.contains("slice") ? " slice " + texel["slice"].dump() : "") << ": "
           << brief(texel["values"]) << "\n";
      for (const ojson& in : texel["inputs"]) {
        out_ << "      " << in["resource"].get<std::string>() << " texel " << brief(in["texel"]) << ": raw "
             << brief(in["raw"]);
        for (const auto& [name, value] : in["decoded"].items()) out_ << "; " << name << " " << brief(value);
        out_ << "\n";
      }
    }
  }

  void write_picture(const std::filesystem::path& file, const ResourceRecord& record, std::span<const uint8_t> raw,
                     const Subimage& subimage, VisualAspect aspect) {
    const Rgba8Image image = visualise(record, raw, session_.frame(), subimage, aspect);
    write_png(file, image.pixels, image.width, image.height);
  }

  void replay(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    const PassRecord& pass = session_.pass();
    if (!pass.ran)
      throw InspectError(pass.name + " was skipped in the capture (" + pass.reason + "): nothing to replay");
    ReplayOptions options;
    options.frame = session_.frame().index;
    options.passes = {pass.name};
    if (args.has("--set")) {
      // NAME=VALUE of this pass: a parameter it shares with a group is set as the group's.
      const std::vector<PassDecl> passes = all_passes();
      const PassDecl* decl = find_pass(passes, pass.name);
      for (const std::string& set : args.options.at("--set")) {
        const ParamDecl* param = decl ? decl->find_param(set.substr(0, set.find('='))) : nullptr;
        parse_set(passes, (param ? override_key(*decl, *param) : pass.name) + "." + set, options.params);
      }
    }
    if (args.has("--shader")) {
      if (args.options.at("--shader").size() > 1) throw InspectError("replay: one --shader at a time");
      options.shader_files[pass.name] = args.options.at("--shader")[0];
    }
    const ReplayReport report = replay_capture(session_.gpu(), session_.capture(), options);
    const PassReplay& result = report.passes.at(0);
    if (!result.replayed) throw InspectError(pass.name + ": not replayed: " + result.reason);
    ojson outputs = ojson::array();
    for (const OutputCheck& check : result.outputs) {
      ojson o = {{"resource", check.resource},
                 {"identical", check.verdict == Verdict::identical},
                 {"metric", check.metric},
                 {"max_abs", check.amount}};
      if (!check.first_difference.empty()) o["first_difference"] = check.first_difference;
      const ResourceRecord& recorded = session_.resource(check.resource);
      o["contract"] = {{"description", contract_description(recorded.contract)}};
      if (check.verdict == Verdict::identical) {
        o["contract"]["holds"] = true;
      } else if (check.contract) {
        o["contract"]["holds"] = check.contract->holds;
        o["contract"]["worst"] = check.contract->worst;
        o["contract"]["bound"] = check.contract->bound;
        o["contract"]["measure"] = check.contract->measure;
      } else {
        o["contract"]["holds"] = false;  // not produced, or another size: nothing to measure
      }
      outputs.push_back(o);
    }
    ojson j = where();
    j["device"] = report.device;
    j["gpu_ms"] = result.gpu_ms ? ojson(*result.gpu_ms) : ojson(nullptr);
    j["recorded_gpu_ms"] = pass.gpu_ms ? ojson(*pass.gpu_ms) : ojson(nullptr);
    j["notes"] = result.notes;
    j["outputs"] = outputs;
    if (json_) return emit(j);
    out_ << "replayed " << pass.name << " on " << report.device << ": gpu " << format_ms(result.gpu_ms)
         << " ms (recorded " << format_ms(pass.gpu_ms) << " ms)\n";
    for (const std::string& note : result.notes) out_ << "  note: " << note << "\n";
    for (const ojson& o : outputs) {
      out_ << "  " << std::left << std::setw(24) << o["resource"].get<std::string>();
      if (o["identical"].get<bool>()) {
        out_ << "identical\n";
        continue;
      }
      const ojson& c = o["contract"];
      out_ << "differs (" << o["metric"].get<std::string>() << ", max abs " << brief(o["max_abs"])
           << (o.contains("first_difference") ? ", first at " + o["first_difference"].get<std::string>() : "")
           << "); contract " << c["description"].get<std::string>() << ": "
           << (c["holds"].get<bool>() ? "holds" : "broken");
      if (c.contains("worst")) out_ << " (worst " << brief(c["worst"]) << " " << c["measure"].get<std::string>() << ")";
      out_ << "\n";
    }
  }

  void help(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 1);
    if (args.positional.empty()) {
      ojson list = ojson::array();
      for (const InspectCommandHelp& c : inspect_commands())
        list.push_back({{"name", c.name}, {"usage", c.usage}, {"summary", c.summary}});
      if (json_) return emit({{"commands", list}});
      for (const InspectCommandHelp& c : inspect_commands())
        out_ << "  " << std::left << std::setw(56) << c.usage << c.summary << "\n";
      out_ << "Every command takes --json: one JSON object per command.\n";
      return;
    }
    const CommandSpec* wanted = spec_of(args.positional[0]);
    if (!wanted) throw InspectError("no command '" + args.positional[0] + "' (see `help`)");
    if (json_)
      return emit({{"name", wanted->help.name}, {"usage", wanted->help.usage}, {"summary", wanted->help.summary}});
    out_ << "usage: " << wanted->help.usage << " [--json]\n  " << wanted->help.summary << "\n";
  }

  void quit(const CommandSpec& spec, const Arguments& args) {
    expect_positionals(spec, args, 0, 0);
    finished_ = true;
    if (json_) emit({{"quit", true}});
  }

  InspectSession& session_;
  std::ostream& out_;
  bool json_;
  bool& finished_;
  std::map<uint32_t, DrawIdImage>& draw_ids_;
};

std::vector<std::string> words_of(const std::string& command) {
  std::istringstream stream(command);
  std::vector<std::string> words;
  for (std::string word; stream >> word;) words.push_back(word);
  return words;
}

}  // namespace

const std::vector<InspectCommandHelp>& inspect_commands() {
  static const std::vector<InspectCommandHelp> list = [] {
    std::vector<InspectCommandHelp> l;
    for (const CommandSpec& spec : specs()) l.push_back(spec.help);
    return l;
  }();
  return list;
}

std::vector<std::string> split_commands(const std::string& script) {
  std::vector<std::string> commands;
  std::istringstream lines(script);
  for (std::string line; std::getline(lines, line);) {
    const size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    std::istringstream parts(line);
    for (std::string part; std::getline(parts, part, ';');)
      if (part.find_first_not_of(" \t\r") != std::string::npos) commands.push_back(part);
  }
  return commands;
}

InspectCommands::InspectCommands(InspectSession& session, std::ostream& out, std::ostream& err)
    : session_(session), out_(out), err_(err) {}

bool InspectCommands::run(const std::string& command) {
  const std::vector<std::string> words = words_of(command);
  if (words.empty()) return true;
  try {
    const CommandSpec* spec = spec_of(words[0]);
    if (!spec) throw InspectError("unknown command '" + words[0] + "' (see `help`)");
    const Arguments args = parse_arguments(*spec, words);
    Runner(session_, out_, args.has("--json"), finished_, draw_ids_).run(*spec, args);
    out_.flush();
    return true;
  } catch (const std::exception& e) {
    // CaptureError (a damaged blob) ends this command only: the session can go on with others.
    err_ << "inspect: " << e.what() << "\n";
    err_.flush();
    return false;
  }
}

}  // namespace nightcap
