#pragma once
// Sub-commands of the `pensight` command line register themselves with PENSIGHT_COMMAND in their
// own cmd_*.cpp, so adding a command touches no shared file.
#include <string>
#include <vector>

namespace pensight::app {

using Args = std::vector<std::string>;
using CommandFn = int (*)(const Args& args);  // returns the process exit code

struct Command {
  const char* name;
  const char* summary;
  CommandFn run;
};

// All registered commands, sorted by name.
std::vector<Command> commands();

struct CommandRegistrar {
  CommandRegistrar(const char* name, const char* summary, CommandFn run);
};

}  // namespace pensight::app

// Use inside namespace pensight::app with an unqualified function name.
#define PENSIGHT_COMMAND(name, summary, fn) \
  static const ::pensight::app::CommandRegistrar command_registrar_##fn(name, summary, fn)
