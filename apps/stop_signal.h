#pragma once
// Ctrl-C (SIGINT) and SIGTERM as a request to finish cleanly, for the commands that run until
// told to stop (record, sim-devices): the flag they poll.
#include <atomic>

namespace pensight::app {

// Installs the handlers (once) and returns the flag they set.
const std::atomic<bool>& stop_on_signals();

}  // namespace pensight::app
