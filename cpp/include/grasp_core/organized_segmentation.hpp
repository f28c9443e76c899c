// (ours) Organized segmentation of the object candidates of one RGB-D frame.
//
// Euclidean clustering with a radius of 15 mm (method.md §1.4) merges objects closer than that, which
// in packed and piled scenes is the common case. When the frame is organized (row v*W + u is
// pixel (u, v)), the candidates (points above the band) are segmented over the image instead,
// in the manner of PCL's OrganizedConnectedComponentSegmentation with a comparator: two
// neighbouring candidate pixels (8-neighbourhood) are in one segment when
//  - their smoothed ranges from the camera differ by at most
//    segment_max_step_m * max(1, r / depth_noise_ref_range_m)^depth_noise_exponent
//    (a depth discontinuity: a height step, a slit between two objects, an occlusion edge); the
//    range of each pixel is first averaged over the candidates of a (2R+1)^2 window whose range
//    is within 3 sigma(r) of its own (an edge-preserving box filter: the sensor's per-pixel
//    noise, 2.8 mm between two pixels at 0.4 m, would otherwise cut surfaces and join steps), and
//  - with colour, where both pixels are bright and saturated enough (max channel >=
//    segment_min_brightness, saturation >= segment_min_saturation), their hues differ by at
//    most segment_max_hue_diff_deg: a colour boundary between two touching objects. Hue, not
//    RGB or chromaticity: shading scales a colour and ambient light or a highlight adds white,
//    neither of which changes the hue; grey, white and black surfaces are not compared.
// A gap between two objects through which the table shows is a boundary by construction: the
// table is below the band, so it is no candidate. Segments of fewer than
// segment_absorb_max_points points (slivers of steep side faces, whose range steps between
// pixels are large) then join the large segment they touch most, over neighbour pairs within
// cluster_eps in 3-D. With the table plane, a segment nested in another one and joined to it by a
// sloped surface then joins it (nested_segments.hpp: a bottle's cap and shoulder, a bowl's floor
// and rim seen from above). Components are then labelled by the rules of
// method.md §1.4 (min_points, extents) through clusters_from_components().
//
// Why not PCL's class itself: OrganizedConnectedComponentSegmentation visits every pixel of
// the frame (307k at 640x480) through a virtual comparator and needs a PCL cloud of the whole
// frame; the candidates are a few percent of it, and this pass visits only them.
#pragma once

#include "grasp_core/clustering.hpp"
#include "grasp_core/nested_segments.hpp"
#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace grasp_core {

/// Reusable buffers (frames of a constant size allocate nothing after the first).
struct OrganizedWorkspace {
  std::vector<int> pixel_to_candidate;  ///< per pixel: candidate index or -1 (kept all -1 between calls)
  std::vector<float> range, smooth;     ///< per candidate [m]
  std::vector<float> range_image;       ///< per pixel: the candidate's range or NaN (kept all NaN between calls)
  std::vector<float> hue;               ///< per candidate [deg], -1: not comparable
  std::vector<int> parent;              ///< union-find
  NestedWorkspace nested;               ///< join_nested_segments' buffers
};

/// Segment ids (any ids in [0, n_cand)) of the candidates of an organized frame.
/// cand_xyz: n_cand interleaved xyz; cand_rows: each candidate's input row = pixel index
/// (ascending or not, each < width * height, distinct); n_pixels = width * height rows of the frame;
/// rgb: nullptr or width*height*3 bytes (row-major RGB, aligned with the pixels).
/// table: the table plane (heights for the nested-segment join) or nullptr (no join).
/// Throws std::invalid_argument on width < 1, n_pixels % width != 0 or a row >= n_pixels.
std::vector<int> organized_components(const float* cand_xyz, const int* cand_rows,
                                      std::size_t n_cand, std::size_t n_pixels, int width,
                                      const std::uint8_t* rgb, const Vec3& camera,
                                      const SceneFilterParams& params, OrganizedWorkspace& ws,
                                      const Plane* table = nullptr);

}  // namespace grasp_core
