// stvd/system/large_array.hpp: the huge-page advice changes where an array lives,
// never what it holds.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "stvd/system/large_array.hpp"
#include "stvd/types.hpp"

namespace stvd {
namespace {

TEST(LargeArray, HoldsCountCopiesOfTheValueAtEverySize) {
  // Empty, smaller than a page, and spanning several 2 MiB huge pages with
  // ragged ends.
  for (std::size_t count : {std::size_t{0}, std::size_t{3}, std::size_t{1} << 20, (std::size_t{3} << 20) + 7}) {
    const std::vector<double> a = makeLargeArray(count, 2.5);
    ASSERT_EQ(a.size(), count);
    for (std::size_t i = 0; i < count; i += 4099) {
      ASSERT_EQ(a[i], 2.5) << i;
    }
    if (count) {
      EXPECT_EQ(a.back(), 2.5);
    }
  }
  const std::vector<SymTensor3> t = makeLargeArray(std::size_t{200000}, SymTensor3{1.f, 0.f, 0.f, 2.f, 0.f, 3.f});
  EXPECT_EQ(t[123456].yy, 2.f);
  EXPECT_EQ(t.back().zz, 3.f);
}

TEST(LargeArray, AdviceOnMemoryThatIsNotPageAlignedIsHarmless) {
  std::vector<std::uint8_t> bytes(5u << 20, 7);
  adviseHugePages(bytes.data() + 1, bytes.size() - 3);
  adviseHugePages(bytes.data(), 100);  // spans no huge page: nothing to advise
  adviseHugePages(nullptr, 0);
  for (std::size_t i = 0; i < bytes.size(); i += 65537) ASSERT_EQ(bytes[i], 7);
}

}  // namespace
}  // namespace stvd
