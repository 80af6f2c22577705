// The worker of rrr_node: callbacks queue their messages, one thread takes
// them in batches and judges them, and services run on that thread between
// messages.
#ifndef RRR_ROS_NODE_WORKER_H_
#define RRR_ROS_NODE_WORKER_H_

#include <ros/console.h>

#include <functional>
#include <future>
#include <utility>
#include <variant>

#include "input_queue.h"
#include "rrr_slam/GetStatus.h"

namespace rrr_ros {

// Messages of the types `Messages` (shared pointers to ROS messages with a
// header) and requests, queued by any thread and taken by the one that
// calls Run(). A request (a service) sees every message received before it.
template <class... Messages>
class NodeWorker {
 public:
  using Request = std::function<void()>;
  using Input = std::variant<Messages..., Request>;
  using Clock = typename InputQueue<Input>::Clock;

  // At most `max_queue_length` messages wait; more are refused.
  explicit NodeWorker(size_t max_queue_length) : queue_(max_queue_length) {}

  // Queues `message`; when max_queue_length messages wait already, refuses
  // it, counts it and warns (throttled), naming it as `kind` message `seq`.
  template <class Message>
  void Enqueue(Message message, const char* kind, uint32_t seq) {
    if (!queue_.Push(Input(std::move(message)), true)) {
      ROS_WARN_THROTTLE(5.0,
                        "rrr_node: refused %s message %u: %zu inputs are "
                        "queued already (max_queue_length; %lu refused so "
                        "far)",
                        kind, seq, queue_.size(),
                        static_cast<unsigned long>(queue_.refused()));
    }
  }
  // Queues `request` to run on the worker (never refused).
  void Enqueue(Request request) {
    queue_.Push(Input(std::move(request)), false);
  }
  // Queues `request` and waits until the worker has run it.
  void RunOnWorker(const Request& request) {
    std::promise<void> done;
    Enqueue(Request([&] {
      request();
      done.set_value();
    }));
    done.get_future().wait();
  }

  // Until Stop(): takes the queue in batches, calls `process(message,
  // arrival)` for each message in order, and `update()` after the messages
  // of a batch and before each request that follows messages.
  template <class Process, class Update>
  void Run(const Process& process, const Update& update) {
    while (true) {
      auto batch = queue_.TakeAll();
      if (batch.empty()) return;  // stopped
      bool pending_update = false;
      for (auto& [input, arrival] : batch) {
        if (auto* request = std::get_if<Request>(&input)) {
          if (pending_update) update();
          pending_update = false;
          (*request)();
          continue;
        }
        std::visit(
            [&, time = arrival](const auto& message) {
              if constexpr (!std::is_same_v<std::decay_t<decltype(message)>,
                                            Request>) {
                process(message, time);
              }
            },
            input);
        pending_update = true;
      }
      if (pending_update) update();
    }
  }
  // Makes Run() return once the inputs taken so far are processed.
  void Stop() { queue_.Stop(); }

  // The queue's counts in `status`.
  void SetQueueStatus(rrr_slam::GetStatus::Response* status) const {
    status->queue_length = static_cast<uint32_t>(queue_.size());
    status->max_queue_length = static_cast<uint32_t>(queue_.longest());
    status->inputs_dropped = 0;
    status->inputs_refused = queue_.refused();
  }

 private:
  InputQueue<Input> queue_;
};

}  // namespace rrr_ros

#endif  // RRR_ROS_NODE_WORKER_H_
