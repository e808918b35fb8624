#pragma once
// Fixed-capacity vector: storage inline, never allocates. push_back on a full vector, an index
// past size() and pop_back on an empty one are programming errors (CARRIL_CHECK: counted, the
// robot stopped safely) that never touch memory outside the storage: the write is refused, the
// index clamped. try_push_back is for callers to whom a full vector is an input they handle (a
// path longer than its output).
#include <array>
#include <cstddef>

#include "firmware/core/Check.hpp"

namespace carril::fw {

template <typename T, std::size_t N>
class StaticVector {
 public:
  constexpr std::size_t capacity() const { return N; }
  constexpr std::size_t size() const { return size_; }
  constexpr bool empty() const { return size_ == 0; }
  constexpr bool full() const { return size_ == N; }
  constexpr void clear() { size_ = 0; }
  // Keeps the first n elements (n no more than size()).
  constexpr void truncate(std::size_t n) {
    if (CARRIL_CHECK(n <= size_) && n < size_) size_ = n;
  }

  constexpr bool push_back(const T& v) {
    if (!CARRIL_CHECK(size_ < N)) return false;  // full
    return try_push_back(v);
  }
  // Appends v; false, and nothing appended, when full.
  constexpr bool try_push_back(const T& v) {
    if (size_ >= N) return false;
    data_[size_++] = v;
    return true;
  }
  constexpr void pop_back() {
    if (CARRIL_CHECK(size_ > 0)) --size_;
  }
  constexpr T& operator[](std::size_t i) {
    if (!CARRIL_CHECK(i < size_)) return data_[clamped(i)];
    return data_[i];
  }
  constexpr const T& operator[](std::size_t i) const {
    if (!CARRIL_CHECK(i < size_)) return data_[clamped(i)];
    return data_[i];
  }
  constexpr T& back() { return (*this)[size_ - 1]; }
  constexpr const T& back() const { return (*this)[size_ - 1]; }
  constexpr T* begin() { return data_.data(); }
  constexpr T* end() { return data_.data() + size_; }
  constexpr const T* begin() const { return data_.data(); }
  constexpr const T* end() const { return data_.data() + size_; }
  // The same elements in the same order (what lies past size() does not count).
  constexpr bool operator==(const StaticVector& o) const {
    if (size_ != o.size_) return false;
    for (std::size_t i = 0; i < size_; ++i) {
      if (!(data_[i] == o.data_[i])) return false;
    }
    return true;
  }

 private:
  static_assert(N > 0);
  // A failed index's stand-in inside the storage.
  static constexpr std::size_t clamped(std::size_t i) { return i < N ? i : N - 1; }
  std::array<T, N> data_{};
  std::size_t size_ = 0;
};

}  // namespace carril::fw
