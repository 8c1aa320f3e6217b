// `nan` and `replay`: where a NaN or Inf first appeared, and the current pass run again and compared.
#include <iomanip>

#include "inspect/command_runner.h"
#include "passes/assembly/frame_passes.h"
#include "replay/replay.h"

namespace nightcap::inspect_cli {

void Runner::nan_origin(const CommandSpec& spec, const Arguments& args) {
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
      out_ << (&o == &listed[0] ? "the first NaN or Inf was written by " : "then one was written by ") << where << "\n";
    else
      out_ << (&o == &listed[0] ? "the first NaN or Inf came in with an input no searched pass wrote, read by "
                                : "then one came in with an input no searched pass wrote, read by ")
           << where << "\n";
    for (const ojson& resource : o["resources"]) print_non_finite(resource);
  }
}

ojson Runner::origin_json(const FrameRecord& frame, const NanOrigin& origin) {
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

void Runner::print_non_finite(const ojson& resource) {
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

void Runner::replay(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 0, 0);
  const PassRecord& pass = session_.pass();
  if (!pass.ran) throw InspectError(pass.name + " was skipped in the capture (" + pass.reason + "): nothing to replay");
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
  j["time_ms"] = result.time_ms;
  j["clock"] = pass_clock_name(result.clock);
  j["recorded_time_ms"] = pass.time_ms;
  j["recorded_clock"] = pass_clock_name(pass.clock);
  j["gpu_ms"] = result.gpu_ms ? ojson(*result.gpu_ms) : ojson(nullptr);
  j["recorded_gpu_ms"] = pass.gpu_ms ? ojson(*pass.gpu_ms) : ojson(nullptr);
  j["notes"] = result.notes;
  j["outputs"] = outputs;
  if (json_) return emit(j);
  out_ << "replayed " << pass.name << " on " << report.device << ": " << format_ms(result.time_ms) << " ms by the "
       << pass_clock_name(result.clock) << " clock (recorded " << format_ms(pass.time_ms) << " ms by the "
       << pass_clock_name(pass.clock) << " clock)\n";
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

}  // namespace nightcap::inspect_cli
