// Bindings of method.md §1: plane fit, extraction, table choice, clustering, persistence,
// and the per-frame SceneFilter.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <climits>

#include "array_input.hpp"
#include "guarded.hpp"
#include "grasp_core/clustering.hpp"
#include "grasp_core/plane_fit.hpp"
#include "grasp_core/plane_persistence.hpp"
#include "grasp_core/scene_filter.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {

/// labels of a result as a read-only numpy view whose lifetime is tied to `owner`.
template <typename R>
py::array_t<int> labels_view(const R& r, const py::object& owner) {
  py::array_t<int> a(static_cast<py::ssize_t>(r.labels.size()), r.labels.data(), owner);
  py::detail::array_proxy(a.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return a;
}

template <typename Fn>
auto with_view(const PointsView& v, Fn&& fn) {
  if (v.is_float) return fn(static_cast<const float*>(v.data));
  return fn(static_cast<const double*>(v.data));
}

/// A float64 view as PointsD (rows kept 1:1, non-finite values included).
PointsD as_points_d(const PointsView& v) {
  const double* p = static_cast<const double*>(v.data);
  PointsD d(static_cast<Eigen::Index>(v.rows), 3);
  for (std::size_t r = 0; r < v.rows; ++r)
    for (int c = 0; c < 3; ++c) d(static_cast<Eigen::Index>(r), c) = p[r * v.row_stride + c];
  return d;
}


}  // namespace

