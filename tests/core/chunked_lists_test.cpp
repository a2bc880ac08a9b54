// Specification of the front queue's bucket storage (detail/chunked_lists.hpp):
// lists give back their values in append order, and a drained list's
// memory is reused rather than kept per list.
#include "stvd/propagation/detail/chunked_lists.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace stvd::detail {
namespace {

using Lists = ChunkedLists<int, 4>;  // small chunks: most lists span several

std::vector<int> drained(Lists& lists, std::size_t list) {
  std::vector<int> values;
  lists.drain(list, [&](const int* run, int n) { values.insert(values.end(), run, run + n); });
  return values;
}

TEST(ChunkedLists, DrainGivesTheValuesInAppendOrderAndEmptiesTheList) {
  Lists lists(3);
  for (int i = 0; i < 11; ++i) lists.append(i % 2, i);  // lists 0 and 1 interleaved
  EXPECT_TRUE(lists.empty(2));
  EXPECT_EQ(drained(lists, 1), (std::vector<int>{1, 3, 5, 7, 9}));
  EXPECT_TRUE(lists.empty(1));
  EXPECT_FALSE(lists.empty(0));
  std::vector<int> seen;
  lists.forEachRun(0, [&](const int* run, int n) { seen.insert(seen.end(), run, run + n); });
  EXPECT_EQ(seen, (std::vector<int>{0, 2, 4, 6, 8, 10}));
  EXPECT_EQ(drained(lists, 0), seen);
  EXPECT_TRUE(lists.empty(0));
  EXPECT_TRUE(drained(lists, 0).empty());
}

TEST(ChunkedLists, ADrainedListsChunksServeTheNextAppends) {
  Lists lists(2);
  for (int i = 0; i < 40; ++i) lists.append(0, i);
  const std::size_t held = lists.capacityBytes();
  for (int round = 0; round < 5; ++round) {
    ASSERT_EQ(drained(lists, round % 2).size(), 40u);
    for (int i = 0; i < 40; ++i) lists.append((round + 1) % 2, i);
    EXPECT_EQ(lists.capacityBytes(), held) << "round " << round;
  }
}

TEST(ChunkedLists, DrainMayAppendToTheListItDrains) {
  Lists lists(1);
  for (int i = 0; i < 9; ++i) lists.append(0, i);
  // Keep the even values, in order, in the same list.
  lists.drain(0, [&](const int* run, int n) {
    for (int i = 0; i < n; ++i)
      if (run[i] % 2 == 0) lists.append(0, run[i]);
  });
  EXPECT_EQ(drained(lists, 0), (std::vector<int>{0, 2, 4, 6, 8}));
}

}  // namespace
}  // namespace stvd::detail
