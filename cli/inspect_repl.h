// The interactive `nightcap inspect` session: line editing, history and tab completion through
// libedit, so the debugger's own code (inspect/) needs no terminal library.
#pragma once

#include "inspect/commands.h"

namespace nightcap {

// Reads commands from the terminal until `quit` or end of input. Completes command names as
// the first word and pass and resource names after it; up and down recall earlier commands.
void run_interactive_inspect(InspectSession& session, InspectCommands& commands);

}  // namespace nightcap