void bind_scene_filter(py::module_& m) {
  py::class_<PlaneFit>(m, "PlaneFit", "Result of one RANSAC plane search (method.md §1.1)")
      .def_readonly("plane", &PlaneFit::plane)
      .def_readonly("ransac_plane", &PlaneFit::ransac_plane)
      .def_readonly("inliers", &PlaneFit::inliers)
      .def_readonly("refined", &PlaneFit::refined)
      .def_readonly("iterations", &PlaneFit::iterations);

  // Parameter structs are copied before the GIL is released: another thread may assign
  // their fields meanwhile.
  m.def("fit_plane_ransac",
        [](const py::object& points, const SceneFilterParams& params_in, const py::object& seed) {
          const SceneFilterParams params = params_in;
          params.validate();
          const std::uint64_t s = seed_arg(seed, "seed");
          PointsD pts = points_double(points, "points", nullptr, false, params.max_abs_coordinate_m);
          py::gil_scoped_release release;
          return fit_plane_ransac(pts, params, s);
        },
        py::arg("points"), py::arg("params"), py::arg("seed") = 0,
        "method.md §1.1: one horizontal-constrained RANSAC plane (PCL sample consensus) with "
        "least-squares refinement and the post-refinement tilt re-check, on the rows that are "
        "finite and within params.max_abs_coordinate_m. None if no model.");

  py::class_<PlaneCandidate>(m, "PlaneCandidate", "One plane of the sequential extraction")
      .def_readonly("plane", &PlaneCandidate::plane)
      .def_readonly("count_whole", &PlaneCandidate::count_whole)
      .def_readonly("subsample_inliers", &PlaneCandidate::subsample_inliers)
      .def_readonly("subsample_size", &PlaneCandidate::subsample_size)
      .def_readonly("removed", &PlaneCandidate::removed)
      .def_readonly("refined", &PlaneCandidate::refined)
      .def("__repr__", [](const PlaneCandidate& c) {
        return "PlaneCandidate(height_m=" + std::to_string(c.plane.height_m()) +
               ", count_whole=" + std::to_string(c.count_whole) + ")";
      });

  m.def("extract_planes",
        [](const py::object& points, const SceneFilterParams& params_in, const py::object& seed) {
          const SceneFilterParams params = params_in;
          params.validate();
          const std::uint64_t s = seed_arg(seed, "seed");
          PointsView v = points_view(points, "points");
          py::gil_scoped_release release;
          if (v.is_float)
            return extract_planes(static_cast<const float*>(v.data), v.rows, v.row_stride, params, s);
          return extract_planes(as_points_d(v), params, s);
        },
        py::arg("points"), py::arg("params"), py::arg("seed") = 0,
        "method.md §1.2: sequential plane extraction on the rows that are finite and within "
        "params.max_abs_coordinate_m; counts are on the whole cloud.");

  m.def("choose_table", [](const std::vector<PlaneCandidate>& planes, double dominance) {
          if (!(dominance > 0 && dominance <= 1)) throw py::value_error("dominance: expected (0, 1]");
          return choose_table(planes, dominance);
        },
        py::arg("planes"), py::arg("dominance"),
        "method.md §1.3: index of the table (dominance, then height), -1 if none.");

  py::class_<ClusterInfo>(m, "ClusterInfo", "One connected component with >= min_points points")
      .def_readonly("label", &ClusterInfo::label)
      .def_readonly("num_points", &ClusterInfo::num_points)
      .def_readonly("extent_m", &ClusterInfo::extent_m)
      .def_readonly("min", &ClusterInfo::min)
      .def_readonly("max", &ClusterInfo::max)
      .def_readonly("accepted", &ClusterInfo::accepted)
      .def_readonly("height_m", &ClusterInfo::height_m,
                    "with the camera position: 90th-percentile height above the table [m]")
      .def_readonly("range_m", &ClusterInfo::range_m, "camera -> centroid distance [m]")
      .def_readonly("min_height_m", &ClusterInfo::min_height_m,
                    "the height it needed at that range [m] (object_min_height_sigmas)")
      .def_readonly("too_low", &ClusterInfo::too_low, "refused by the range-dependent minimum height");

  py::class_<ClusterResult>(m, "ClusterResult", "Euclidean clustering result")
      .def_property_readonly("labels", [](py::object self) {
        return labels_view(self.cast<const ClusterResult&>(), self);
      })
      .def_readonly("clusters", &ClusterResult::clusters)
      .def_readonly("num_accepted", &ClusterResult::num_accepted)
      .def_readonly("num_components", &ClusterResult::num_components)
      .def_readonly("num_invalid", &ClusterResult::num_invalid,
                    "rows labelled LABEL_INVALID: NaN/Inf or beyond max_abs_coordinate_m")
      .def_readonly("num_out_of_range", &ClusterResult::num_out_of_range,
                    "of num_invalid: finite rows with a |coordinate| > max_abs_coordinate_m");

  m.def("euclidean_clusters",
        [](const py::object& points, double eps_m, const py::object& min_points_obj,
           double min_extent_m, double max_extent_m, double voxel_m, double bound) {
          if (!(eps_m > 0 && eps_m <= 1.0)) throw py::value_error("eps_m: expected a radius in (0, 1] m");
          const int min_points = static_cast<int>(int_arg(min_points_obj, "min_points", 1, INT_MAX));
          checked_bound(bound);
          if (!(min_extent_m >= 0)) throw py::value_error("min_extent_m: expected >= 0");
          if (!std::isfinite(max_extent_m)) throw py::value_error("max_extent_m: must be finite");
          if (!(voxel_m >= 0 && voxel_m < eps_m)) throw py::value_error("voxel_m: expected [0, eps_m)");
          PointsView v = points_view(points, "points");
          py::gil_scoped_release release;
          if (v.is_float)
            return euclidean_clusters(static_cast<const float*>(v.data), v.rows, v.row_stride, eps_m,
                                      min_points, min_extent_m, max_extent_m, voxel_m, bound);
          return euclidean_clusters(as_points_d(v), eps_m, min_points, min_extent_m, max_extent_m,
                                    voxel_m, bound);
        },
        py::arg("points"), py::arg("eps_m"), py::arg("min_points"), py::arg("min_extent_m"),
        py::arg("max_extent_m"), py::arg("voxel_m") = 0.0,
        py::arg("max_abs_coordinate_m") = kDefaultMaxAbsCoordinate_m,
        "method.md §1.4: Euclidean clusters (PCL semantics) with extent filters; labels for every row "
        "(LABEL_INVALID for NaN/Inf rows and rows with a |coordinate| > max_abs_coordinate_m).");

  py::enum_<FrameEvent::Level>(m, "EventLevel")
      .value("DEBUG", FrameEvent::Level::kDebug)
      .value("INFO", FrameEvent::Level::kInfo)
      .value("WARNING", FrameEvent::Level::kWarning)
      .value("ERROR", FrameEvent::Level::kError);
  py::class_<FrameEvent>(m, "FrameEvent", "A log line from the core (Python logs it)")
      .def_readonly("level", &FrameEvent::level)
      .def_readonly("message", &FrameEvent::message)
      .def("__repr__", [](const FrameEvent& e) { return "FrameEvent(" + e.message + ")"; });

  py::enum_<PlaneDecision>(m, "PlaneDecision")
      .value("NO_PLANE", PlaneDecision::kNoPlane)
      .value("FALLBACK", PlaneDecision::kFallback)
      .value("LOCKED", PlaneDecision::kLocked)
      .value("FOLLOWED", PlaneDecision::kFollowed)
      .value("RESTARTED", PlaneDecision::kRestarted)
      .value("HARDENED", PlaneDecision::kHardened)
      .value("REFUSED", PlaneDecision::kRefused)
      .value("KEPT_NO_FIT", PlaneDecision::kKeptNoFit)
      .value("UNLOCKED_FIT", PlaneDecision::kUnlockedFit);

  py::class_<PersistenceState>(m, "PersistenceState", "method.md §1.5 lock state")
      .def_readonly("lock", &PersistenceState::lock)
      .def_readonly("anchor", &PersistenceState::anchor)
      .def_readonly("hits", &PersistenceState::hits)
      .def_readonly("hardened", &PersistenceState::hardened)
      .def_readonly("frames_without_lock", &PersistenceState::frames_without_lock)
      .def_readonly("fallback_active", &PersistenceState::fallback_active)
      .def_readonly("fallback_reported", &PersistenceState::fallback_reported);

  py::class_<PersistenceUpdate>(m, "PersistenceUpdate")
      .def_readonly("table", &PersistenceUpdate::table)
      .def_readonly("environment_emitted", &PersistenceUpdate::environment_emitted)
      .def_readonly("fallback", &PersistenceUpdate::fallback)
      .def_readonly("decision", &PersistenceUpdate::decision)
      .def_readonly("events", &PersistenceUpdate::events);

  m.def("planes_close", &planes_close, py::arg("a"), py::arg("b"), py::arg("tol_deg"),
        py::arg("tol_m"), "method.md §1.5 closeness: normal angle <= tol_deg and height diff <= tol_m");

  using GPersistence = Guarded<PlanePersistence>;
  py::class_<GPersistence>(m, "PlanePersistence",
                           "method.md §1.5 plane persistence state machine. Thread-safe: calls from "
                           "several threads are serialised by a mutex (the GIL is released while "
                           "waiting); a view (SceneFilter.persistence) shares its owner's mutex.")
      .def(py::init([](const SceneFilterParams& p) { return GPersistence::make(p); }), py::arg("params"))
      .def("update", [](const GPersistence& g, const std::optional<Plane>& fit) {
             return locked(g, [&](PlanePersistence& p) { return p.update(fit); });
           }, py::arg("fit"), "Feed this frame's fit (None: no plane this frame).")
      .def_property_readonly("state", [](const GPersistence& g) {
             return locked(g, [](PlanePersistence& p) { return PersistenceState(p.state()); });
           }, "a snapshot (copy) of the lock state")
      .def_property_readonly("locked", [](const GPersistence& g) {
             return locked(g, [](PlanePersistence& p) { return p.locked(); });
           })
      .def_property_readonly("hardened", [](const GPersistence& g) {
             return locked(g, [](PlanePersistence& p) { return p.hardened(); });
           })
      .def("reset", [](const GPersistence& g) { locked(g, [](PlanePersistence& p) { p.reset(); }); });

  py::class_<SceneFilterResult>(m, "SceneFilterResult", "Everything the scene filter computed for one frame")
      .def_property_readonly("labels", [](py::object self) {
        return labels_view(self.cast<const SceneFilterResult&>(), self);
      }, "one int per input row: LABEL_INVALID (-2), LABEL_ENVIRONMENT (-1) or an object id >= 0")
      .def_readonly("environment_emitted", &SceneFilterResult::environment_emitted)
      .def_readonly("fallback", &SceneFilterResult::fallback)
      .def_readonly("table", &SceneFilterResult::table)
      .def_readonly("fit", &SceneFilterResult::fit)
      .def_readonly("band", &SceneFilterResult::band)
      .def_readonly("planes", &SceneFilterResult::planes)
      .def_readonly("table_index", &SceneFilterResult::table_index)
      .def_readonly("num_valid", &SceneFilterResult::num_valid,
                    "rows used: finite and within max_abs_coordinate_m")
      .def_readonly("num_invalid", &SceneFilterResult::num_invalid,
                    "rows dropped (LABEL_INVALID): NaN/Inf, or a |coordinate| > max_abs_coordinate_m")
      .def_readonly("num_out_of_range", &SceneFilterResult::num_out_of_range,
                    "of num_invalid: finite rows with a |coordinate| > max_abs_coordinate_m")
      .def_readonly("max_abs_coordinate_m", &SceneFilterResult::max_abs_coordinate_m,
                    "the coordinate bound applied this frame [m]")
      .def_readonly("num_candidates", &SceneFilterResult::num_candidates)
      .def_readonly("cluster_ids", &SceneFilterResult::cluster_ids)
      .def_readonly("clusters", &SceneFilterResult::clusters)
      .def_readonly("decision", &SceneFilterResult::decision)
      .def_readonly("persistence", &SceneFilterResult::persistence)
      .def_readonly("events", &SceneFilterResult::events)
      .def_readonly("ms_pack", &SceneFilterResult::ms_pack,
                    "validity check, packing and labels of every row [ms]")
      .def_readonly("ms_plane", &SceneFilterResult::ms_plane)
      .def_readonly("ms_cluster", &SceneFilterResult::ms_cluster)
      .def_readonly("ms_total", &SceneFilterResult::ms_total)
      .def_readonly("organized", &SceneFilterResult::organized,
                    "the candidates were segmented over the image (organized segmentation)")
      .def_readonly("num_too_low", &SceneFilterResult::num_too_low,
                    "clusters refused by the range-dependent minimum object height");

  using GFilter = Guarded<SceneFilter>;
  py::class_<GFilter>(m, "SceneFilter",
                      "The per-frame scene filter (method.md §1); owns the plane lock. Thread-safe: "
                      "calls from several threads are serialised by a mutex (the GIL is released "
                      "while waiting and while processing); a view (Perception.scene_filter) "
                      "shares its owner's mutex.")
      .def(py::init([](const SceneFilterParams& p) { return GFilter::make(p); }), py::arg("params"))
      .def("process",
           [](const GFilter& g, const py::object& points) {
             PointsView v = points_view(points, "points");
             return locked(g, [&](SceneFilter& f) {
               return with_view(v, [&](auto* p) { return f.process(p, v.rows, v.row_stride); });
             });
           },
           py::arg("points"),
           "Process one (N,3) float32/float64 frame in world coordinates. Rows with a NaN/Inf "
           "or a |coordinate| > params.max_abs_coordinate_m are dropped and counted "
           "(num_invalid, num_out_of_range).")
      .def_property_readonly("persistence", [](const GFilter& g) {
             // A view into this filter: const access in C++, serialised by the same mutex.
             return g.view(const_cast<PlanePersistence&>(g.obj->persistence()));
           }, "the plane persistence (a view sharing this filter's lifetime and mutex)")
      .def_property_readonly("params", [](const GFilter& g) {
             return locked(g, [](SceneFilter& f) { return SceneFilterParams(f.params()); });
           }, "a copy of the parameters (validated at construction)")
      .def_property_readonly("frame_index", [](const GFilter& g) {
             return locked(g, [](SceneFilter& f) { return f.frame_index(); });
           })
      .def("reset", [](const GFilter& g) { locked(g, [](SceneFilter& f) { f.reset(); }); });
}

}  // namespace grasp_bind
