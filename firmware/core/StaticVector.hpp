#pragma once
// Fixed-capacity vector: storage inline, never allocates. push_back on a full vector is a
// programming error (assert) and is refused (returns false) in release builds; try_push_back is
// for callers to whom a full vector is an input they handle (a path longer than its output).
#include <array>
#include <cassert>
#include <cstddef>

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
    assert(n <= size_);
    if (n < size_) size_ = n;
  }

  constexpr bool push_back(const T& v) {
    assert(size_ < N && "StaticVector full");
    return try_push_back(v);
  }
  // Appends v; false, and nothing appended, when full.
  constexpr bool try_push_back(const T& v) {
    if (size_ >= N) return false;
    data_[size_++] = v;
    return true;
  }
  constexpr void pop_back() {
    assert(size_ > 0);
    if (size_ > 0) --size_;
  }
  constexpr T& operator[](std::size_t i) {
    assert(i < size_);
    return data_[i];
  }
  constexpr const T& operator[](std::size_t i) const {
    assert(i < size_);
    return data_[i];
  }
  constexpr T& back() { return (*this)[size_ - 1]; }
  constexpr const T& back() const { return (*this)[size_ - 1]; }
  constexpr T* begin() { return data_.data(); }
  constexpr T* end() { return data_.data() + size_; }
  constexpr const T* begin() const { return data_.data(); }
  constexpr const T* end() const { return data_.data() + size_; }

 private:
  std::array<T, N> data_{};
  std::size_t size_ = 0;
};

}  // namespace carril::fw
