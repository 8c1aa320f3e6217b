// `passes`, `goto`, `next`, `prev`, `frame`, `info`, `pipeline` and `shader`: the frame, its passes
// and what the current one read, wrote and bound.
#include <algorithm>
#include <iomanip>

#include "inspect/command_runner.h"
#include "inspect/disassemble.h"

namespace nightcap::inspect_cli {

void Runner::passes(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 0, 0);
  const FrameRecord& frame = session_.frame();
  ojson list = ojson::array();
  for (const PassRecord& p : frame.passes) {
    ojson pass = {{"name", p.name}, {"status", p.ran ? "ran" : "skipped"}};
    if (!p.ran) pass["reason"] = p.reason;
    pass["time_ms"] = p.time_ms;
    pass["clock"] = pass_clock_name(p.clock);
    pass["gpu_ms"] = p.gpu_ms ? ojson(*p.gpu_ms) : ojson(nullptr);
    pass["cpu_ms"] = p.cpu_ms;
    ojson outputs = ojson::array();
    for (const ResourceRecord& r : p.outputs) outputs.push_back(r.resource);
    pass["outputs"] = outputs;
    list.push_back(pass);
  }
  if (json_) return emit({{"frame", frame.index}, {"current", session_.pass().name}, {"passes", list}});
  out_ << "frame " << frame.index << "\n";
  size_t name_width = 20;
  for (const PassRecord& p : frame.passes) name_width = std::max(name_width, p.name.size() + 1);
  for (size_t i = 0; i < frame.passes.size(); ++i) {
    const PassRecord& p = frame.passes[i];
    out_ << (i == session_.pass_index() ? "> " : "  ") << std::left << std::setw(int(name_width)) << p.name
         << std::setw(9) << (p.ran ? "ran" : "skipped") << std::right << std::setw(10)
         << (p.ran ? format_ms(p.time_ms) : std::string("-")) << " ms  " << std::left << std::setw(11)
         << (p.ran ? pass_clock_name(p.clock) : "") << std::right;
    if (!p.ran) out_ << "(" << p.reason << ") ";
    for (const ResourceRecord& r : p.outputs) out_ << r.resource << " ";
    out_ << "\n";
  }
}

void Runner::go(const CommandSpec& spec, const Arguments& args) {
  if (spec.help.name == "goto") {
    expect_positionals(spec, args, 1, 1);
    session_.go_to_pass(args.positional[0]);
  } else {
    expect_positionals(spec, args, 0, 0);
    spec.help.name == "next" ? session_.next_pass() : session_.previous_pass();
  }
  show_current();
}

void Runner::show_current() {
  const PassRecord& p = session_.pass();
  if (json_) return emit(where());
  out_ << "frame " << session_.frame().index << ", pass " << session_.pass_index() + 1 << "/"
       << session_.frame().passes.size() << ": " << p.name << (p.ran ? "" : " (skipped: " + p.reason + ")") << "\n";
}

void Runner::frame(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 0, 1);
  if (!args.positional.empty()) session_.go_to_frame(parse_index("frame", args.positional[0]));
  const FrameRecord& f = session_.frame();
  ojson frames = ojson::array();
  for (const FrameRecord& r : session_.capture().manifest().frames) frames.push_back(r.index);
  if (json_) {
    ojson j = where();
    j["time"] = f.time;
    j["wall_ms"] = f.wall_ms ? ojson(*f.wall_ms) : ojson(nullptr);
    j["camera_cut"] = f.camera_cut;
    j["width"] = f.width;
    j["height"] = f.height;
    j["recorded_frames"] = frames;
    return emit(j);
  }
  out_ << "frame " << f.index << " of recorded " << brief(frames) << ", " << f.width << "x" << f.height << " at "
       << f.time << " s" << (f.camera_cut ? ", camera cut" : "") << "; pass " << session_.pass().name << "\n";
}

void Runner::info(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 0, 0);
  const PassRecord& p = session_.pass();
  ojson j = where();
  j["status"] = p.ran ? "ran" : "skipped";
  if (!p.ran) j["reason"] = p.reason;
  j["time_ms"] = p.time_ms;
  j["clock"] = pass_clock_name(p.clock);
  j["gpu_ms"] = p.gpu_ms ? ojson(*p.gpu_ms) : ojson(nullptr);
  j["cpu_ms"] = p.cpu_ms;
  j["params"] = p.params;
  j["inputs"] = ojson::array();
  j["outputs"] = ojson::array();
  for (const ResourceRecord& r : p.inputs) j["inputs"].push_back(resource_json(r, false));
  for (const ResourceRecord& r : p.outputs) j["outputs"].push_back(resource_json(r, true));
  if (json_) return emit(j);
  show_current();
  if (p.ran)
    out_ << "  " << format_ms(p.time_ms) << " ms by the " << pass_clock_name(p.clock) << " clock; gpu timestamps "
         << format_ms(p.gpu_ms) << " ms, cpu " << format_ms(p.cpu_ms) << " ms\n";
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

void Runner::pipeline(const CommandSpec& spec, const Arguments& args) {
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

void Runner::shader(const CommandSpec& spec, const Arguments& args) {
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

}  // namespace nightcap::inspect_cli
