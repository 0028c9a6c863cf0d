#pragma once
// A program a test starts and stops (roscore, pensight_node, rosbag play, `pensight record`): its
// own process group, so stopping it stops what it started (roscore's rosmaster and rosout), with
// stdout and stderr in a log file.
#include <sys/types.h>

#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace pensight::testing {

class ChildProcess {
 public:
  // Starts argv[0] (looked up in PATH) with the caller's environment. Throws std::runtime_error
  // when it cannot be started.
  ChildProcess(const std::vector<std::string>& argv, const std::filesystem::path& log);
  // stop() with a 5 s grace, then SIGKILL to the group.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  // The exit status once the process ended within `timeout` (a signal s as 128 + s), else
  // nullopt.
  std::optional<int> wait(std::chrono::milliseconds timeout);
  // SIGINT to the group (as Ctrl-C), then wait(timeout).
  std::optional<int> stop(std::chrono::milliseconds timeout);
  // SIGKILL to the group (a power cut, the OOM killer): nothing of the process runs after it.
  // Returns the exit status, 128 + SIGKILL unless it had ended before.
  int kill();
  bool running();
  // What the process wrote so far.
  std::string log() const;

 private:
  pid_t pid_ = -1;
  std::optional<int> status_;
  std::filesystem::path log_;
};

}  // namespace pensight::testing
