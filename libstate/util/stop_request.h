// Ctrl-C (SIGINT) and SIGTERM as a request to stop cleanly. Long stages poll stop_requested()
// at their safe points (hapstate-expand: between batches) and end like a reached --max-seconds:
// everything committed so far stays, and running the same command again resumes. The first
// signal prints what will happen; a second one ends the process at once (exit 130, with a
// message), which is still safe to resume from.
#pragma once

namespace hapstate {

// Exit code of a run stopped by a signal (the shell's 128 + SIGINT).
inline constexpr int kExitInterrupted = 130;

// Installs the handlers; `message` (a string literal) is written to stderr on the first signal.
void install_stop_request_handler(const char* message);

// Whether a stop was requested since install_stop_request_handler.
bool stop_requested();

}  // namespace hapstate
