#include "reports/graph_layout.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <stdexcept>
#include <vector>

#include "reports/html.h"

extern char** environ;

namespace nightcap {
namespace {

// Runs `argv` with its standard error kept; returns the exit status (-1: not started, or killed).
int run(std::vector<std::string> args, std::string& error) {
  int pipe_ends[2];
  if (pipe(pipe_ends) != 0) return -1;
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_adddup2(&files, pipe_ends[1], STDERR_FILENO);
  posix_spawn_file_actions_addclose(&files, pipe_ends[0]);
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawnp(&pid, argv[0], &files, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&files);
  close(pipe_ends[1]);
  std::array<char, 4096> chunk;
  for (ssize_t n; (n = read(pipe_ends[0], chunk.data(), chunk.size())) > 0;)
    if (error.size() < 4096) error.append(chunk.data(), size_t(n));
  close(pipe_ends[0]);
  if (spawned != 0) {
    error = std::string("cannot run ") + argv[0] + " (is Graphviz installed?)";
    return -1;
  }
  int status = 0;
  if (waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace

void layout_graph(const std::string& dot_text, const std::filesystem::path& dot_file,
                  const std::filesystem::path& svg_file) {
  write_file(dot_file, dot_text);
  const std::filesystem::path partial = svg_file.string() + ".partial";
  std::string error;
  const int status = run({"dot", "-Tsvg", dot_file.string(), "-o", partial.string()}, error);
  if (status != 0) {
    std::filesystem::remove(partial);
    while (!error.empty() && (error.back() == '\n' || error.back() == '\r')) error.pop_back();
    throw std::runtime_error(svg_file.string() + ": Graphviz dot failed" + (error.empty() ? "" : ": " + error));
  }
  std::filesystem::rename(partial, svg_file);
}

}  // namespace nightcap
