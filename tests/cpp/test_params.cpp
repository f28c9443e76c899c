#include <gtest/gtest.h>

#include "grasp_core/params.hpp"

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
