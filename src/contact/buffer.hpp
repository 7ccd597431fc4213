#pragma once
// Capacity policy of the contact buffers: they are reused every step and only ever
// grow, with headroom, so a slowly growing contact count or grid does not reallocate
// at every step (no allocation per step once warmed up, docs/developer-guide.md §3).
#include <algorithm>
#include <cstddef>
#include <vector>

namespace dsdem::contact {

// Makes room for n elements; when that needs a reallocation, takes 25% more (and at
// least 1.5x the old capacity), so the next small growth does not reallocate again.
template <class Vector>
void reserve_with_headroom(Vector& v, std::size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(std::max(n + n / 4 + 16, v.capacity() + v.capacity() / 2));
}

// A vector that one thread fills while the others fill theirs, on cache lines of its own.
// push_back writes the vector's end pointer each time: vectors of adjacent threads on one
// 64-byte line would make two threads' pushes keep taking it from each other (false
// sharing).
template <class T>
struct alignas(64) ThreadVector : std::vector<T> {};

}  // namespace dsdem::contact
