// pybind11 module grasp_pipeline._core — entry point; the bindings of each part live in
// their own bind_*.cpp file. Input validation happens at this edge (array_input.hpp):
// wrong shapes/dtypes/values raise TypeError/ValueError naming the argument; C++
// std::invalid_argument becomes ValueError; nothing a caller passes may crash Python.
#include <pybind11/pybind11.h>

namespace py = pybind11;

namespace grasp_bind {
void bind_types(py::module_& m);
void bind_scene_filter(py::module_& m);
void bind_estimate(py::module_& m);
void bind_tracker(py::module_& m);
void bind_perception(py::module_& m);
void bind_collision(py::module_& m);
void bind_ik(py::module_& m);
void bind_scene_volume(py::module_& m);
void bind_depth_image(py::module_& m);
void bind_cloud_passes(py::module_& m);
void bind_distance_transform(py::module_& m);
void bind_pad_contacts(py::module_& m);
void bind_tray_spots(py::module_& m);
}  // namespace grasp_bind

PYBIND11_MODULE(_core, m) {
  m.doc() = "grasp_pipeline perception core (C++17, Eigen, PCL): scene filter, object "
            "estimates, grasp pose math, tracker, the per-frame Perception entry point, the planning state checker, the arm IK refinement, the scene volume and the simulated depth image's per-pixel passes and the passes over whole clouds (voxel thinning, tray cells, thin products), the occupancy grid's distance transform and the grasp sampler's contact passes";
  grasp_bind::bind_types(m);
  grasp_bind::bind_scene_filter(m);
  grasp_bind::bind_estimate(m);
  grasp_bind::bind_tracker(m);
  grasp_bind::bind_perception(m);
  grasp_bind::bind_collision(m);
  grasp_bind::bind_ik(m);
  grasp_bind::bind_scene_volume(m);
  grasp_bind::bind_depth_image(m);
  grasp_bind::bind_cloud_passes(m);
  grasp_bind::bind_distance_transform(m);
  grasp_bind::bind_pad_contacts(m);
  grasp_bind::bind_tray_spots(m);
}
