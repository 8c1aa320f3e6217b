#include "inspect/commands.h"

#include <iomanip>
#include <sstream>

#include "inspect/command_runner.h"

namespace nightcap {
namespace inspect_cli {

void Runner::run(const CommandSpec& spec, const Arguments& args) {
  static const std::map<std::string, void (Runner::*)(const CommandSpec&, const Arguments&)> handlers = {
      {"passes", &Runner::passes},
      {"goto", &Runner::go},
      {"next", &Runner::go},
      {"prev", &Runner::go},
      {"frame", &Runner::frame},
      {"info", &Runner::info},
      {"pipeline", &Runner::pipeline},
      {"shader", &Runner::shader},
      {"pixel", &Runner::pixel},
      {"direction", &Runner::direction},
      {"buffer", &Runner::buffer},
      {"stats", &Runner::stats},
      {"export", &Runner::export_files},
      {"history", &Runner::history},
      {"pick", &Runner::pick_draw},
      {"replay", &Runner::replay},
      {"nan", &Runner::nan_origin},
      {"help", &Runner::help},
      {"quit", &Runner::quit}};
  (this->*handlers.at(spec.help.name))(spec, args);
}

ojson Runner::where() const {
  return {{"frame", session_.frame().index}, {"pass", session_.pass().name}, {"index", session_.pass_index()}};
}

void Runner::help(const CommandSpec& spec, const Arguments& args) {
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

void Runner::quit(const CommandSpec& spec, const Arguments& args) {
  expect_positionals(spec, args, 0, 0);
  finished_ = true;
  if (json_) emit({{"quit", true}});
}

}  // namespace inspect_cli

const std::vector<InspectCommandHelp>& inspect_commands() {
  static const std::vector<InspectCommandHelp> list = [] {
    std::vector<InspectCommandHelp> l;
    for (const inspect_cli::CommandSpec& spec : inspect_cli::specs()) l.push_back(spec.help);
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
  const std::vector<std::string> words = inspect_cli::words_of(command);
  if (words.empty()) return true;
  try {
    const inspect_cli::CommandSpec* spec = inspect_cli::spec_of(words[0]);
    if (!spec) throw InspectError("unknown command '" + words[0] + "' (see `help`)");
    const inspect_cli::Arguments args = inspect_cli::parse_arguments(*spec, words);
    inspect_cli::Runner(session_, out_, args.has("--json"), finished_, draw_ids_).run(*spec, args);
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