// Buffers reused from call to call that only ever grow (the per-frame path's scratch).
// std::vector::resize and assign past the capacity allocate exactly the new size, so a problem a
// little larger than the last one reallocates every time; these reserve at least twice the old
// capacity instead, so a run allocates a few times per buffer while its problems grow to their
// largest size, and never after (capacity that is reserved but not written stays virtual memory).
#pragma once

#include <algorithm>
#include <cstddef>

namespace ale {

// Makes room for n elements, at least doubling the capacity when it has to grow.
template <class V>
void grow_capacity(V& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n, 2 * v.capacity()));
}

template <class V>
void grow_resize(V& v, std::size_t n) {
  grow_capacity(v, n);
  v.resize(n);
}

template <class V, class T>
void grow_assign(V& v, std::size_t n, const T& value) {
  grow_capacity(v, n);
  v.assign(n, value);
}

// to = from, element by element, growing `to` as above.
template <class V>
void grow_copy(V& to, const V& from) {
  grow_capacity(to, from.size());
  to.assign(from.begin(), from.end());
}

}  // namespace ale
