#pragma once
// Capacity policy of the contact buffers: they are reused every step and only ever
// grow, with headroom, so a slowly growing contact count or grid does not reallocate
// at every step (no allocation per step once warmed up, DESIGN.md §9).
#include <algorithm>
#include <cstddef>

namespace dsdem::contact {

// Makes room for n elements; when that needs a reallocation, takes 25% more (and at
// least 1.5x the old capacity), so the next small growth does not reallocate again.
template <class Vector>
void reserve_with_headroom(Vector& v, std::size_t n) {
  if (v.capacity() >= n) return;
  v.reserve(std::max(n + n / 4 + 16, v.capacity() + v.capacity() / 2));
}

}  // namespace dsdem::contact
