// (ours) Joining a segment nested in another one across a sloped surface.
//
// Seen straight from above, a bottle's cap and its shoulder, or a bowl's floor and its rim, are
// separated in the image by a range step with no visible wall between them: the organized
// segmentation cuts them into two segments, one enclosed by the other. A box standing on a larger
// box looks the same from above, except that the surface around the inner segment is flat (the
// lower box's top), whereas around a cap the shoulder falls away and around a bowl's floor the
// inner wall rises. The rule: segment A joins segment B when
//  - A is nested in B: B takes at least segment_nest_fraction of the image-neighbour pairs
//    leaving A for other segments (pairs to non-candidate pixels — the table, holes below the
//    band inside a bowl — and to slivers smaller than max(segment_absorb_max_points,
//    cluster_min_points) do not count; B must not be one), and A's pixel box lies within B's
//    (1 px slack), and
//  - the surface joining them slopes: over the first segment_nest_rings_px one-pixel rings of B
//    around A (a shoulder around a cap), or of A inside B (a bowl's inner wall inside its rim),
//    the rings' mean heights above the table change with their mean horizontal distance from A's
//    centroid by between tan(segment_nest_min_slope_deg) and tan(segment_nest_max_slope_deg) (a
//    least-squares line through the rings that have a few pixels; steeper is a wall seen
//    edge-on, e.g. the side face of a box standing on a box, seen obliquely).
// A join whose union's 3-D box diagonal would exceed cluster_max_extent is not made (the joined
// segment would be rejected as a cluster, losing both parts).
// Decisions are taken on the segments as they are before a pass, then applied; up to three
// passes (a cap nested in a ring nested in a shoulder joins one level per pass).
#pragma once

#include "grasp_core/params.hpp"
#include "grasp_core/types.hpp"

#include <array>
#include <cstddef>
#include <utility>
#include <vector>

namespace grasp_core {

/// Reusable buffers of join_nested_segments (a frame of a constant size allocates little).
struct NestedWorkspace {
  std::vector<int> root, size, leaving, mark;
  std::vector<std::array<int, 4>> box;
  std::vector<Vec3> lo, hi;
  std::vector<std::pair<int, int>> into;
};

/// Joins nested segments (see above) in the union-find `parent` of the candidates.
/// xyz: n_cand interleaved points; cand_rows: their pixels (v * width + u); pix: per pixel its
/// candidate index or -1 (width * height entries); table: heights are measured from it.
/// Does nothing when segment_nest_fraction <= 0.
void join_nested_segments(const float* xyz, const int* cand_rows, std::size_t n_cand, int width,
                          int height, const Plane& table, const SceneFilterParams& params,
                          const int* pix, std::vector<int>& parent, NestedWorkspace& ws);

}  // namespace grasp_core
