#pragma once
// The data bus: one Topic per message, written in place by exactly one producer component and
// read by any number of consumers through their own Reader, which remembers the last sequence
// number it took. A consumer knows whether its input is new without flags set elsewhere, and
// messages are fixed-size objects owned by the bus: publishing never allocates or copies more
// than the producer writes.
#include <cstdint>
#include <utility>

#include "hal/Types.hpp"

namespace carril::fw {

template <typename T>
class Topic {
 public:
  template <typename... Args>
  explicit Topic(Args&&... args) : data_(std::forward<Args>(args)...) {}
  Topic(const Topic&) = delete;
  Topic& operator=(const Topic&) = delete;

  // Producer: the message, to be written in place; then publish().
  T& edit() { return data_; }
  // Producer: the message written by edit() is complete; stamps it [ns] and counts it.
  void publish(hal::TimeNs stamp_ns) {
    stamp_ns_ = stamp_ns;
    ++seq_;
  }
  void publish(const T& msg, hal::TimeNs stamp_ns) {
    data_ = msg;
    publish(stamp_ns);
  }

  // The newest message (default-constructed before the first publish).
  const T& get() const { return data_; }
  // Messages published so far (0: none yet).
  std::uint32_t seq() const { return seq_; }
  // Time of the newest message [ns].
  hal::TimeNs stamp_ns() const { return stamp_ns_; }
  bool ever() const { return seq_ != 0; }

 private:
  T data_;
  std::uint32_t seq_ = 0;
  hal::TimeNs stamp_ns_ = 0;
};

// One consumer's view of a topic.
template <typename T>
class Reader {
 public:
  explicit Reader(const Topic<T>& topic) : topic_(&topic) {}

  // A message was published since this reader last took one.
  bool fresh() const { return topic_->seq() != seen_; }
  // The newest message, marking it seen.
  const T& take() {
    seen_ = topic_->seq();
    return topic_->get();
  }
  // The newest message, without marking it seen.
  const T& peek() const { return topic_->get(); }
  bool ever() const { return topic_->ever(); }
  hal::TimeNs stamp_ns() const { return topic_->stamp_ns(); }

 private:
  const Topic<T>* topic_;
  std::uint32_t seen_ = 0;
};

}  // namespace carril::fw
