// What the `nightcap` commands share: exit codes, the error for a bad command line, and how a
// command is added to the command line and run once it is parsed. Each command is a file of its
// own (cli/<command>.cpp); main.cpp puts them on one command line.
#pragma once

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

namespace nightcap::cli {

constexpr int kExitDifferent = 1;
constexpr int kExitBadInput = 2;

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A subcommand, and what runs it once the command line is parsed (its exit code).
struct Command {
  CLI::App* subcommand;
  std::function<int()> run;
};

Command add_render_command(CLI::App& app);
Command add_bake_tod_command(CLI::App& app);
Command add_passes_command(CLI::App& app);
Command add_check_command(CLI::App& app);
Command add_replay_command(CLI::App& app);
Command add_diff_command(CLI::App& app);
// `golden update` and `golden list`, under `golden`.
std::vector<Command> add_golden_commands(CLI::App& app);
Command add_graph_command(CLI::App& app);
Command add_report_command(CLI::App& app);
Command add_inspect_command(CLI::App& app);

// NIGHTCAP_VALIDATION=1: the Khronos validation layer, as the tests run.
bool validation_requested();
// Milliseconds with three decimals; "-" for none.
std::string ms(const std::optional<double>& value);

}  // namespace nightcap::cli
