// How an inspect command line is read: each command's usage, summary and options (the table
// `help` prints and the parser checks), and its words parsed into positionals and options.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "inspect/commands.h"
#include "inspect/decode.h"

namespace nightcap::inspect_cli {

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

// Every command, in the order `help` lists them; null for a name no command has.
const std::vector<CommandSpec>& specs();
const CommandSpec* spec_of(const std::string& name);

// A command's words split at spaces; the first is its name.
std::vector<std::string> words_of(const std::string& command);
// Throws InspectError for an option the command does not take or one short of its values.
Arguments parse_arguments(const CommandSpec& spec, const std::vector<std::string>& words);
// A whole number of at most 9 digits; InspectError names `what` otherwise.
uint32_t parse_index(const std::string& what, const std::string& text);
uint32_t option_index(const Arguments& args, const std::string& option, uint32_t fallback);
// --mip, --layer and --slice, 0 where not given.
Subimage subimage_of(const Arguments& args);
// Throws InspectError with the command's usage unless it has between min and max positionals.
void expect_positionals(const CommandSpec& spec, const Arguments& args, size_t min, size_t max);

}  // namespace nightcap::inspect_cli
