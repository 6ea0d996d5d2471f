// A non-owning view of a contiguous run of T: what a container lends its callers instead of a
// raw pointer and a count kept elsewhere (C++20's std::span, which this C++17 tree lacks). Sizes
// and indices are int like the counts they replace (num_features, num_observations).
#pragma once

#include <cassert>
#include <cstddef>

namespace ale {

template <class T>
class Span {
 public:
  constexpr Span() = default;
  constexpr Span(T* data, int size) : data_(data), size_(data != nullptr && size > 0 ? size : 0) {}

  constexpr T* data() const { return data_; }
  constexpr int size() const { return size_; }
  constexpr bool empty() const { return size_ == 0; }
  constexpr T* begin() const { return data_; }
  constexpr T* end() const { return data_ + size_; }
  // i in [0, size()); checked in debug builds only (this is the hot path's accessor)
  T& operator[](int i) const {
    assert(i >= 0 && i < size_);
    return data_[i];
  }
  // The first n elements (all of them when n >= size()).
  constexpr Span first(int n) const { return Span(data_, n < size_ ? n : size_); }

 private:
  T* data_ = nullptr;
  int size_ = 0;
};

}  // namespace ale
