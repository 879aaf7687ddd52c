#include "synth/process_end.h"

#include <atomic>
#include <chrono>
#include <thread>

namespace grapebench {

namespace {
std::atomic<bool> g_ending{false};
}  // namespace

void begin_process_end() { g_ending.store(true); }

void wait_here_if_ending() {
  while (g_ending.load()) std::this_thread::sleep_for(std::chrono::hours(1));
}

}  // namespace grapebench
