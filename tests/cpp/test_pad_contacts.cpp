// The contact checks' passes (pad_contacts.cpp) on a few hand-placed points whose answers are
// known: the strips, the material's window, the patches at its ends and the fingers' way in.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "grasp_core/pad_contacts.hpp"

using grasp_core::FrameColumns;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

/// Points (X, Y, Z) in one column, read by two frames whose lines sit at x0 = 0 and x0 = 0.05.
struct Case {
  std::vector<float> x{0.000f, 0.005f, 0.012f, 0.030f, 0.001f, -0.004f};
  std::vector<float> y{-0.020f, 0.018f, 0.000f, 0.000f, 0.019f, 0.050f};
  std::vector<float> z{0.010f, 0.020f, 0.005f, 0.001f, 0.030f, 0.015f};
  std::vector<float> xyz;
  std::vector<std::int64_t> column{0, 0};
  std::vector<double> x0{0.0, 0.05};

  FrameColumns columns() {
    xyz.clear();
    for (const auto* v : {&x, &y, &z}) xyz.insert(xyz.end(), v->begin(), v->end());
    FrameColumns f;
    f.n_points = x.size(), f.n_frames = 2;
    f.x = xyz.data(), f.y = xyz.data() + x.size(), f.z = xyz.data() + 2 * x.size();
    f.column = column.data(), f.x0 = x0.data();
    return f;
  }
};

}  // namespace

TEST(PadContacts, DepthBoundsOfTheStripsAndNoneOutside) {
  Case c;
  const auto b = grasp_core::pad_depth_bounds(c.columns(), 0.01, 0.021);
  // strip |X| <= 0.01: points 0, 1, 4, 5 (Z 0.010, 0.020, 0.030, 0.015); palm adds point 2
  EXPECT_FLOAT_EQ(b.z_first[0], 0.010f);
  EXPECT_FLOAT_EQ(b.z_last[0], 0.030f);
  EXPECT_FLOAT_EQ(b.z_palm[0], 0.005f);
  // the second line (x0 = 0.05): nothing within 0.01, point 3 within 0.021
  EXPECT_EQ(b.z_first[1], kInf);
  EXPECT_EQ(b.z_last[1], -kInf);
  EXPECT_FLOAT_EQ(b.z_palm[1], 0.001f);
}

TEST(PadContacts, MaterialInTheWindowInBothPrecisions) {
  Case c;
  const FrameColumns f = c.columns();
  const std::vector<double> z64{0.015, 0.015};
  const std::vector<float> z32{0.015f, 0.015f};
  for (const auto& m : {grasp_core::pad_material<double>(f, 0.01, z64.data(), 0.006),
                        grasp_core::pad_material<float>(f, 0.01, z32.data(), 0.006)}) {
    // window |Z - 0.015| <= 0.006 within the strip: points 0 (Y -0.020), 1 (0.018), 5 (0.050)
    EXPECT_EQ(m.count[0], 3);
    EXPECT_FLOAT_EQ(m.y_lo[0], -0.020f);
    EXPECT_FLOAT_EQ(m.y_hi[0], 0.050f);
    EXPECT_EQ(m.count[1], 0);
    EXPECT_EQ(m.y_lo[1], kInf);
  }
}

TEST(PadContacts, PatchesAtBothEndsAndFingersInTheWay) {
  Case c;
  const FrameColumns f = c.columns();
  const std::vector<float> along{0.9f, 0.5f, 0.95f, 1.0f, 0.99f, 0.8f};  // one column of |n.c|
  const std::vector<std::int64_t> along_col{0, 0};
  grasp_core::EndLimits lim;
  lim.strip_half_width_m = 0.01, lim.half_length_m = 0.006;
  lim.contact_depth_m = 0.004f, lim.cos_cone = 0.85f, lim.finger_half_width_m = 0.012;
  const std::vector<double> z{0.015, 0.015};
  const std::vector<float> lo{-0.020f, kInf}, hi{0.020f, -kInf}, mid{0.0f, 0.0f};
  const std::vector<float> inner{0.017f, 0.017f}, outer{0.025f, 0.025f};
  const auto e = grasp_core::pad_contact_ends(f, along.data(), along_col.data(), lim, z.data(), lo.data(),
                                              hi.data(), mid.data(), inner.data(), outer.data());
  // material: points 0, 1, 5; upper end (Y >= 0.016): 1 and 5; lower end (Y <= -0.016): 0
  EXPECT_EQ(e.upper.count[0], 2);
  EXPECT_FLOAT_EQ(e.upper.x_lo[0], -0.004f);
  EXPECT_FLOAT_EQ(e.upper.x_hi[0], 0.005f);
  EXPECT_FLOAT_EQ(e.upper.normal_sum[0], 0.5f + 0.8f);
  EXPECT_EQ(e.upper.facing[0], 0);
  EXPECT_EQ(e.lower.count[0], 1);
  EXPECT_EQ(e.lower.facing[0], 1);
  // the way in (|X| <= 0.012, Z <= 0.021): upper band 0.017..0.025 holds point 1 (point 4 is
  // deeper); lower band -0.025..-0.017 holds point 0
  EXPECT_EQ(e.blocked_upper[0], 1);
  EXPECT_EQ(e.blocked_lower[0], 1);
  // the second line has no material: empty patches, its fingers meet nothing
  EXPECT_EQ(e.upper.count[1], 0);
  EXPECT_EQ(e.upper.x_lo[1], kInf);
  EXPECT_EQ(e.upper.normal_sum[1], 0.0f);
  EXPECT_EQ(e.blocked_upper[1], 0);
}
