// Contact history store: carried for persistent contacts, dropped when a contact
// ends, deterministic lookups, no allocation once warm (docs/theory.md §4).
#include <gtest/gtest.h>

#include "common/alloc_counter.hpp"
#include "contact/contact_history.hpp"

using namespace dsdem;
using namespace dsdem::contact;

TEST(ContactHistory, CarriesPersistentContactsAndDropsEndedOnes) {
  ContactHistory h;
  const ContactKey a{1, 5, 0}, b{1, 5, 4}, c{2, 3, 1}, d{7, 9, 2};
  EXPECT_EQ(h.previous(a), Vec2::Zero());  // nothing stored yet
  h.begin_step();
  h.record(a, Vec2(1.0, 2.0));
  h.record(b, Vec2(-3.0, 0.5));
  h.record(c, Vec2(0.0, 7.0));
  h.end_step();
  EXPECT_EQ(h.previous(a), Vec2(1.0, 2.0));
  EXPECT_EQ(h.previous(b), Vec2(-3.0, 0.5));
  EXPECT_EQ(h.previous(c), Vec2(0.0, 7.0));
  EXPECT_EQ(h.previous(ContactKey{1, 5, 1}), Vec2::Zero());  // other feature of the pair
  // Next step: b ended, a and c persist with new forces, d is new.
  h.begin_step();
  h.record(a, h.previous(a) + Vec2(1.0, 0.0));
  h.record(c, h.previous(c) * 0.5);
  h.record(d, h.previous(d) + Vec2(4.0, 4.0));
  h.end_step();
  EXPECT_EQ(h.previous(a), Vec2(2.0, 2.0));
  EXPECT_EQ(h.previous(b), Vec2::Zero());  // dropped
  EXPECT_EQ(h.previous(c), Vec2(0.0, 3.5));
  EXPECT_EQ(h.previous(d), Vec2(4.0, 4.0));
  ASSERT_EQ(h.entries().size(), 3u);
  EXPECT_EQ(h.entries()[0].key, a);
  EXPECT_EQ(h.entries()[1].key, c);
  EXPECT_EQ(h.entries()[2].key, d);
  // b comes back: a new contact, starting from zero.
  h.begin_step();
  h.record(b, h.previous(b));
  h.end_step();
  EXPECT_EQ(h.previous(b), Vec2::Zero());
  EXPECT_EQ(h.entries().size(), 1u);
}

TEST(ContactHistory, KeyOrderIsTriangleITriangleJFeature) {
  EXPECT_LT((ContactKey{1, 9, 5}), (ContactKey{2, 3, 0}));
  EXPECT_LT((ContactKey{2, 3, 5}), (ContactKey{2, 4, 0}));
  EXPECT_LT((ContactKey{2, 4, 0}), (ContactKey{2, 4, 1}));
}

TEST(ContactHistory, NoAllocationOnceWarm) {
  ContactHistory h;
  auto step = [&](int n, int shift) {
    h.begin_step();
    for (int k = 0; k < n; ++k) {
      const ContactKey key{k + shift, k + shift + 1, static_cast<std::uint8_t>(k % 6)};
      h.record(key, h.previous(key) + Vec2(1.0, 0.0));
    }
    h.end_step();
  };
  for (int s = 0; s < 3; ++s) step(5000, s);  // warm-up: both vectors grow
  dsdem::test::AllocationScope scope;
  for (int s = 0; s < 50; ++s) step(4000 + 20 * s, s % 3);
  EXPECT_EQ(scope.count(), 0);
  // The shift changes every step, so no key of the last step was in the one before: all
  // were dropped in between and restart from zero (+1 this step).
  ASSERT_EQ(h.entries().size(), 4000u + 20 * 49);
  for (const auto& e : h.entries()) EXPECT_EQ(e.ft, Vec2(1.0, 0.0));
  // Same keys twice in a row: carried (+1 per step).
  step(100, 0);
  step(100, 0);
  for (const auto& e : h.entries()) EXPECT_EQ(e.ft, Vec2(2.0, 0.0));
}

