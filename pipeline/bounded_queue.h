#pragma once
// A bounded multi-producer queue between pipeline stages. When full, push() either waits for room
// (kBlock: nothing is lost, the producer slows down) or drops the oldest item and counts it
// (kDropOldest: a stage that may fall behind sees the newest data and memory stays bounded).
// close() lets consumers drain what is queued and then see the end.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace pensight {

enum class QueuePolicy { kBlock, kDropOldest };

template <class T>
class BoundedQueue {
 public:
  BoundedQueue(size_t capacity, QueuePolicy policy)
      : capacity_(capacity > 0 ? capacity : 1), policy_(policy) {}

  // False when the queue is closed (the item is not queued).
  bool push(T item) {
    std::unique_lock lock(mutex_);
    if (policy_ == QueuePolicy::kBlock) {
      not_full_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
    } else if (items_.size() >= capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    if (closed_) return false;
    items_.push_back(std::move(item));
    lock.unlock();
    not_empty_.notify_one();
    return true;
  }

  // Waits for an item; nullopt once the queue is closed and empty.
  std::optional<T> pop() {
    std::unique_lock lock(mutex_);
    not_empty_.wait(lock, [&] { return closed_ || !items_.empty(); });
    return take(lock);
  }

  // Waits for an item until `deadline`; nullopt then, or once the queue is closed and empty.
  template <class TimePoint>
  std::optional<T> pop_until(TimePoint deadline) {
    std::unique_lock lock(mutex_);
    not_empty_.wait_until(lock, deadline, [&] { return closed_ || !items_.empty(); });
    return take(lock);
  }

  // An item if one is queued now.
  std::optional<T> try_pop() {
    std::unique_lock lock(mutex_);
    return take(lock);
  }

  void close() {
    {
      std::lock_guard lock(mutex_);
      closed_ = true;
    }
    not_empty_.notify_all();
    not_full_.notify_all();
  }

  size_t dropped() const {
    std::lock_guard lock(mutex_);
    return dropped_;
  }

 private:
  std::optional<T> take(std::unique_lock<std::mutex>& lock) {
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    lock.unlock();
    not_full_.notify_one();
    return item;
  }

  const size_t capacity_;
  const QueuePolicy policy_;
  mutable std::mutex mutex_;
  std::condition_variable not_empty_, not_full_;
  std::deque<T> items_;
  bool closed_ = false;
  size_t dropped_ = 0;
};

}  // namespace pensight
