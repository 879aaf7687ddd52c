// Runs another program (an external estimator) so that it cannot outlive, outwait or
// reach past its request: a warden process (a fork of ours, the program's parent and
// subreaper) sets resource limits, runs the program -- inside bubblewrap by default --
// and, when it ends or the harness says stop, kills everything the program started,
// daemons that left its process group included.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace grapebench {

struct ProgramLimits {
  // bwrap: read-only root file system, `work_dir` the only writable folder, a private
  // /tmp, /dev and /proc (its own PID namespace: the harness is not visible), no
  // network, no capabilities. none: the same limits and cleanup without the sandbox
  // (where user namespaces are not available).
  enum class Sandbox { Bwrap, None };
  Sandbox sandbox = Sandbox::Bwrap;
  double cpu_seconds = 300;     // RLIMIT_CPU of each of its processes, s
  double memory_mb = 8192;      // RLIMIT_AS of each of its processes (address space), MB
  double file_mb = 1024;        // RLIMIT_FSIZE: largest file it may write, MB
  std::size_t output_bytes = std::size_t{16} << 20;  // stdout + stderr read before it is stopped
  // Variables set for the program (name, value), over the harness's own environment.
  std::vector<std::pair<std::string, std::string>> environment;
};

class ConfinedProgram {
 public:
  using Clock = std::chrono::steady_clock;
  // Starts `argv` (argv[0] looked up in PATH) in `work_dir`. `stdio`: a socket to be its
  // stdin and stdout, or -1 (stdin empty, stdout read and dropped like stderr, keeping
  // a tail). Throws std::runtime_error when it cannot start (bwrap or the program not
  // found).
  ConfinedProgram(const std::vector<std::string>& argv, const std::filesystem::path& work_dir,
                  const ProgramLimits& limits, int stdio = -1);
  ConfinedProgram(const ConfinedProgram&) = delete;
  ConfinedProgram& operator=(const ConfinedProgram&) = delete;
  ~ConfinedProgram();  // stops it (and what it started) if it still runs

  // Exited: it and everything it started have ended, status() holds its wait status.
  // TimedOut, TooMuchOutput: it was stopped at the deadline or past the output cap.
  // Ready: wait_fd's descriptor is ready.
  enum class End { Exited, TimedOut, TooMuchOutput, Ready };
  // Reads its output until it and everything it started have ended, or `deadline`
  // (then stops them).
  End wait(Clock::time_point deadline);
  // Waits until `fd` is ready for `events` (poll), reading its output meanwhile.
  End wait_fd(int fd, short events, Clock::time_point deadline);
  // Stops the program and everything it started; waits for the warden.
  void stop();

  int status() const { return status_; }
  // Why it failed in words: "exit status 3", "killed by signal 9 (over its CPU time
  // limit?)"; "" for exit status 0.
  std::string failure() const;
  // The last bytes of its stderr (400 at most), trimmed.
  std::string error_tail() const;

 private:
  // Reads once from stdout and stderr where poll reported events; false once the
  // output cap is passed.
  bool read_output(short out_events, short err_events);
  void reap();

  pid_t warden_ = -1;
  int pidfd_ = -1;
  int out_ = -1, err_ = -1;  // read ends of its stdout (unless a socket) and stderr
  int status_fd_ = -1;       // the warden writes the program's wait status here
  std::size_t output_read_ = 0, output_cap_ = 0;
  std::string err_tail_;
  int status_ = -1;
  bool ended_ = false;
  bool bwrap_ = false;
};

// Where `name` is found in PATH (or `name` itself when it holds a '/'); "" when not.
std::string find_program(const std::string& name);

}  // namespace grapebench
