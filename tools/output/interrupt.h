// Ctrl-C handling for long runs: the first SIGINT only sets a flag, which the run checks between frames so it
// stops cleanly with every finished frame on disk; a second SIGINT ends the process at once.
#pragma once

namespace jetshell {

/// Installs the SIGINT handler (idempotent) and clears the flag.
void installInterruptHandler();
/// True once SIGINT arrived after installInterruptHandler().
bool interruptRequested();
/// Sets the flag as SIGINT would (tests, and callers that stop a run for their own reasons).
void requestInterrupt();
/// Restores the default SIGINT behaviour and clears the flag.
void removeInterruptHandler();

}  // namespace jetshell
