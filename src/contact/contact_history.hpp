#pragma once
// Tangential-force history of the contacts (docs/theory.md §4: stored per element pair +
// feature, carried between steps). Two sets of sorted segments: `previous` (last step's
// contacts, read-only this step) and `current` (being written this step); end_step()
// swaps them. Several threads may write a step at once, one segment each: segment t
// holds ascending keys, all above those of segment t - 1, so the segments in order are
// one sorted list. Each thread then writes and next step mostly reads its own segment
// (the contacts of its share of the pairs): no serial copy of every thread's contacts,
// and no history line last written by another core (a costly transfer between cores).
// A contact absent this step is dropped; deterministic; no allocation once the segments
// have grown to the largest contact counts.
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
    std::size_t segment = 0;
    std::size_t pos = 0;
  };
  Vec2 previous(const ContactKey& key, Cursor& cursor) const;

  // Starts writing a new step's contacts in n_segments segments (keeps capacity).
  void begin_step(int n_segments = 1);
  // Segment t of this step, to append entries to (one writer per segment).
  std::vector<Entry>& segment(int t) { return current_[static_cast<std::size_t>(t)]; }
  // Records a contact of this step in the last segment; keys must come in strictly
  // ascending order.
  void record(const ContactKey& key, const Vec2& ft) {
    std::vector<Entry>& last = current_[static_cast<std::size_t>(n_current_ - 1)];
    assert(last.empty() || last.back().key < key);
    last.push_back({key, ft});
  }
  // Room for n entries in each segment of this step, in both sets (grows only): any
  // segment may hold up to a whole step's contacts.
  void reserve_headroom(std::size_t n);
  // This step's contacts become `previous`; the rest are forgotten.
  void end_step();

  void clear();
  // Contacts stored at the last end_step(), in key order (a copy: checkpoints, tests).
  std::vector<Entry> entries() const;
  std::size_t size() const;

 private:
  std::vector<ThreadVector<Entry>> previous_, current_;
  int n_previous_ = 0, n_current_ = 0;
};

}  // namespace dsdem::contact
