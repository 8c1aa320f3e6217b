// The commands of `nightcap inspect`: each parses its words, answers from the session, and
// prints either lines for people or one JSON object (`--json`). A command that fails prints one
// line on the error stream and leaves the session as it was, so a session goes on after it.
#pragma once

#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "inspect/pick.h"
#include "inspect/session.h"

namespace nightcap {

struct InspectCommandHelp {
  std::string name, usage, summary;
};
// Every command, in the order `help` lists them.
const std::vector<InspectCommandHelp>& inspect_commands();

// Splits a script into commands: one per line, and lines split at ';'. Blank ones are dropped,
// and so are lines starting with '#'.
std::vector<std::string> split_commands(const std::string& script);

class InspectCommands {
 public:
  InspectCommands(InspectSession& session, std::ostream& out, std::ostream& err);

  // Runs one command, e.g. "pixel 640 360 gbuffer.normal --json". False when it failed (the
  // reason is on the error stream).
  bool run(const std::string& command);
  // `quit` was given.
  bool finished() const { return finished_; }

 private:
  InspectSession& session_;
  std::ostream &out_, &err_;
  bool finished_ = false;
  std::map<uint32_t, DrawIdImage> draw_ids_;  // by frame index: what `pick` rendered
};

}  // namespace nightcap
