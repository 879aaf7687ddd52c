#include "bench/stop_on_signal.h"

#include "synth/confined_program.h"
#include "synth/process_end.h"
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
    begin_process_end();  // nothing that fails from here on is stored
    // A second signal ends the process at once (this thread no longer blocks them).
    for (int s : {SIGINT, SIGTERM, SIGHUP})
      if (sigismember(&set, s)) signal(s, SIG_DFL);
    pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
    // Programs first: Blender or an estimator could still write into its folder.
    stop_every_program();
    remove_temp_folders_before_exit();
    raise(sig);
    _exit(128 + sig);  // not reached: the default action ends the process
  }).detach();
}

}  // namespace grapebench
