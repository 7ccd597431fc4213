#include "contact/contact_history.hpp"

#include <algorithm>

namespace dsdem::contact {

Vec2 ContactHistory::previous(const ContactKey& key) const {
  const auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                                   [](const Entry& e, const ContactKey& k) { return e.key < k; });
  if (it != previous_.end() && it->key == key) return it->ft;
  return Vec2::Zero();
}

Vec2 ContactHistory::previous(const ContactKey& key, Cursor& cursor) const {
  const auto less = [](const Entry& e, const ContactKey& k) { return e.key < k; };
  const std::size_t n = previous_.size();
  std::size_t lo = std::min(cursor.pos, n);
  // Every entry before the cursor is below key: when the entry at the cursor is not,
  // it is key's lower bound (the common case: the same contact as last step, or a new one).
  if (lo == n) {
    cursor.pos = n;
    return Vec2::Zero();
  }
  if (!(previous_[lo].key < key)) {
    if (previous_[lo].key == key) {
      cursor.pos = lo + 1;
      return previous_[lo].ft;
    }
    cursor.pos = lo;
    return Vec2::Zero();
  }
  // Gallop: find a bound hi with previous_[hi - 1].key >= key (or hi = n).
  std::size_t step = 1, hi = lo;
  while (hi < n && previous_[hi].key < key) {
    lo = hi + 1;
    hi += step;
    step *= 2;
  }
  hi = std::min(hi + 1, n);
  const auto it = std::lower_bound(previous_.begin() + static_cast<std::ptrdiff_t>(lo),
                                   previous_.begin() + static_cast<std::ptrdiff_t>(hi), key, less);
  cursor.pos = static_cast<std::size_t>(it - previous_.begin());
  if (it != previous_.end() && it->key == key) return it->ft;
  return Vec2::Zero();
}

}  // namespace dsdem::contact
