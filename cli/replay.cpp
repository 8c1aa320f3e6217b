// `replay`: passes of a capture run again from their recorded inputs, with changed parameters or
// shaders, and their outputs verified against the recorded ones.
#include <iostream>
#include <memory>

#include "cli/command.h"
#include "passes/assembly/frame_passes.h"
#include "replay/replay.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

int run_replay(const std::string& path, uint32_t frame, const std::vector<std::string>& pass_names,
               const std::vector<std::string>& sets, const std::vector<std::string>& shaders, const std::string& device,
               bool verify, bool chain, bool json) {
  nc::ReplayOptions options;
  options.frame = frame;
  options.passes = pass_names;
  options.chain = chain;
  for (const std::string& s : sets) nc::parse_set(nc::all_passes(), s, options.params);
  for (const std::string& s : shaders) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == s.size())
      throw UsageError("--shader '" + s + "': expected PASS=FILE");
    options.shader_files[s.substr(0, eq)] = s.substr(eq + 1);
  }
  const nc::Capture capture = nc::Capture::open(path);
  nc::GpuDevice gpu({device, validation_requested()});
  const nc::ReplayReport report = nc::replay_capture(gpu, capture, options);
  if (json) {
    nlohmann::json out = {{"frame", report.frame}, {"device", report.device}, {"passes", nlohmann::json::array()}};
    for (const nc::PassReplay& p : report.passes) {
      nlohmann::json pass = {{"name", p.name}, {"replayed", p.replayed}, {"notes", p.notes}};
      if (!p.replayed) pass["reason"] = p.reason;
      if (p.replayed) {
        pass["time_ms"] = p.time_ms;
        pass["clock"] = nc::pass_clock_name(p.clock);
      }
      pass["gpu_ms"] = p.gpu_ms ? nlohmann::json(*p.gpu_ms) : nlohmann::json(nullptr);
      pass["cpu_ms"] = p.cpu_ms;
      if (verify) {
        pass["outputs"] = nlohmann::json::array();
        for (const nc::OutputCheck& o : p.outputs) {
          pass["outputs"].push_back({{"resource", o.resource},
                                     {"verdict", nc::verdict_name(o.verdict)},
                                     {"metric", o.metric},
                                     {"max_abs", o.amount},
                                     {"recorded_hash", o.recorded_hash},
                                     {"replayed_hash", o.replayed_hash}});
          if (!o.first_difference.empty()) pass["outputs"].back()["first_difference"] = o.first_difference;
          if (o.contract)
            pass["outputs"].back()["contract"] = {{"holds", o.contract->holds},
                                                  {"worst", o.contract->worst},
                                                  {"bound", o.contract->bound},
                                                  {"measure", o.contract->measure}};
        }
      }
      out["passes"].push_back(pass);
    }
    out["different"] = verify && report.any_different();
    std::cout << out.dump(1) << "\n";
  } else {
    std::cout << "replay of frame " << report.frame << " on " << report.device << "\n";
    for (const nc::PassReplay& p : report.passes) {
      std::cout << "  " << std::left << std::setw(20) << p.name;
      if (!p.replayed) {
        std::cout << "not replayed: " << p.reason << "\n";
        continue;
      }
      std::cout << ms(p.time_ms) << " ms (" << nc::pass_clock_name(p.clock) << " clock; gpu timestamps " << ms(p.gpu_ms)
                << " ms)\n";
      for (const std::string& note : p.notes) std::cout << "      note: " << note << "\n";
      if (!verify) continue;
      for (const nc::OutputCheck& o : p.outputs) {
        std::cout << "      " << std::left << std::setw(24) << o.resource << nc::verdict_name(o.verdict);
        if (o.verdict != nc::Verdict::identical)
          std::cout << " (" << o.metric << ", max abs " << o.amount
                    << (o.first_difference.empty() ? "" : ", first at " + o.first_difference) << ")";
        std::cout << "\n";
      }
    }
    if (verify)
      std::cout << (report.any_different() ? "replay differs from the capture\n" : "replay matches the capture\n");
  }
  return verify && report.any_different() ? kExitDifferent : 0;
}

}  // namespace

Command add_replay_command(CLI::App& app) {
  struct Flags {
    std::string capture, device;
    uint32_t frame = 0;
    std::vector<std::string> passes, sets, shaders;
    bool verify = false, chain = false, json = false;
  };
  auto flags = std::make_shared<Flags>();
  auto* replay = app.add_subcommand("replay", "Re-execute passes of a capture from their recorded inputs");
  replay->add_option("capture", flags->capture, "capture folder")->required();
  replay->add_option("--frame", flags->frame, "frame index")->capture_default_str();
  replay->add_option("--pass", flags->passes, "pass to replay (repeatable; default: every pass that ran)");
  replay->add_option("--set", flags->sets, "PASS.PARAM=VALUE parameter override (repeatable)");
  replay->add_option("--shader", flags->shaders,
                     "PASS=FILE: replace the pass's shader of FILE's stage (.vert/.frag/.comp)");
  replay->add_option("--device", flags->device, "Vulkan device name (substring); default: lavapipe");
  replay->add_flag("--verify", flags->verify, "compare every output with the recorded one (exit 1 if any differs)");
  replay->add_flag("--chain", flags->chain, "feed replayed outputs to later passes instead of the recorded inputs");
  replay->add_flag("--json", flags->json, "machine-readable output");
  return {replay, [flags] {
            return run_replay(flags->capture, flags->frame, flags->passes, flags->sets, flags->shaders, flags->device,
                              flags->verify, flags->chain, flags->json);
          }};
}
}  // namespace nightcap::cli
