// The `pensight` command line.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>

#include "apps/command.h"

namespace pensight::app {
namespace {

std::vector<Command>& registry() {
  static std::vector<Command> r;
  return r;
}

void usage(FILE* out) {
  std::fprintf(out,
               "usage: pensight <command> [options]   (pensight <command> --help for more)\n\n");
  std::fprintf(out, "commands:\n");
  for (const Command& c : commands()) std::fprintf(out, "  %-14s %s\n", c.name, c.summary);
  std::fprintf(out, R"(
environment:
  PENSIGHT_VK_DEVICE       Vulkan device index or name substring (default: best GPU, else lavapipe)
  PENSIGHT_VK_VALIDATION   1 = enable the Khronos validation layer
  PENSIGHT_CACHE_DIR       pipeline cache directory (default ~/.cache/pensight, "-" = none)
)");
}

}  // namespace

CommandRegistrar::CommandRegistrar(const char* name, const char* summary, CommandFn run) {
  registry().push_back({name, summary, run});
}

std::vector<Command> commands() {
  std::vector<Command> sorted = registry();
  std::sort(sorted.begin(), sorted.end(),
            [](const Command& a, const Command& b) { return std::string(a.name) < b.name; });
  return sorted;
}

}  // namespace pensight::app

int main(int argc, char** argv) {
  using namespace pensight::app;
  const std::string name = argc > 1 ? argv[1] : "";
  if (name.empty() || name == "help" || name == "--help" || name == "-h") {
    usage(name.empty() ? stderr : stdout);
    return name.empty() ? 2 : 0;
  }
  const auto all = commands();
  const auto it =
      std::find_if(all.begin(), all.end(), [&](const Command& c) { return name == c.name; });
  if (it == all.end()) {
    std::fprintf(stderr, "pensight: unknown command '%s'\n\n", name.c_str());
    usage(stderr);
    return 2;
  }
  try {
    return it->run(Args(argv + 2, argv + argc));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pensight %s: error: %s\n", name.c_str(), e.what());
    return 1;
  }
}
