#include "core/backend.h"

#include "core/enum_names.h"
#include "core/error.h"

namespace pensight {
namespace {

constexpr EnumName<Backend> kBackendNames[] = {
    {Backend::kAuto, "auto"},
    {Backend::kCpu, "cpu"},
    {Backend::kVulkan, "vulkan"},
    {Backend::kCuda, "cuda"},
};

}  // namespace

const char* to_string(Backend backend) {
  return enum_name<Backend>(kBackendNames, backend);
}

Backend parse_backend(const std::string& name) {
  if (const auto b = parse_enum_name<Backend>(kBackendNames, name)) return *b;
  throw Error("unknown backend '" + name + "'; use " + enum_choices<Backend>(kBackendNames));
}

}  // namespace pensight
