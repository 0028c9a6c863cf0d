#pragma once
// Device buffers. Storage buffers live in device-local memory; where the device also lets the
// host map that memory (lavapipe, Jetson, resizable BAR) uploads and downloads are plain copies,
// otherwise they go through a staging buffer and a one-off transfer.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "runtime/vk_context.h"

namespace pensight::vk {

struct ImplAccess;

enum class MemoryUsage {
  kDevice,    // device-local; host-mappable where the device allows
  kReadback,  // host-visible and cached, for results the host reads every frame
};

class Buffer {
 public:
  Buffer(const Context& ctx, size_t size_bytes, MemoryUsage usage = MemoryUsage::kDevice);
  ~Buffer();
  Buffer(Buffer&&) noexcept;
  Buffer& operator=(Buffer&&) noexcept;

  size_t size_bytes() const;
  bool host_mapped() const;
  // Copies bytes in or out; blocks until done. Range-checked: throws on out-of-bounds access.
  void upload(const void* src, size_t bytes, size_t offset = 0);
  void download(void* dst, size_t bytes, size_t offset = 0) const;

  struct Impl;

 private:
  friend struct ImplAccess;  // vk_detail.h: runtime/ sources only
  std::unique_ptr<Impl> impl_;
};

// A buffer of `count` elements of T.
template <class T>
class TypedBuffer {
 public:
  TypedBuffer(const Context& ctx, size_t count, MemoryUsage usage = MemoryUsage::kDevice)
      : buffer_(ctx, (count ? count : 1) * sizeof(T), usage), count_(count) {}

  size_t size() const { return count_; }
  Buffer& raw() { return buffer_; }
  const Buffer& raw() const { return buffer_; }

  void upload(std::span<const T> src, size_t first = 0) {
    buffer_.upload(src.data(), src.size_bytes(), first * sizeof(T));
  }
  void download(std::span<T> dst, size_t first = 0) const {
    buffer_.download(dst.data(), dst.size_bytes(), first * sizeof(T));
  }
  std::vector<T> to_vector() const {
    std::vector<T> out(count_);
    download(out);
    return out;
  }
  void fill(const T& value) { upload(std::vector<T>(count_, value)); }

 private:
  Buffer buffer_;
  size_t count_ = 0;
};

}  // namespace pensight::vk
