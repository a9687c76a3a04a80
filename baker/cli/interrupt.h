#pragma once
/// SIGTERM, SIGINT and SIGHUP end clothbake cleanly: every unfinished output
/// (io/atomic_file.h) is removed, a line on stderr says so, and the process
/// exits with 128 + the signal number (143 for SIGTERM). Final names keep
/// what they held before the run, since outputs only appear by rename.

namespace clothbake::cli {

/// Blocks the signals in the calling thread (and so in every thread it starts
/// later, the task scheduler's workers included) and starts one thread that
/// waits for them. Call first thing in main, before any other thread exists.
void install_interrupt_handler();

}  // namespace clothbake::cli
