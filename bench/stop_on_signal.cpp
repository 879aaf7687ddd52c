#include "bench/stop_on_signal.h"

#include "synth/confined_program.h"
#include "synth/temp_folder.h"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <thread>

namespace grapebench {

void stop_on_signal() {
  sigset_t set;
  sigemptyset(&set);
  for (int s : {SIGINT, SIGTERM, SIGHUP}) {
    // One ignored on entry stays ignored: `nohup grapebench run ...` outlives its terminal.
    struct sigaction old {};
    if (sigaction(s, nullptr, &old) == 0 && old.sa_handler != SIG_IGN) sigaddset(&set, s);
  }
  pthread_sigmask(SIG_BLOCK, &set, nullptr);
  std::thread([set] {
    int sig = 0;
    if (sigwait(&set, &sig) != 0) return;
    // Programs first: Blender or an estimator could still write into its folder.
    stop_every_program();
    remove_temp_folders_before_exit();
    signal(sig, SIG_DFL);
    sigset_t one;
    sigemptyset(&one);
    sigaddset(&one, sig);
    pthread_sigmask(SIG_UNBLOCK, &one, nullptr);
    raise(sig);
    _exit(128 + sig);  // not reached: the default action ends the process
  }).detach();
}

}  // namespace grapebench
