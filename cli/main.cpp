// nightcap: render a scene to a capture, list its passes, check every blob of it, replay them, diff two captures (or a
// capture and a golden of a store), keep goldens, draw a frame's graph, step through a capture
// pass by pass.
// Exit codes: 0 success, 1 differences beyond tolerance, 2 bad input or failure.
#include <malloc.h>

#include <iostream>

#include "cli/command.h"
#include "passes/core/device.h"

namespace nc = nightcap;

int main(int argc, char** argv) {
  // The commands load image blobs of several MB one after another. By default glibc maps each
  // such buffer on its own and unmaps it when freed, so every load faults its pages in anew (a
  // quarter of a diff's time); kept in the heap, freed buffers are reused.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  CLI::App app{
      "nightcap: render-capture analysis and replay.\n"
      "Exit codes: 0 success, 1 differences beyond tolerance, 2 bad input or failure."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every command");

  std::vector<nc::cli::Command> commands = {nc::cli::add_render_command(app), nc::cli::add_bake_tod_command(app),
                                            nc::cli::add_passes_command(app), nc::cli::add_check_command(app),
                                            nc::cli::add_replay_command(app), nc::cli::add_diff_command(app)};
  for (nc::cli::Command& golden : nc::cli::add_golden_commands(app)) commands.push_back(golden);
  commands.push_back(nc::cli::add_graph_command(app));
  commands.push_back(nc::cli::add_report_command(app));
  commands.push_back(nc::cli::add_inspect_command(app));

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return nc::cli::kExitBadInput;
  }
  int code = nc::cli::kExitBadInput;
  try {
    for (const nc::cli::Command& command : commands)
      if (command.subcommand->parsed()) code = command.run();
  } catch (const std::exception& e) {
    std::cerr << "nightcap: " << e.what() << "\n";
  }
  // Checked here, once every device is destroyed: destruction reports leaked objects too.
  // Validation errors fail the command: tests run with the layer and must see none.
  if (const uint32_t errors = nc::validation_errors_reported(); errors > 0) {
    std::cerr << "nightcap: " << errors << " Vulkan validation error(s) reported\n";
    return nc::cli::kExitBadInput;
  }
  return code;
}