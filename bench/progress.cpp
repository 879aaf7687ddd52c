#include "bench/progress.h"

#include <unistd.h>

#include <cstdio>

namespace grapebench {

Progress::Progress(std::string what, int total, Verbosity verbosity)
    : what_(std::move(what)),
      total_(total),
      verbosity_(verbosity),
      tty_(isatty(fileno(stderr)) != 0),
      t0_(std::chrono::steady_clock::now()) {}

void Progress::done(const std::string& detail, bool failed) {
  std::lock_guard<std::mutex> lock(mutex_);
  ++count_;
  if (verbosity_ == Verbosity::quiet) return;
  const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  const double eta = el / count_ * (total_ - count_);
  if (tty_ && verbosity_ == Verbosity::normal) {
    const int width = 30, fill = total_ > 0 ? width * count_ / total_ : width;
    std::fprintf(stderr, "\r  [%s%s] %d/%d %ss  %.0f s elapsed, ETA %.0f s ",
                 std::string(static_cast<std::size_t>(fill), '#').c_str(),
                 std::string(static_cast<std::size_t>(width - fill), '.').c_str(), count_, total_, what_.c_str(), el,
                 eta);
    if (count_ == total_) std::fprintf(stderr, "\n");
  } else {
    std::fprintf(stderr, "  %s %d/%d (%s)%s  %.1f s elapsed, ETA %.0f s\n", what_.c_str(), count_, total_,
                 detail.c_str(), failed ? " FAILED" : "", el, eta);
  }
  std::fflush(stderr);
}

}  // namespace grapebench
