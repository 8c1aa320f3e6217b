// peak_rss PROGRAM [ARGS...]: runs PROGRAM with its output discarded, prints its peak resident
// memory in KiB (ru_maxrss of wait4) and exits with its exit code.
// Why a program of its own: Linux records the high-water mark of the address space a process
// leaves at exec as that process's own ru_maxrss, so a command that the benchmark (hundreds of
// MiB) starts by posix_spawn, vfork or fork reports the benchmark's peak. This small program,
// freshly exec'd, forks the measured command from its own small address space.
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: peak_rss PROGRAM [ARGS...]\n");
    return 2;
  }
  const pid_t pid = fork();
  if (pid == 0) {
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, STDOUT_FILENO);
    dup2(null, STDERR_FILENO);
    execv(argv[1], argv + 1);
    _exit(127);
  }
  int status = 0;
  rusage usage{};
  if (pid < 0 || wait4(pid, &status, 0, &usage) < 0) return 2;
  std::printf("%ld\n", usage.ru_maxrss);
  return WIFEXITED(status) ? WEXITSTATUS(status) : 2;
}
