#include "cli/inspect_repl.h"

#include <histedit.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>

namespace nightcap {

namespace {

struct ReplState {
  InspectSession& session;
  std::string prompt;
};

ReplState& state_of(EditLine* editor) {
  void* data = nullptr;
  el_get(editor, EL_CLIENTDATA, &data);
  return *static_cast<ReplState*>(data);
}

const char* prompt(EditLine* editor) { return state_of(editor).prompt.c_str(); }

std::vector<std::string> candidates(const InspectSession& session, bool first_word) {
  std::vector<std::string> names;
  if (first_word) {
    for (const InspectCommandHelp& c : inspect_commands()) names.push_back(c.name);
  } else {
    names = session.pass_names();
    for (const std::string& r : session.resource_names()) names.push_back(r);
  }
  return names;
}

// Tab: completes the word before the cursor to the longest prefix its matches share, and lists
// the matches when that adds nothing.
unsigned char complete(EditLine* editor, int) {
  const LineInfo* line = el_line(editor);
  const std::string before(line->buffer, line->cursor);
  const size_t start = before.find_last_of(" \t") == std::string::npos ? 0 : before.find_last_of(" \t") + 1;
  const std::string word = before.substr(start);
  const bool first_word = before.find_first_not_of(" \t") >= start;
  std::vector<std::string> matches;
  for (const std::string& name : candidates(state_of(editor).session, first_word))
    if (name.rfind(word, 0) == 0 && std::find(matches.begin(), matches.end(), name) == matches.end())
      matches.push_back(name);
  if (matches.empty()) return CC_ERROR;
  std::string common = matches[0];
  for (const std::string& m : matches) {
    size_t n = 0;
    while (n < common.size() && n < m.size() && common[n] == m[n]) ++n;
    common.resize(n);
  }
  if (matches.size() == 1) common += " ";
  if (common.size() > word.size()) {
    el_insertstr(editor, common.substr(word.size()).c_str());
    return CC_REFRESH;
  }
  std::cout << "\n";
  for (const std::string& m : matches) std::cout << m << "\n";
  std::cout.flush();
  return CC_REDISPLAY;
}

}  // namespace

void run_interactive_inspect(InspectSession& session, InspectCommands& commands) {
  ReplState state{session, ""};
  EditLine* editor = el_init("nightcap", stdin, stdout, stderr);
  History* history = history_init();
  HistEvent event;
  ::history(history, &event, H_SETSIZE, 1000);
  ::history(history, &event, H_SETUNIQUE, 1);
  el_set(editor, EL_CLIENTDATA, &state);
  el_set(editor, EL_EDITOR, "emacs");
  el_set(editor, EL_HIST, ::history, history);
  el_set(editor, EL_PROMPT, &prompt);
  el_set(editor, EL_ADDFN, "nightcap-complete", "complete a command, pass or resource name", &complete);
  el_set(editor, EL_BIND, "^I", "nightcap-complete", nullptr);
  while (!commands.finished()) {
    state.prompt = "frame " + std::to_string(session.frame().index) + " " + session.pass().name + "> ";
    int count = 0;
    const char* line = el_gets(editor, &count);
    if (!line || count <= 0) break;
    std::string command(line);
    while (!command.empty() && (command.back() == '\n' || command.back() == '\r')) command.pop_back();
    if (command.find_first_not_of(" \t") == std::string::npos) continue;
    ::history(history, &event, H_ENTER, command.c_str());
    for (const std::string& part : split_commands(command)) {
      commands.run(part);
      if (commands.finished()) break;
    }
  }
  history_end(history);
  el_end(editor);
}

}  // namespace nightcap
