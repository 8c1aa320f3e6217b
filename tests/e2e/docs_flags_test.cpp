// Each command's flags are stated twice, by its `--help` (CLI11, cli/main.cpp) and by its page in
// docs/commands/: these tests hold the two to the same set, both ways, for every command the
// top-level `--help` lists (subcommands of a command, `golden update`, included).
#include <gtest/gtest.h>

#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

namespace fs = std::filesystem;

using Flags = std::set<std::string>;

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The indented lines of one section of CLI11's help ("Options:", "Subcommands:"), up to the
// blank line that ends it. A footer (inspect's command list) is another section.
std::vector<std::string> help_section(const std::string& help, const std::string& title) {
  std::vector<std::string> section;
  bool inside = false;
  for (const std::string& line : lines_of(help)) {
    if (line == title) {
      inside = true;
    } else if (inside) {
      if (line.empty()) break;
      section.push_back(line);
    }
  }
  return section;
}

// Every spelling of every option, "-o,--output TEXT REQUIRED" giving -o and --output.
Flags help_flags(const std::string& help) {
  Flags flags;
  // Two spaces in: deeper lines continue a description.
  static const std::regex option_line(R"(^  (-[^\s]+))");
  for (const std::string& line : help_section(help, "Options:")) {
    std::smatch match;
    if (!std::regex_search(line, match, option_line)) continue;
    std::istringstream names(match[1].str());
    for (std::string name; std::getline(names, name, ',');) flags.insert(name);
  }
  return flags;
}

std::vector<std::string> help_subcommands(const std::string& help) {
  std::vector<std::string> names;
  static const std::regex subcommand_line(R"(^  ([a-z][a-z-]*)( |$))");
  for (const std::string& line : help_section(help, "Subcommands:")) {
    std::smatch match;
    if (std::regex_search(line, match, subcommand_line)) names.push_back(match[1].str());
  }
  return names;
}

// The commands whose flags a page must list: each subcommand of the top level and, where one
// has subcommands of its own (golden), those instead.
std::vector<std::string> documented_commands() {
  std::vector<std::string> commands;
  const CliResult top = run_cli("--help");
  EXPECT_EQ(top.code, 0) << top.err;
  for (const std::string& name : help_subcommands(top.out)) {
    const CliResult help = run_cli(name + " --help");
    EXPECT_EQ(help.code, 0) << name << ": " << help.err;
    const std::vector<std::string> nested = help_subcommands(help.out);
    if (nested.empty()) commands.push_back(name);
    for (const std::string& sub : nested) commands.push_back(name + " " + sub);
  }
  return commands;
}

fs::path page_of(const std::string& command) {
  return fs::path(NIGHTCAP_SOURCE) / "docs" / "commands" / (command.substr(0, command.find(' ')) + ".md");
}

// The heading of the flags table: "## Flags", or "## Flags of `golden update`" where one page
// holds several commands.
std::string flags_heading(const std::string& command) {
  return command.find(' ') == std::string::npos ? "## Flags" : "## Flags of `" + command + "`";
}

// The flags named in the first cell of each row of the page's flags table ("`-o`, `--output
// CAP`" gives -o and --output; "`CAP` (positional)" none).
Flags page_flags(const std::string& page, const std::string& heading, bool& found) {
  Flags flags;
  found = false;
  bool inside = false;
  static const std::regex flag(R"((^|[\s`(,])(--?[A-Za-z][A-Za-z0-9-]*))");
  for (const std::string& line : lines_of(page)) {
    if (line.rfind("## ", 0) == 0) {
      inside = line == heading;
      found = found || inside;
      continue;
    }
    if (!inside || line.rfind("|", 0) != 0 || line.rfind("| ---", 0) == 0) continue;
    const std::string first_cell = line.substr(1, line.find(" | ") - 1);
    for (auto it = std::sregex_iterator(first_cell.begin(), first_cell.end(), flag); it != std::sregex_iterator(); ++it)
      flags.insert((*it)[2].str());
  }
  return flags;
}

std::string joined(const Flags& flags) {
  std::string text;
  for (const std::string& f : flags) text += (text.empty() ? "" : " ") + f;
  return text.empty() ? "(none)" : text;
}

TEST(DocsFlags, EveryCommandsPageListsExactlyTheFlagsOfItsHelp) {
  const std::vector<std::string> commands = documented_commands();
  // The commands of cli/main.cpp today; more may come, fewer would mean the parsing broke.
  ASSERT_GE(commands.size(), 10u);
  for (const std::string& command : commands) {
    SCOPED_TRACE(command);
    const CliResult help = run_cli(command + " --help");
    ASSERT_EQ(help.code, 0) << help.err;
    Flags from_help = help_flags(help.out);
    // Every command has -h, --help and --help-all (docs/commands/README.md says so once); their
    // absence here would mean the help's options were not parsed at all.
    ASSERT_TRUE(from_help.erase("--help") && from_help.erase("-h") && from_help.erase("--help-all")) << help.out;

    const fs::path page = page_of(command);
    ASSERT_TRUE(fs::exists(page)) << page;
    bool found = false;
    const Flags from_page = page_flags(slurp(page), flags_heading(command), found);
    ASSERT_TRUE(found) << page << " has no '" << flags_heading(command) << "' section";

    Flags missing_from_page, missing_from_help;
    for (const std::string& f : from_help)
      if (!from_page.count(f)) missing_from_page.insert(f);
    for (const std::string& f : from_page)
      if (!from_help.count(f)) missing_from_help.insert(f);
    EXPECT_TRUE(missing_from_page.empty()) << "in --help, not on " << page << ": " << joined(missing_from_page);
    EXPECT_TRUE(missing_from_help.empty()) << "on " << page << ", not in --help: " << joined(missing_from_help);
  }
}

TEST(DocsFlags, TheCommandsIndexLinksEveryCommandsPage) {
  const std::string index = slurp(fs::path(NIGHTCAP_SOURCE) / "docs" / "commands" / "README.md");
  ASSERT_FALSE(index.empty());
  const CliResult top = run_cli("--help");
  ASSERT_EQ(top.code, 0) << top.err;
  const std::vector<std::string> commands = help_subcommands(top.out);
  ASSERT_FALSE(commands.empty()) << top.out;
  for (const std::string& name : commands)
    EXPECT_NE(index.find("](" + name + ".md)"), std::string::npos) << "docs/commands/README.md: no link to " << name;
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
