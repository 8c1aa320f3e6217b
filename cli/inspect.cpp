// `inspect`: a capture stepped through pass by pass, interactively or by a script of commands.
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/command.h"
#include "cli/inspect_repl.h"
#include "inspect/commands.h"

namespace nc = nightcap;

namespace nightcap::cli {

namespace {

// Interactive without -c or --script. Scripted, every command runs (a failed one does not stop
// the others) and the exit code says whether any failed.
int run_inspect(const std::string& path, const std::string& commands, const std::string& script_file,
                const std::string& device) {
  nc::InspectSession session(nc::Capture::open(path), {device, validation_requested()});
  nc::InspectCommands runner(session, std::cout, std::cerr);
  if (commands.empty() && script_file.empty()) {
    nc::run_interactive_inspect(session, runner);
    return 0;
  }
  std::string script = commands;
  if (!script_file.empty()) {
    std::ifstream file(script_file, std::ios::binary);
    if (!file) throw UsageError("--script " + script_file + ": cannot read");
    std::ostringstream text;
    text << file.rdbuf();
    script = text.str();
  }
  bool failed = false;
  for (const std::string& command : nc::split_commands(script)) {
    failed |= !runner.run(command);
    if (runner.finished()) break;
  }
  return failed ? kExitBadInput : 0;
}

std::string inspect_commands_help() {
  std::string text = "Commands (every one takes --json; `help CMD` inside a session):\n";
  for (const nc::InspectCommandHelp& c : nc::inspect_commands()) text += "  " + c.usage + "\n      " + c.summary + "\n";
  return text;
}

}  // namespace

Command add_inspect_command(CLI::App& app) {
  struct Flags {
    std::string capture, commands, script, device;
  };
  auto flags = std::make_shared<Flags>();
  auto* inspect = app.add_subcommand(
      "inspect", "Step through a capture pass by pass: pixels, buffers and statistics decoded by what they hold");
  inspect->add_option("capture", flags->capture, "capture folder")->required();
  auto* commands_option =
      inspect->add_option("-c,--commands", flags->commands, "run these commands (separated by ';') and exit");
  inspect->add_option("--script", flags->script, "run the commands of FILE (one a line, or separated by ';') and exit")
      ->excludes(commands_option);
  inspect->add_option("--device", flags->device,
                      "Vulkan device for the commands that run a pass again (replay, pick); default: lavapipe");
  inspect->footer(inspect_commands_help() +
                  "Without -c or --script the session is interactive (history, tab completion). Scripted, the exit "
                  "code is 2 if any command failed, else 0.");
  return {inspect, [flags] { return run_inspect(flags->capture, flags->commands, flags->script, flags->device); }};
}
}  // namespace nightcap::cli
