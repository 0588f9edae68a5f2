// The machine's memory as commands judge it (core/system_memory.h).
#include "core/system_memory.h"

#include <catch2/catch.hpp>

#include "core/error.h"

namespace ssgi {
namespace {

TEST_CASE("byte counts: k, M, G and KiB, MiB, GiB binary, kB, MB, GB decimal, fractions allowed", "[memory]") {
  constexpr size_t kGiB = size_t(1) << 30;
  CHECK(ParseByteCount("1g") == kGiB);
  CHECK(ParseByteCount("1.5G") == kGiB + kGiB / 2);
  CHECK(ParseByteCount("512M") == size_t(512) << 20);
  CHECK(ParseByteCount("1GiB") == kGiB);
  CHECK(ParseByteCount("1GB") == size_t(1000000000));
  CHECK(ParseByteCount("800MB") == size_t(800000000));
  CHECK(ParseByteCount("64k") == 65536);
  CHECK(ParseByteCount("64kB") == 64000);
  CHECK(ParseByteCount("4096") == 4096);
  CHECK(ParseByteCount("4096B") == 4096);
  for (const char* bad : {"", "lots", "0", "0M", "1.2.3G", "G", "-1G", "1 G", "1Gb", "1e9"}) {
    CAPTURE(bad);
    CHECK_THROWS_AS(ParseByteCount(bad), InputError);
  }
  CHECK_THROWS_WITH(ParseByteCount("lots", "--max-memory"),
                    "--max-memory: must be a size like 512M, 1.5G, 2GiB or 800MB, got 'lots'");
}

TEST_CASE("byte counts for messages", "[memory]") {
  CHECK(FormatBytes(size_t(730) << 20) == "730 MiB");
  CHECK(FormatBytes(size_t(3) << 29) == "1.5 GiB");
  CHECK(FormatBytes(12 * 1024) == "12 KiB");
}

TEST_CASE("the default memory budget is known on Linux and no larger than what is available", "[memory]") {
  const MemoryBudget budget = DefaultMemoryBudget();
  CHECK(budget.bytes > 0);
  CHECK(budget.bytes <= AvailableMemoryBytes());
  CHECK(!budget.source.empty());
  CHECK(ResidentBytes() > 0);
  CHECK(PeakResidentBytes() >= ResidentBytes() / 2);
}

}  // namespace
}  // namespace ssgi
