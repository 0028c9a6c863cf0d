#pragma once
// A command stream records a chain of dispatches and copies once and submits it as one batch,
// as often as needed (record once per shape, submit every frame). Barriers are inserted only
// where a buffer written earlier in the chain is read or written again, or a buffer read earlier
// is overwritten. Each dispatch can be timed on the device by name.
#include <cstdint>
#include <cstring>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "runtime/vk_buffer.h"
#include "runtime/vk_pipeline.h"

namespace pensight::vk {

enum class Access { kRead, kWrite, kReadWrite };

struct Binding {
  const Buffer* buffer;
  Access access;
};
inline Binding in(const Buffer& b) {
  return {&b, Access::kRead};
}
inline Binding out(const Buffer& b) {
  return {&b, Access::kWrite};
}
inline Binding inout(const Buffer& b) {
  return {&b, Access::kReadWrite};
}
template <class T>
Binding in(const TypedBuffer<T>& b) {
  return in(b.raw());
}
template <class T>
Binding out(const TypedBuffer<T>& b) {
  return out(b.raw());
}
template <class T>
Binding inout(const TypedBuffer<T>& b) {
  return inout(b.raw());
}

struct Groups {
  uint32_t x = 1, y = 1, z = 1;
};

struct DispatchTime {
  std::string name;
  double device_ms = 0;
};

class CommandStream {
 public:
  explicit CommandStream(const Context& ctx);
  ~CommandStream();
  CommandStream(const CommandStream&) = delete;
  CommandStream& operator=(const CommandStream&) = delete;

  // Records a dispatch. `name` labels its timing (default: the shader name).
  void dispatch(const Pipeline& pipeline, std::span<const Binding> buffers, Groups groups,
                const void* push_constants = nullptr, size_t push_bytes = 0, std::string name = {});
  void dispatch(const Pipeline& pipeline, std::initializer_list<Binding> buffers, Groups groups,
                const void* push_constants = nullptr, size_t push_bytes = 0,
                std::string name = {}) {
    dispatch(pipeline, std::span<const Binding>(buffers.begin(), buffers.size()), groups,
             push_constants, push_bytes, std::move(name));
  }
  template <class Push>
  void dispatch(const Pipeline& pipeline, std::initializer_list<Binding> buffers, Groups groups,
                const Push& push, std::string name = {}) {
    dispatch(pipeline, buffers, groups, &push, sizeof(Push), std::move(name));
  }
  // Records a buffer-to-buffer copy of `bytes` (default: all of src).
  void copy(const Buffer& src, const Buffer& dst, size_t bytes = 0, size_t src_offset = 0,
            size_t dst_offset = 0);

  // Submits everything recorded so far and waits. May be called again without re-recording.
  void submit_and_wait();
  // Forgets the recorded commands so the stream can be recorded anew.
  void reset();

  size_t num_commands() const;
  // Barriers the hazard tracking inserted between recorded commands (diagnostics, tests).
  size_t num_barriers() const;
  // Device time of each recorded command in the last submission, in recording order
  // (empty when the device has no timestamp queries).
  std::vector<DispatchTime> timings() const;

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace pensight::vk
