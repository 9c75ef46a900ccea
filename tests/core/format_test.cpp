#include "core/format.h"

#include <catch2/catch.hpp>

#include <string>

namespace jetshell {

TEST_CASE("formatNumber: the whole text, however long") {
  CHECK(formatNumber("%.3f", 1.23456) == "1.235");
  CHECK(formatNumber("%9.4f", -2.0) == "  -2.0000");
  // 1e70 in fixed notation: 71 digits and ".000", which a fixed buffer of 64 characters would have cut to a
  // number 1e8 times smaller.
  const std::string big = formatNumber("%.3f", 1e70);
  CHECK(big.size() == 75);
  CHECK(big.substr(big.size() - 4) == ".000");
  CHECK(formatNumber("%.3f", 1e300).size() == 305);
  CHECK(formatNumber("%.1e", -1e-300) == "-1.0e-300");
}

}  // namespace jetshell
