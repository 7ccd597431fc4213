#pragma once
// Tangential-force history of the contacts (DESIGN.md §4: stored per element pair +
// feature, carried between steps). Two sorted vectors: `previous` (last step's
// contacts, read-only this step) and `current` (being written in key order this
// step); end_step() swaps them. A contact absent this step is dropped; deterministic;
// no allocation once the vectors have grown to the largest contact count.
#include <cassert>
#include <compare>
#include <cstdint>
#include <vector>

#include "contact/buffer.hpp"
#include "model/types.hpp"

namespace dsdem::contact {

struct ContactKey {
  Index i = 0;  // triangles, i < j
  Index j = 0;
  std::uint8_t feature = 0;  // ContactGeometry::feature
  friend auto operator<=>(const ContactKey&, const ContactKey&) = default;
  friend bool operator==(const ContactKey&, const ContactKey&) = default;
};

class ContactHistory {
 public:
  struct Entry {
    ContactKey key;
    Vec2 ft = Vec2::Zero();  // tangential force on i, N/m
  };

  // Previous step's tangential force of `key`, or zero for a new contact. Binary
  // search; thread-safe between begin_step and end_step (reads `previous` only).
  Vec2 previous(const ContactKey& key) const;

  // The same for a run of ascending keys: the cursor remembers where the last key
  // was, and the search gallops forward from there (O(1) per key for dense runs).
  // One cursor per thread; start each run with a fresh (zero) cursor.
  struct Cursor {
    std::size_t pos = 0;
  };
  Vec2 previous(const ContactKey& key, Cursor& cursor) const;

  // Starts writing a new step's contacts (keeps capacity).
  void begin_step() { current_.clear(); }
  // Records a contact of this step; keys must come in strictly ascending order.
  void record(const ContactKey& key, const Vec2& ft) {
    assert(current_.empty() || current_.back().key < key);
    current_.push_back({key, ft});
  }
  // This step's contacts become `previous`; the rest are forgotten.
  void end_step() { previous_.swap(current_); }

  void clear() {
    previous_.clear();
    current_.clear();
  }
  // Room for n contacts in both vectors (grows only, with headroom).
  void reserve(std::size_t n) {
    reserve_with_headroom(previous_, n);
    reserve_with_headroom(current_, n);
  }
  // Contacts stored at the last end_step().
  const std::vector<Entry>& entries() const { return previous_; }

 private:
  std::vector<Entry> previous_;
  std::vector<Entry> current_;
};

}  // namespace dsdem::contact
