// Lengths, areas and volumes in the CLI's text summaries.

#include "Units.h"

#include <gtest/gtest.h>

#include <limits>

namespace levelfuse::cli {
namespace {

TEST(Units, LengthsTakeTheUnitTheirSizeCallsFor) {
  EXPECT_EQ(length(0.0005002), "0.50 mm");
  EXPECT_EQ(length(9.305e-05), "0.093 mm");
  EXPECT_EQ(length(0.012), "1.2 cm");
  EXPECT_EQ(length(0.01), "1.0 cm");
  EXPECT_EQ(length(0.00819), "8.2 mm");
  EXPECT_EQ(length(3.4), "3.4 m");
  EXPECT_EQ(length(250.0), "250 m");
  EXPECT_EQ(length(4e-6), "4.0 µm");
  EXPECT_EQ(length(-0.0021), "-2.1 mm");
  EXPECT_EQ(length(0.0), "0 m");
}

TEST(Units, RoundingUpMovesToTheNextUnit) {
  EXPECT_EQ(length(0.00996), "1.0 cm");
  EXPECT_EQ(length(0.998), "1.0 m");
  EXPECT_EQ(length(0.0996), "10 cm");
}

TEST(Units, AreasAndVolumes) {
  EXPECT_EQ(area(0.0571), "571 cm²");
  EXPECT_EQ(area(2.5), "2.50 m²");
  EXPECT_EQ(area(3e-5), "30.0 mm²");
  EXPECT_EQ(volume(7.62e-4), "762 cm³");
  EXPECT_EQ(volume(12.0), "12.0 m³");
}

TEST(Units, NumbersThatAreNotFinitePrintAsThemselves) {
  EXPECT_EQ(length(std::numeric_limits<double>::infinity()), "inf m");
  EXPECT_EQ(length(std::numeric_limits<double>::quiet_NaN()), "nan m");
}

}  // namespace
}  // namespace levelfuse::cli
