// Bindings of method.md §4 (tracker) and the per-frame Perception entry point.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>

#include "array_input.hpp"
#include "guarded.hpp"
#include "grasp_core/perception.hpp"
#include "grasp_core/tracker.hpp"

namespace py = pybind11;
using namespace grasp_core;

namespace grasp_bind {

namespace {
double finite_time(double t, const char* name) {
  if (!std::isfinite(t)) throw py::value_error(std::string(name) + ": must be finite");
  return t;
}
}  // namespace

void bind_tracker(py::module_& m) {
  py::class_<Track>(m, "Track", "One tracked object (smoothed estimate, best quality seen)")
      .def_readonly("tid", &Track::tid)
      .def_readonly("quality", &Track::quality)
      .def_readonly("last_seen_s", &Track::last_seen_s)
      .def_readonly("smoothed", &Track::smoothed)
      .def_property_readonly("window_size", &Track::window_size);

  using GTracker = Guarded<Tracker>;
  py::class_<GTracker>(m, "Tracker",
                       "method.md §4 tracker. Thread-safe: calls from several threads are serialised by "
                       "a mutex (the GIL is released while waiting); a view (Perception.tracker) "
                       "shares its owner's mutex.")
      .def(py::init([](const ObbParams& p) { p.validate(); return GTracker::make(p); }), py::arg("params"))
      .def_static("gate_for", [](const std::vector<Vec3>& centres, double frac) {
          if (!(frac > 0 && std::isfinite(frac))) throw py::value_error("frac: expected > 0");
          for (const Vec3& c : centres)
            if (!c.allFinite()) throw py::value_error("centres: must be finite");
          return Tracker::gate_for(centres, frac);
        }, py::arg("centres"), py::arg("frac"))
      .def("prior_theta", [](const GTracker& g, const py::object& c, std::optional<double> gate) {
          const Vec3 centre = vec3(c, "centre");
          return locked(g, [&](Tracker& t) { return t.prior_theta(centre, gate); });
        }, py::arg("centre"), py::arg("gate") = py::none())
      .def("update", [](const GTracker& g, const std::vector<ObjectEstimate>& ests,
                        const std::vector<ViewQuality>& q, double now_s) {
          if (q.size() != ests.size()) throw py::value_error("q: expected one quality per estimate");
          const double now = finite_time(now_s, "now_s");
          return locked(g, [&](Tracker& t) { return t.update(ests, q, now); });
        }, py::arg("estimates"), py::arg("qualities"), py::arg("now_s"))
      .def("retire", [](const GTracker& g, double now_s) {
          const double now = finite_time(now_s, "now_s");
          locked(g, [&](Tracker& t) { t.retire(now); });
        }, py::arg("now_s"))
      // By value: Python must never hold references into the tracker's vector, which
      // the next update reallocates (that would read freed memory).
      .def_property_readonly("tracks", [](const GTracker& g) {
          return locked(g, [](Tracker& t) { return std::vector<Track>(t.tracks()); });
        }, "a copy of the tracks, sorted by tid")
      .def_property_readonly("last_gate", [](const GTracker& g) {
          return locked(g, [](Tracker& t) { return t.last_gate(); });
        })
      .def("reset", [](const GTracker& g) { locked(g, [](Tracker& t) { t.reset(); }); });

  m.def("estimate_with_priors",
        [](const std::vector<py::object>& clusters, const Plane& plane, const ObbParams& p_in,
           const GTracker& tracker, std::optional<double> band, double bound) {
          const ObbParams p = p_in;  // copied: another thread may assign its fields
          p.validate();
          checked_bound(bound);
          if (band && !std::isfinite(*band)) throw py::value_error("band: must be finite or None");
          std::vector<PointsD> pts;
          for (std::size_t i = 0; i < clusters.size(); ++i) {
            const std::string name = "clusters[" + std::to_string(i) + "]";
            pts.push_back(points_double(clusters[i], name.c_str(), nullptr, false, bound));
          }
          return locked(tracker, [&](Tracker& t) {
            return estimate_with_priors(pts, plane, p, t, band, bound);
          });
        },
        py::arg("clusters"), py::arg("plane"), py::arg("params"), py::arg("tracker"),
        py::arg("band") = py::none(), py::arg("max_abs_coordinate_m") = kDefaultMaxAbsCoordinate_m,
        "method.md §4 two-pass estimation of one frame's clusters (rows with a NaN/Inf or a "
        "|coordinate| > max_abs_coordinate_m are dropped).");
}

void bind_perception(py::module_& m) {
  py::class_<PerceptionFrame>(m, "PerceptionFrame", "Everything perception produced for one frame")
      .def_readonly("filter", &PerceptionFrame::filter)
      .def_readonly("estimate_labels", &PerceptionFrame::estimate_labels)
      .def_readonly("estimates", &PerceptionFrame::estimates)
      .def_readonly("views", &PerceptionFrame::views)
      .def_readonly("tids", &PerceptionFrame::tids)
      .def_readonly("failed_labels", &PerceptionFrame::failed_labels)
      .def_readonly("failures", &PerceptionFrame::failures)
      .def_readonly("time_s", &PerceptionFrame::time_s)
      .def_readonly("camera_position", &PerceptionFrame::camera_position)
      .def_readonly("ms_estimate", &PerceptionFrame::ms_estimate)
      .def_readonly("ms_track", &PerceptionFrame::ms_track)
      .def_readonly("ms_total", &PerceptionFrame::ms_total);

  using GPerception = Guarded<Perception>;
  py::class_<GPerception>(m, "Perception",
                          "Per-frame entry point: scene filter -> two-pass estimates -> view "
                          "quality -> tracker, for one camera session. Thread-safe: calls from "
                          "several threads (also through the scene_filter / tracker views) are "
                          "serialised by one mutex; the GIL is released while waiting and while "
                          "processing, so other Python threads keep running.")
      .def(py::init([](const SceneFilterParams& fp, const ObbParams& op) {
             return GPerception::make(fp, op);
           }), py::arg("filter_params"), py::arg("obb_params"))
      .def("process",
           [](const GPerception& g, const py::object& points, const py::object& camera_position,
              double time_s, int image_width, const py::object& rgb) {
             PointsView v = points_view(points, "points");
             const Vec3 cam = vec3(camera_position, "camera_position");
             if (image_width < 0 || (image_width > 0 && v.rows % static_cast<std::size_t>(image_width) != 0))
               throw py::value_error("image_width: expected 0 (unorganized) or the width of an organized "
                                     "frame whose row count is a multiple of it");
             const py::array colour = rgb_view(rgb, v.rows);
             // (a default py::array is an empty array, not a null handle: test for None)
             const auto* c = rgb.is_none() ? nullptr : static_cast<const std::uint8_t*>(colour.data());
             return locked(g, [&](Perception& self) {
               if (v.is_float)
                 return self.process(static_cast<const float*>(v.data), v.rows, v.row_stride, cam,
                                     time_s, image_width, c);
               return self.process(static_cast<const double*>(v.data), v.rows, v.row_stride, cam,
                                   time_s, image_width, c);
             });
           },
           py::arg("points"), py::arg("camera_position"), py::arg("time_s"),
           py::arg("image_width") = 0, py::arg("rgb") = py::none(),
           "One (N,3) float32/float64 frame in world coordinates with the camera position at "
           "capture and the capture time [s]. image_width > 0: the frame is organized (row "
           "v*W + u is pixel (u, v)) and its object candidates are segmented over the image; "
           "rgb: None or an (H, W, 3) / (N, 3) uint8 colour image aligned with the rows (read in "
           "place when C-contiguous).")
      // Views into this object: they keep it alive and share its mutex. (Perception exposes
      // them const; the binding keeps the old, mutable Python API, serialised.)
      .def_property_readonly("scene_filter", [](const GPerception& g) {
             return g.view(const_cast<SceneFilter&>(g.obj->scene_filter()));
           }, "the scene filter (a view sharing this object's lifetime and mutex)")
      .def_property_readonly("tracker", [](const GPerception& g) {
             return g.view(const_cast<Tracker&>(g.obj->tracker()));
           }, "the tracker (a view sharing this object's lifetime and mutex)")
      .def("retire", [](const GPerception& g, double now_s) {
             const double now = finite_time(now_s, "now_s");
             locked(g, [&](Perception& p) { p.retire(now); });
           }, py::arg("now_s"))
      .def("reset", [](const GPerception& g) { locked(g, [](Perception& p) { p.reset(); }); });
}

}  // namespace grasp_bind