TEST(ContactHistory, CursorLookupsMatchBinarySearch) {
  // Random stored keys; ascending runs of queries (present and absent) through a cursor
  // give exactly what the plain binary search gives.
  ContactHistory h;
  h.begin_step();
  unsigned state = 12345;
  auto next = [&state]() { return state = state * 1103515245u + 12345u; };
  Index i = 0;
  for (int k = 0; k < 3000; ++k) {  // strictly ascending: 1 or 2 features per (i, j)
    i += 1 + static_cast<Index>(next() % 2);
    const Index j = i + 1 + static_cast<Index>(next() % 2);
    const std::uint8_t f = static_cast<std::uint8_t>(next() % 5);
    h.record({i, j, f}, Vec2(k, -k));
    if (next() % 2) h.record({i, j, static_cast<std::uint8_t>(f + 1)}, Vec2(-k, k));
  }
  h.end_step();
  const std::vector<ContactHistory::Entry> stored = h.entries();
  for (std::size_t k = 1; k < stored.size(); ++k) ASSERT_LT(stored[k - 1].key, stored[k].key);
  for (int run = 0; run < 20; ++run) {
    ContactHistory::Cursor cursor;
    int found = 0;
    for (Index qi = 0; qi <= i + 1; qi += 1 + static_cast<Index>(next() % (run + 1))) {
      for (Index dj = 1; dj <= 2; ++dj)
        for (std::uint8_t f = 0; f < 6; f += 1 + next() % 2) {
          const ContactKey key{qi, qi + dj, f};
          const Vec2 want = h.previous(key);
          EXPECT_EQ(h.previous(key, cursor), want);
          found += want != Vec2::Zero() ? 1 : 0;
        }
    }
    EXPECT_GT(found, 0);
  }
}

TEST(ContactHistory, SegmentsWrittenByThreadsReadAsOneSortedList) {
  // One step written as one segment, the next as 3 segments of one ascending key list
  // (one empty): lookups (cursor and binary search) and entries() see the same list.
  std::vector<ContactKey> keys;
  for (Index i = 0; i < 600; ++i)
    for (std::uint8_t f = 0; f < 3; f += 1 + static_cast<std::uint8_t>(i % 2)) keys.push_back({i, i + 1 + (i % 3), f});
  ContactHistory one, three;
  one.begin_step();
  for (std::size_t k = 0; k < keys.size(); ++k) one.record(keys[k], Vec2(k, 1.0));
  one.end_step();
  three.begin_step(3);
  const std::size_t cut = keys.size() / 3;
  for (std::size_t k = 0; k < keys.size(); ++k)  // segment 1 stays empty
    three.segment(k < cut ? 0 : 2).push_back({keys[k], Vec2(k, 1.0)});
  three.end_step();
  const auto a = one.entries(), b = three.entries();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].key, b[k].key);
    EXPECT_EQ(a[k].ft, b[k].ft);
  }
  EXPECT_EQ(three.size(), keys.size());
  // Present and absent keys, in ascending runs that start anywhere.
  for (std::size_t start : {std::size_t{0}, cut - 1, cut, keys.size() - 2}) {
    ContactHistory::Cursor c1, c3;
    for (std::size_t k = start; k < keys.size(); ++k) {
      const ContactKey absent{keys[k].i, keys[k].j, 7};
      EXPECT_EQ(three.previous(keys[k], c3), Vec2(k, 1.0));
      EXPECT_EQ(one.previous(keys[k], c1), Vec2(k, 1.0));
      EXPECT_EQ(three.previous(keys[k]), Vec2(k, 1.0));
      if (k + 1 < keys.size() && absent < keys[k + 1]) {
        EXPECT_EQ(three.previous(absent, c3), Vec2::Zero());
        EXPECT_EQ(three.previous(absent), Vec2::Zero());
      }
    }
  }
  EXPECT_EQ(three.previous(ContactKey{9999, 10000, 0}), Vec2::Zero());
  ContactHistory::Cursor past;
  EXPECT_EQ(three.previous(ContactKey{9999, 10000, 0}, past), Vec2::Zero());
}
