#pragma once
// Sub-commands of the `pensight` command line. Each returns the process exit code.
#include <string>
#include <vector>

namespace pensight::app {

using Args = std::vector<std::string>;

int cmd_devices(const Args& args);
int cmd_demo(const Args& args);

}  // namespace pensight::app
