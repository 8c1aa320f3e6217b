// The interactive `nightcap inspect` through a pseudo-terminal, typed as a person would: a pass
// name completed with Tab, a command recalled with the up arrow.
#include <gtest/gtest.h>
#include <poll.h>
#include <pty.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <string>

#include "tests/e2e/cli.h"

namespace nightcap::test {
namespace {
namespace NIGHTCAP_FILE_ID {

class Terminal {
 public:
  explicit Terminal(const std::filesystem::path& capture) {
    child_ = forkpty(&fd_, nullptr, nullptr, nullptr);
    if (child_ == 0) {
      setenv("TERM", "xterm", 1);
      execl(NIGHTCAP_CLI, NIGHTCAP_CLI, "inspect", capture.c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
  }
  ~Terminal() {
    if (child_ > 0 && !exited_) {
      kill(child_, SIGKILL);
      waitpid(child_, nullptr, 0);
    }
    if (fd_ >= 0) close(fd_);
  }
  bool started() const { return child_ > 0; }

  void type(const std::string& keys) { ASSERT_EQ(write(fd_, keys.data(), keys.size()), ssize_t(keys.size())); }

  // Reads until `text` has appeared in what was read since the last call, or 20 s passed.
  bool read_until(const std::string& text) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (transcript_.find(text, mark_) == std::string::npos) {
      if (std::chrono::steady_clock::now() > deadline) return false;
      pollfd p{fd_, POLLIN, 0};
      if (poll(&p, 1, 200) <= 0) continue;
      char buffer[4096];
      const ssize_t n = read(fd_, buffer, sizeof buffer);
      if (n <= 0) return false;
      transcript_.append(buffer, size_t(n));
    }
    mark_ = transcript_.find(text, mark_) + text.size();
    return true;
  }

  int wait_exit() {
    int status = 0;
    waitpid(child_, &status, 0);
    exited_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  const std::string& transcript() const { return transcript_; }

 private:
  pid_t child_ = -1;
  int fd_ = -1;
  bool exited_ = false;
  std::string transcript_;
  size_t mark_ = 0;
};

TEST(InspectTerminal, CompletesPassNamesAndRecallsHistory) {
  const std::filesystem::path capture = shared_capture("city", "--city-block --size 320x180 --frames 2");
  Terminal terminal(capture);
  ASSERT_TRUE(terminal.started());
  ASSERT_TRUE(terminal.read_until("frame 0 cull.main> ")) << terminal.transcript();

  // "gbuffer.op" + Tab completes to the only pass starting so.
  terminal.type("goto gbuffer.op\t");
  ASSERT_TRUE(terminal.read_until("aque ")) << terminal.transcript();
  terminal.type("\r");
  ASSERT_TRUE(terminal.read_until(": gbuffer.opaque\r\n")) << terminal.transcript();
  ASSERT_TRUE(terminal.read_until("frame 0 gbuffer.opaque> ")) << terminal.transcript();

  // A command name completes too.
  terminal.type("nex\t\r");
  ASSERT_TRUE(terminal.read_until("frame 0 gbuffer.dynamic> ")) << terminal.transcript();

  // Up twice: back past `next` to the completed `goto`, which runs again.
  terminal.type("\x1b[A\x1b[A\r");
  ASSERT_TRUE(terminal.read_until(": gbuffer.opaque\r\n")) << terminal.transcript();
  ASSERT_TRUE(terminal.read_until("frame 0 gbuffer.opaque> ")) << terminal.transcript();

  // And a resource name: gbuffer.mot is only gbuffer.motion.
  terminal.type("pixel 0 0 gbuffer.mot\t\r");
  ASSERT_TRUE(terminal.read_until("gbuffer.motion (motion, R16G16_SFLOAT) frame 0 texel (0, 0)"))
      << terminal.transcript();

  terminal.type("pixel 0 0 no.such.resource\r");
  ASSERT_TRUE(terminal.read_until("no resource 'no.such.resource'")) << terminal.transcript();
  terminal.type("quit\r");
  EXPECT_EQ(terminal.wait_exit(), 0) << terminal.transcript();
}

}  // namespace NIGHTCAP_FILE_ID
}  // namespace
}  // namespace nightcap::test
