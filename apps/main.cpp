// The `pensight` command line.
#include <cstdio>
#include <exception>
#include <string>

#include "apps/commands.h"

namespace {

constexpr const char* kUsage = R"(usage: pensight <command> [options]

commands:
  demo       run the built-in default job and print timing and accuracy
  devices    list Vulkan and CUDA devices and the one pensight would choose
  help       show this text

environment:
  PENSIGHT_VK_DEVICE       Vulkan device index or name substring (default: best GPU, else lavapipe)
  PENSIGHT_VK_VALIDATION   1 = enable the Khronos validation layer
  PENSIGHT_CACHE_DIR       pipeline cache directory (default ~/.cache/pensight, "-" = none)
)";

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return 2;
  }
  const std::string command = argv[1];
  const pensight::app::Args args(argv + 2, argv + argc);
  try {
    if (command == "demo") return pensight::app::cmd_demo(args);
    if (command == "devices") return pensight::app::cmd_devices(args);
    if (command == "help" || command == "--help" || command == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    std::fprintf(stderr, "pensight: unknown command '%s'\n\n%s", command.c_str(), kUsage);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pensight %s: error: %s\n", command.c_str(), e.what());
    return 1;
  }
}
