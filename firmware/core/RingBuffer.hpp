#pragma once
// Fixed-capacity FIFO; when full, push overwrites the oldest element (newest data wins, as a
// sensor history should). Never allocates.
#include <array>
#include <cstddef>

#include "firmware/core/Check.hpp"

namespace carril::fw {

template <typename T, std::size_t N>
class RingBuffer {
  static_assert(N > 0);

 public:
  constexpr std::size_t capacity() const { return N; }
  constexpr std::size_t size() const { return size_; }
  constexpr bool empty() const { return size_ == 0; }
  constexpr bool full() const { return size_ == N; }
  constexpr void clear() { head_ = size_ = 0; }

  // Appends; returns false when the oldest element was overwritten.
  constexpr bool push(const T& v) {
    data_[(head_ + size_) % N] = v;
    if (size_ < N) {
      ++size_;
      return true;
    }
    head_ = (head_ + 1) % N;
    return false;
  }
  constexpr bool pop(T& out) {
    if (size_ == 0) return false;
    out = data_[head_];
    head_ = (head_ + 1) % N;
    --size_;
    return true;
  }
  // i = 0 is the oldest element, size()-1 the newest.
  constexpr const T& operator[](std::size_t i) const {
    CARRIL_CHECK(i < size_);  // the index wraps into the storage all the same
    return data_[(head_ + i) % N];
  }
  constexpr const T& newest() const { return (*this)[size_ - 1]; }

 private:
  std::array<T, N> data_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
};

}  // namespace carril::fw
