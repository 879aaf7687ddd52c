// How grapebench ends on SIGINT (Ctrl-C), SIGTERM or SIGHUP: like a finished run, it
// leaves no program running and no temporary folder behind.
#pragma once

namespace grapebench {

// From here on SIGINT, SIGTERM and SIGHUP are taken by one thread of their own, which
// stops storing results (begin_process_end: a case that fails because its program is
// stopped is not saved), stops every external program still running
// (stop_every_program), removes every temporary folder
// (remove_temp_folders_before_exit) and then ends the process by the same signal (a
// shell reads 128 + its number); a second signal meanwhile ends it at once. Cases
// finished before it are in the run folder already, as after a kill; a resumed run
// goes on from them. A signal ignored when the process starts (nohup's SIGHUP, SIGINT
// of a script's `cmd &`) stays ignored. Call first
// in main, before any other thread starts: threads inherit the signals blocked.
void stop_on_signal();

}  // namespace grapebench
