// Runs another program (an external estimator) so that it cannot outlive, outwait or
// reach past its request: a warden process (a fork of ours, the program's parent and
// subreaper) sets resource limits, runs the program -- inside bubblewrap by default --
// and, when it ends, the harness says stop or the harness is gone (killed), kills
// everything the program started, daemons that left its process group included.
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
  // bwrap: the program sees only the system's folders (/usr, /etc and the /bin, /lib
  // links), read-only; the files its command names by a path (holding a '/') and
  // `readable`, read-only;
  // `work_dir`, the only writable folder (also its HOME and TMPDIR); an empty /tmp; its
  // own /dev and /proc (its own PID namespace: the harness is not visible); no network,
  // no capabilities. Nothing else: not the user's home, not other programs' folders,
  // not the run's output (hide_from_programs). none: the same limits and cleanup
  // without the sandbox (where user namespaces are not available): it sees everything.
  enum class Sandbox { Bwrap, None };
  Sandbox sandbox = Sandbox::Bwrap;
  // bwrap only: more files or folders it may read (absolute, or relative to the
  // harness's working folder), e.g. the folder of a script's modules; refused where
  // one lies inside a hidden folder.
  std::vector<std::filesystem::path> readable;
  // The same for the harness's own files it needs (a request inbox, a preloaded
  // library, Blender's own folder): never refused.
  std::vector<std::filesystem::path> harness_readable;
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

// Stops every program this process still runs (for a harness about to end on a
// signal): each warden is told to stop and given 3 s in all, then killed with its
// group. Thread-safe; a program started meanwhile is stopped by its warden once the
// harness has ended (a warden checks for its parent every 200 ms).
void stop_every_program();

// Folders no sandboxed program may see, whatever its `readable` says (the run's
// --out: case files and truth): each is covered by an empty folder in its view.
// Process-wide; thread-safe.
void hide_from_programs(const std::filesystem::path& folder);

}  // namespace grapebench
