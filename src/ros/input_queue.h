// The queue between the threads that receive rrr_node's inputs and the one
// worker that judges them.
#ifndef RRR_ROS_INPUT_QUEUE_H_
#define RRR_ROS_INPUT_QUEUE_H_

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <mutex>
#include <utility>

namespace rrr_ros {

// Inputs with their arrival times, taken by one worker in batches (so that
// it catches up when inputs come faster than it judges). Holds at most
// `capacity` inputs that may be refused; an input that may not be refused
// (a service request) always gets in. Every method is thread-safe.
template <class Input>
class InputQueue {
 public:
  using Clock = std::chrono::steady_clock;
  struct Arrival {
    Input input;
    Clock::time_point time;
  };

  explicit InputQueue(size_t capacity) : capacity_(capacity) {}

  // Appends `input` and returns true; returns false and counts a refusal
  // instead when `refusable` and `capacity` inputs wait already.
  bool Push(Input input, bool refusable) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (refusable && waiting_.size() >= capacity_) {
        ++refused_;
        return false;
      }
      waiting_.push_back({std::move(input), Clock::now()});
      longest_ = std::max(longest_, waiting_.size());
    }
    ready_.notify_one();
    return true;
  }

  // Waits until inputs wait or Stop() was called, then returns every
  // waiting input in arrival order; returns an empty batch only once
  // stopped with nothing left.
  std::deque<Arrival> TakeAll() {
    std::unique_lock<std::mutex> lock(mutex_);
    ready_.wait(lock, [this] { return stopping_ || !waiting_.empty(); });
    std::deque<Arrival> batch;
    batch.swap(waiting_);
    return batch;
  }

  // Wakes the worker; TakeAll() no longer waits.
  void Stop() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stopping_ = true;
    }
    ready_.notify_all();
  }

  size_t size() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return waiting_.size();
  }
  // The most inputs that ever waited at once.
  size_t longest() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return longest_;
  }
  uint64_t refused() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return refused_;
  }

 private:
  const size_t capacity_;
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::deque<Arrival> waiting_;
  bool stopping_ = false;
  size_t longest_ = 0;
  uint64_t refused_ = 0;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_INPUT_QUEUE_H_
