// Progress of a long subcommand on stderr: a bar with elapsed time and ETA on a
// terminal, one line per item otherwise (logs), nothing when quiet. Thread-safe.
#pragma once

#include <chrono>
#include <mutex>
#include <string>

namespace grapebench {

// -q: errors and results only; default: progress; -v: also a line per item on a terminal.
enum class Verbosity { quiet = 0, normal = 1, verbose = 2 };

class Progress {
 public:
  // `what` names the items ("case", "bunch"); total items to come.
  Progress(std::string what, int total, Verbosity verbosity);
  // One item finished; `detail` is appended to its log line ("condition 0, bunch 3").
  void done(const std::string& detail, bool failed = false);

 private:
  std::string what_;
  int total_, count_ = 0;
  Verbosity verbosity_;
  bool tty_;
  std::mutex mutex_;
  std::chrono::steady_clock::time_point t0_;
};

}  // namespace grapebench
