#include <gtest/gtest.h>

#include "grasp_core/params.hpp"

#include <limits>
#include <string>

using namespace grasp_core;

TEST(Params, DefaultsAreValid) {
  EXPECT_NO_THROW(SceneFilterParams{}.validate());
  EXPECT_NO_THROW(ObbParams{}.validate());
}

TEST(Params, NegativeValueNamesTheParameter) {
  SceneFilterParams p;
  p.cluster_eps = -1.0;
  try {
    p.validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("cluster_eps"), std::string::npos);
  }
}

TEST(Params, CoordinateBoundIsValidated) {
  EXPECT_DOUBLE_EQ(SceneFilterParams{}.max_abs_coordinate_m, kDefaultMaxAbsCoordinate_m);
  EXPECT_DOUBLE_EQ(kDefaultMaxAbsCoordinate_m, 1000.0);
  for (const double bad : {0.0, -1.0, 2e9, std::numeric_limits<double>::quiet_NaN(),
                           std::numeric_limits<double>::infinity()}) {
    SceneFilterParams p;
    p.max_abs_coordinate_m = bad;
    try {
      p.validate();
      FAIL() << "expected std::invalid_argument for " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("max_abs_coordinate_m"), std::string::npos);
    }
  }
  SceneFilterParams ok;
  ok.max_abs_coordinate_m = kMaxAbsCoordinateLimit_m;
  EXPECT_NO_THROW(ok.validate());
}
