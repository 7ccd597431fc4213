#include "contact/contact_history.hpp"

#include <algorithm>

namespace dsdem::contact {

namespace {
bool entry_below(const ContactHistory::Entry& e, const ContactKey& k) { return e.key < k; }
}  // namespace

void ContactHistory::begin_step(int n_segments) {
  const std::size_t n = static_cast<std::size_t>(std::max(1, n_segments));
  if (current_.size() < n) current_.resize(n);
  if (previous_.size() < n) previous_.resize(n);
  for (std::size_t t = 0; t < n; ++t) current_[t].clear();
  n_current_ = static_cast<int>(n);
}

void ContactHistory::end_step() {
  previous_.swap(current_);
  n_previous_ = n_current_;
  n_current_ = 0;
}

void ContactHistory::reserve_headroom(std::size_t n) {
  for (int t = 0; t < n_current_; ++t) {
    reserve_with_headroom(current_[static_cast<std::size_t>(t)], n);
    reserve_with_headroom(previous_[static_cast<std::size_t>(t)], n);
  }
}

void ContactHistory::clear() {
  for (auto& s : previous_) s.clear();
  for (auto& s : current_) s.clear();
  n_previous_ = n_current_ = 0;
}

std::vector<ContactHistory::Entry> ContactHistory::entries() const {
  std::vector<Entry> all;
  all.reserve(size());
  for (int t = 0; t < n_previous_; ++t) {
    const auto& s = previous_[static_cast<std::size_t>(t)];
    all.insert(all.end(), s.begin(), s.end());
  }
  return all;
}

std::size_t ContactHistory::size() const {
  std::size_t n = 0;
  for (int t = 0; t < n_previous_; ++t) n += previous_[static_cast<std::size_t>(t)].size();
  return n;
}

Vec2 ContactHistory::previous(const ContactKey& key) const {
  for (int t = 0; t < n_previous_; ++t) {
    const auto& s = previous_[static_cast<std::size_t>(t)];
    if (s.empty() || s.back().key < key) continue;  // all below key: the next segment
    const auto it = std::lower_bound(s.begin(), s.end(), key, entry_below);
    return it->key == key ? it->ft : Vec2(Vec2::Zero());
  }
  return Vec2::Zero();
}

Vec2 ContactHistory::previous(const ContactKey& key, Cursor& cursor) const {
  // The segment that may hold key: the first whose last key is not below it.
  while (cursor.segment < static_cast<std::size_t>(n_previous_)) {
    const auto& s = previous_[cursor.segment];
    if (cursor.pos < s.size() && !(s.back().key < key)) break;
    ++cursor.segment;
    cursor.pos = 0;
  }
  if (cursor.segment >= static_cast<std::size_t>(n_previous_)) return Vec2::Zero();
  const std::vector<Entry>& seg = previous_[cursor.segment];
  const std::size_t n = seg.size();
  std::size_t lo = cursor.pos;
  // Every entry before the cursor is below key: when the entry at the cursor is not,
  // it is key's lower bound (the common case: the same contact as last step, or a new one).
  if (!(seg[lo].key < key)) {
    if (seg[lo].key == key) {
      cursor.pos = lo + 1;
      return seg[lo].ft;
    }
    cursor.pos = lo;
    return Vec2::Zero();
  }
  // Gallop: find a bound hi with seg[hi - 1].key >= key (it exists: seg.back() >= key).
  std::size_t step = 1, hi = lo;
  while (hi < n && seg[hi].key < key) {
    lo = hi + 1;
    hi += step;
    step *= 2;
  }
  hi = std::min(hi + 1, n);
  const auto it = std::lower_bound(seg.begin() + static_cast<std::ptrdiff_t>(lo),
                                   seg.begin() + static_cast<std::ptrdiff_t>(hi), key, entry_below);
  cursor.pos = static_cast<std::size_t>(it - seg.begin());
  if (it != seg.end() && it->key == key) return it->ft;
  return Vec2::Zero();
}

}  // namespace dsdem::contact
