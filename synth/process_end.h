// A process ending on a signal (bench/stop_on_signal.h) stores nothing more: a case
// that failed only because the stop killed its program must not be saved as its result
// (a resumed run would reuse it).
#pragma once

namespace grapebench {

// Marks this process as ending. From then on wait_here_if_ending never returns.
void begin_process_end();

// Returns at once unless the process is ending; then the calling thread waits for the
// process's end. write_file_atomic calls it before it writes.
void wait_here_if_ending();

}  // namespace grapebench
