# Type stubs of the compiled extension grasp_pipeline._core: drafted with pybind11-stubgen,
# then tidied by hand (numpy types, aliases below). tests/python/core/test_core_stubs.py
# fails when the module gains a public name the stubs do not declare.
"""
grasp_pipeline perception core (C++17, Eigen, PCL): scene filter, object estimates, grasp pose math, tracker, the per-frame Perception entry point, the planning state checker, the arm IK refinement and the scene volume
"""
from __future__ import annotations
from collections.abc import Sequence
import numpy
import numpy.typing
import typing

# Type aliases (stub-only). Eigen vectors/matrices come back as float64 numpy arrays of
# shape (3,), (3, 3) or (4, 4); arguments accept anything numpy can convert.
Vec3: typing.TypeAlias = numpy.typing.NDArray[numpy.float64]
Mat3: typing.TypeAlias = numpy.typing.NDArray[numpy.float64]
Mat4: typing.TypeAlias = numpy.typing.NDArray[numpy.float64]
Vec3Like: typing.TypeAlias = numpy.typing.ArrayLike
Mat3Like: typing.TypeAlias = numpy.typing.ArrayLike
#: An (N, 3) float32 or float64 array of points in `world`. Rows with a NaN/Inf or a
#: |coordinate| > max_abs_coordinate_m (default 1000 m) are dropped and counted wherever
#: points are taken (labelled LABEL_INVALID where labels are returned).
Points: typing.TypeAlias = numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64]
#
# Threads: the stateful classes (Perception, SceneFilter, PlanePersistence, Tracker, SceneVolume) are
# thread-safe by serialisation: each instance has a mutex (views such as
# Perception.scene_filter / .tracker and SceneFilter.persistence share their owner's); the
# GIL is released while a call waits for it and while a frame is processed. Parameter
# objects are copied before the GIL is released.
#
# Parameter setters (SceneFilterParams / ObbParams) raise TypeError naming the field for a
# wrong type and ValueError for an integer beyond the C++ type; ranges: validate().
class ViewQuality:
    """
    View quality of an observation (NADIR > OBLIQUE)
    
    Members:
    
      OBLIQUE
    
      NADIR
    """
    NADIR: typing.ClassVar[ViewQuality]
    OBLIQUE: typing.ClassVar[ViewQuality]
    __members__: typing.ClassVar[dict[str, ViewQuality]]
    @typing.overload
    def __eq__(self, other: ViewQuality) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    def __init__(self, value: int) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: ViewQuality) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: int) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class Plane:
    """
    A plane n.p + c = 0 with |n| = 1 and n_z > 0 (world frame)
    """
    def __init__(self, n: Vec3Like, c: float) -> None:
        """
        Normalises n and orients it so n_z > 0 (c scaled and flipped accordingly).
        """
    def __repr__(self) -> str:
        ...
    def foot(self) -> Vec3:
        """
        -c n: foot of the origin on the plane
        """
    def rotation(self) -> Mat3:
        """
        rotation taking +z to n (det +1)
        """
    def signed_distance(self, p: Vec3Like) -> float:
        """
        n.p + c (positive above) [m]
        """
    def tilt_deg(self) -> float:
        """
        angle between n and +z [deg]
        """
    @property
    def c(self) -> float:
        ...
    @property
    def height_m(self) -> float:
        """
        -c / n_z: where it meets the z axis [m]
        """
    @property
    def n(self) -> Vec3:
        ...
class Pose:
    """
    A rigid pose: x_world = R x_local + t
    """
    @staticmethod
    def from_matrix(T: numpy.typing.ArrayLike) -> Pose:
        ...
    def __init__(self, R: Mat3Like, t: Vec3Like) -> None:
        ...
    def matrix(self) -> Mat4:
        """
        4x4 homogeneous matrix
        """
    @property
    def R(self) -> Mat3:
        ...
    @property
    def t(self) -> Vec3:
        ...
class SceneFilterParams:
    """
    method.md §1.6 scene filter parameters
    """
    plane_lock: bool
    #: organized segmentation and the range-dependent minimum object height
    segment_organized: bool
    segment_smooth_radius_px: int
    segment_max_step_m: float
    segment_max_hue_diff_deg: float
    segment_min_saturation: float
    segment_min_brightness: float
    segment_absorb_max_points: int
    segment_nest_fraction: float
    segment_nest_min_slope_deg: float
    segment_nest_max_slope_deg: float
    segment_nest_rings_px: int
    depth_noise_sigma_m: float
    depth_noise_ref_range_m: float
    depth_noise_exponent: float
    object_min_height_sigmas: float
    def __init__(self) -> None:
        ...
    @property
    def max_abs_coordinate_m(self) -> float:
        """
        (ours) sane coordinate bound [m], in (0, 1e9]: rows with any |coordinate| above it are dropped and counted like NaN rows
        """
    @max_abs_coordinate_m.setter
    def max_abs_coordinate_m(self, arg0: float) -> None:
        ...
    def validate(self) -> None:
        """
        Raise ValueError naming the first invalid parameter.
        """
    @property
    def band(self) -> float:
        ...
    @band.setter
    def band(self, arg0: float) -> None:
        ...
    @property
    def cluster_eps(self) -> float:
        ...
    @cluster_eps.setter
    def cluster_eps(self, arg0: float) -> None:
        ...
    @property
    def cluster_max_extent(self) -> float:
        ...
    @cluster_max_extent.setter
    def cluster_max_extent(self, arg0: float) -> None:
        ...
    @property
    def cluster_min_extent(self) -> float:
        ...
    @cluster_min_extent.setter
    def cluster_min_extent(self, arg0: float) -> None:
        ...
    @property
    def cluster_min_points(self) -> int:
        ...
    @cluster_min_points.setter
    def cluster_min_points(self, arg0: int) -> None:
        ...
    @property
    def cluster_voxel_m(self) -> float:
        ...
    @cluster_voxel_m.setter
    def cluster_voxel_m(self, arg0: float) -> None:
        ...
    @property
    def plane_dist_thresh(self) -> float:
        ...
    @plane_dist_thresh.setter
    def plane_dist_thresh(self, arg0: float) -> None:
        ...
    @property
    def plane_dominance(self) -> float:
        ...
    @plane_dominance.setter
    def plane_dominance(self, arg0: float) -> None:
        ...
    @property
    def plane_fit_max_points(self) -> int:
        ...
    @plane_fit_max_points.setter
    def plane_fit_max_points(self, arg0: int) -> None:
        ...
    @property
    def plane_init_frames(self) -> int:
        ...
    @plane_init_frames.setter
    def plane_init_frames(self, arg0: int) -> None:
        ...
    @property
    def plane_lock_after(self) -> int:
        ...
    @plane_lock_after.setter
    def plane_lock_after(self, arg0: int) -> None:
        ...
    @property
    def plane_max_count(self) -> int:
        ...
    @plane_max_count.setter
    def plane_max_count(self, arg0: int) -> None:
        ...
    @property
    def plane_max_tilt_deg(self) -> float:
        ...
    @plane_max_tilt_deg.setter
    def plane_max_tilt_deg(self, arg0: float) -> None:
        ...
    @property
    def plane_min_inlier_ratio(self) -> float:
        ...
    @plane_min_inlier_ratio.setter
    def plane_min_inlier_ratio(self, arg0: float) -> None:
        ...
    @property
    def plane_ransac_iters(self) -> int:
        ...
    @plane_ransac_iters.setter
    def plane_ransac_iters(self, arg0: int) -> None:
        ...
    @property
    def plane_update_tol_deg(self) -> float:
        ...
    @plane_update_tol_deg.setter
    def plane_update_tol_deg(self, arg0: float) -> None:
        ...
    @property
    def plane_update_tol_m(self) -> float:
        ...
    @plane_update_tol_m.setter
    def plane_update_tol_m(self, arg0: float) -> None:
        ...
    @property
    def seed(self) -> int:
        ...
    @seed.setter
    def seed(self, arg0: int) -> None:
        ...
class ObbParams:
    """
    method.md §2.7 object estimate / guard / tracker parameters
    """
    def __init__(self) -> None:
        ...
    def validate(self) -> None:
        """
        Raise ValueError naming the first invalid parameter.
        """
    @property
    def assoc_gate_frac(self) -> float:
        ...
    @assoc_gate_frac.setter
    def assoc_gate_frac(self, arg0: float) -> None:
        ...
    @property
    def depth_noise_sigma(self) -> float:
        ...
    @depth_noise_sigma.setter
    def depth_noise_sigma(self, arg0: float) -> None:
        ...
    @property
    def gripper_open(self) -> float:
        ...
    @gripper_open.setter
    def gripper_open(self, arg0: float) -> None:
        ...
    @property
    def isotropy_ratio_max(self) -> float:
        ...
    @isotropy_ratio_max.setter
    def isotropy_ratio_max(self, arg0: float) -> None:
        ...
    @property
    def max_age_s(self) -> float:
        ...
    @max_age_s.setter
    def max_age_s(self, arg0: float) -> None:
        ...
    @property
    def min_graspable_width(self) -> float:
        ...
    @min_graspable_width.setter
    def min_graspable_width(self, arg0: float) -> None:
        ...
    @property
    def min_height(self) -> float:
        ...
    @min_height.setter
    def min_height(self, arg0: float) -> None:
        ...
    @property
    def n_theta(self) -> int:
        ...
    @n_theta.setter
    def n_theta(self, arg0: int) -> None:
        ...
    @property
    def nadir_angle_max_deg(self) -> float:
        ...
    @nadir_angle_max_deg.setter
    def nadir_angle_max_deg(self, arg0: float) -> None:
        ...
    @property
    def nadir_min_distance_m(self) -> float:
        ...
    @nadir_min_distance_m.setter
    def nadir_min_distance_m(self, arg0: float) -> None:
        ...
    @property
    def nadir_hold_s(self) -> float:
        ...
    @nadir_hold_s.setter
    def nadir_hold_s(self, arg0: float) -> None:
        ...
    @property
    def resting_margin(self) -> float:
        ...
    @resting_margin.setter
    def resting_margin(self, arg0: float) -> None:
        ...
    @property
    def side_seen_sigmas(self) -> float:
        ...
    @side_seen_sigmas.setter
    def side_seen_sigmas(self, arg0: float) -> None:
        ...
    @property
    def top_slice_iters(self) -> int:
        ...
    @top_slice_iters.setter
    def top_slice_iters(self, arg0: int) -> None:
        ...
    @property
    def top_slice_sigmas(self) -> float:
        ...
    @top_slice_sigmas.setter
    def top_slice_sigmas(self, arg0: float) -> None:
        ...
    @property
    def width_tol_m(self) -> float:
        ...
    @width_tol_m.setter
    def width_tol_m(self, arg0: float) -> None:
        ...
    @property
    def window(self) -> int:
        ...
    @window.setter
    def window(self, arg0: int) -> None:
        ...
class PlaneFit:
    """
    Result of one RANSAC plane search (method.md §1.1)
    """
    @property
    def inliers(self) -> int:
        ...
    @property
    def iterations(self) -> int:
        ...
    @property
    def plane(self) -> Plane:
        ...
    @property
    def ransac_plane(self) -> Plane:
        ...
    @property
    def refined(self) -> bool:
        ...
class PlaneCandidate:
    """
    One plane of the sequential extraction
    """
    def __repr__(self) -> str:
        ...
    @property
    def count_whole(self) -> int:
        ...
    @property
    def plane(self) -> Plane:
        ...
    @property
    def refined(self) -> bool:
        ...
    @property
    def removed(self) -> int:
        ...
    @property
    def subsample_inliers(self) -> int:
        ...
    @property
    def subsample_size(self) -> int:
        ...
class ClusterInfo:
    """
    One connected component with >= min_points points
    """
    #: the range-dependent minimum height (with the camera position)
    height_m: float
    range_m: float
    min_height_m: float
    too_low: bool
    @property
    def accepted(self) -> bool:
        ...
    @property
    def extent_m(self) -> float:
        ...
    @property
    def label(self) -> int:
        ...
    @property
    def max(self) -> Vec3:
        ...
    @property
    def min(self) -> Vec3:
        ...
    @property
    def num_points(self) -> int:
        ...
class ClusterResult:
    """
    Euclidean clustering result
    """
    @property
    def clusters(self) -> list[ClusterInfo]:
        ...
    @property
    def labels(self) -> numpy.typing.NDArray[numpy.int32]:
        ...
    @property
    def num_accepted(self) -> int:
        ...
    @property
    def num_components(self) -> int:
        ...
    @property
    def num_invalid(self) -> int:
        """
        rows labelled LABEL_INVALID: NaN/Inf or beyond max_abs_coordinate_m
        """
    @property
    def num_out_of_range(self) -> int:
        """
        of num_invalid: finite rows with a |coordinate| > max_abs_coordinate_m
        """
class EventLevel:
    """
    Members:
    
      DEBUG
    
      INFO
    
      WARNING
    
      ERROR
    """
    DEBUG: typing.ClassVar[EventLevel]
    ERROR: typing.ClassVar[EventLevel]
    INFO: typing.ClassVar[EventLevel]
    WARNING: typing.ClassVar[EventLevel]
    __members__: typing.ClassVar[dict[str, EventLevel]]
    @typing.overload
    def __eq__(self, other: EventLevel) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    def __init__(self, value: int) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: EventLevel) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: int) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class FrameEvent:
    """
    A log line from the core (Python logs it)
    """
    def __repr__(self) -> str:
        ...
    @property
    def level(self) -> EventLevel:
        ...
    @property
    def message(self) -> str:
        ...
class PlaneDecision:
    """
    Members:
    
      NO_PLANE
    
      FALLBACK
    
      LOCKED
    
      FOLLOWED
    
      RESTARTED
    
      HARDENED
    
      REFUSED
    
      KEPT_NO_FIT
    
      UNLOCKED_FIT
    """
    FALLBACK: typing.ClassVar[PlaneDecision]
    FOLLOWED: typing.ClassVar[PlaneDecision]
    HARDENED: typing.ClassVar[PlaneDecision]
    KEPT_NO_FIT: typing.ClassVar[PlaneDecision]
    LOCKED: typing.ClassVar[PlaneDecision]
    NO_PLANE: typing.ClassVar[PlaneDecision]
    REFUSED: typing.ClassVar[PlaneDecision]
    RESTARTED: typing.ClassVar[PlaneDecision]
    UNLOCKED_FIT: typing.ClassVar[PlaneDecision]
    __members__: typing.ClassVar[dict[str, PlaneDecision]]
    @typing.overload
    def __eq__(self, other: PlaneDecision) -> bool:
        ...
    @typing.overload
    def __eq__(self, other: typing.Any) -> bool:
        ...
    def __getstate__(self) -> int:
        ...
    def __hash__(self) -> int:
        ...
    def __index__(self) -> int:
        ...
    def __init__(self, value: int) -> None:
        ...
    def __int__(self) -> int:
        ...
    @typing.overload
    def __ne__(self, other: PlaneDecision) -> bool:
        ...
    @typing.overload
    def __ne__(self, other: typing.Any) -> bool:
        ...
    def __repr__(self) -> str:
        ...
    def __setstate__(self, state: int) -> None:
        ...
    def __str__(self) -> str:
        ...
    @property
    def name(self) -> str:
        ...
    @property
    def value(self) -> int:
        ...
class PersistenceState:
    """
    method.md §1.5 lock state
    """
    @property
    def anchor(self) -> Plane | None:
        ...
    @property
    def fallback_active(self) -> bool:
        ...
    @property
    def fallback_reported(self) -> bool:
        ...
    @property
    def frames_without_lock(self) -> int:
        ...
    @property
    def hardened(self) -> bool:
        ...
    @property
    def hits(self) -> int:
        ...
    @property
    def lock(self) -> Plane | None:
        ...
class PersistenceUpdate:
    """
    Result of feeding one frame's fit to PlanePersistence.update (method.md §1.5)
    """
    @property
    def decision(self) -> PlaneDecision:
        ...
    @property
    def environment_emitted(self) -> bool:
        ...
    @property
    def events(self) -> list[FrameEvent]:
        ...
    @property
    def fallback(self) -> bool:
        ...
    @property
    def table(self) -> Plane | None:
        ...
class PlanePersistence:
    """
    method.md §1.5 plane persistence state machine. Thread-safe: calls from several threads are serialised by a mutex (the GIL is released while waiting); a view (SceneFilter.persistence) shares its owner's mutex.
    """
    def __init__(self, params: SceneFilterParams) -> None:
        ...
    def reset(self) -> None:
        ...
    def update(self, fit: Plane | None) -> PersistenceUpdate:
        """
        Feed this frame's fit (None: no plane this frame).
        """
    @property
    def hardened(self) -> bool:
        ...
    @property
    def locked(self) -> bool:
        ...
    @property
    def state(self) -> PersistenceState:
        ...
class SceneFilterResult:
    """
    Everything the scene filter computed for one frame
    """
    #: segmented over the image; clusters refused by the minimum height
    organized: bool
    num_too_low: int
    @property
    def band(self) -> float:
        ...
    @property
    def cluster_ids(self) -> list[int]:
        ...
    @property
    def clusters(self) -> list[ClusterInfo]:
        ...
    @property
    def decision(self) -> PlaneDecision:
        ...
    @property
    def environment_emitted(self) -> bool:
        ...
    @property
    def events(self) -> list[FrameEvent]:
        ...
    @property
    def fallback(self) -> bool:
        ...
    @property
    def fit(self) -> Plane | None:
        ...
    @property
    def labels(self) -> numpy.typing.NDArray[numpy.int32]:
        """
        one int per input row: LABEL_INVALID (-2), LABEL_ENVIRONMENT (-1) or an object id >= 0
        """
    @property
    def ms_cluster(self) -> float:
        ...
    @property
    def ms_pack(self) -> float:
        """
        validity check, packing and labels of every row [ms]
        """
    @property
    def ms_plane(self) -> float:
        ...
    @property
    def ms_total(self) -> float:
        ...
    @property
    def num_candidates(self) -> int:
        ...
    @property
    def max_abs_coordinate_m(self) -> float:
        """
        the coordinate bound applied this frame [m]
        """
    @property
    def num_invalid(self) -> int:
        """
        rows dropped (LABEL_INVALID): NaN/Inf, or a |coordinate| > max_abs_coordinate_m
        """
    @property
    def num_out_of_range(self) -> int:
        """
        of num_invalid: finite rows with a |coordinate| > max_abs_coordinate_m
        """
    @property
    def num_valid(self) -> int:
        """
        rows used: finite and within max_abs_coordinate_m
        """
    @property
    def persistence(self) -> PersistenceState:
        ...
    @property
    def planes(self) -> list[PlaneCandidate]:
        ...
    @property
    def table(self) -> Plane | None:
        ...
    @property
    def table_index(self) -> int:
        ...
class SceneFilter:
    """
    The per-frame scene filter (method.md §1); owns the plane lock. Thread-safe: calls from several threads are serialised by a mutex (the GIL is released while waiting and while processing); a view (Perception.scene_filter) shares its owner's mutex.
    """
    def __init__(self, params: SceneFilterParams) -> None:
        ...
    def process(self, points: Points) -> SceneFilterResult:
        """
        Process one (N,3) float32/float64 frame in world coordinates. Rows with a NaN/Inf or a |coordinate| > params.max_abs_coordinate_m are dropped and counted (num_invalid, num_out_of_range).
        """
    def reset(self) -> None:
        ...
    @property
    def frame_index(self) -> int:
        ...
    @property
    def params(self) -> SceneFilterParams:
        ...
    @property
    def persistence(self) -> PlanePersistence:
        ...
class PcaBox:
    """
    PCA oriented box (method.md §2.5; diagnostic only)
    """
    @property
    def R(self) -> Mat3:
        ...
    @property
    def center(self) -> Vec3:
        ...
    @property
    def eigenvalues(self) -> Vec3:
        ...
    @property
    def extents(self) -> Vec3:
        ...
class ObjectEstimate:
    """
    Grasp-ready box of one object (method.md §2)
    """
    def __repr__(self) -> str:
        ...
    @property
    def R_box(self) -> Mat3:
        ...
    @property
    def anisotropy(self) -> float:
        ...
    @property
    def center(self) -> Vec3:
        ...
    @property
    def extents(self) -> Vec3:
        ...
    @property
    def grasp_ok(self) -> bool:
        ...
    @property
    def height_m(self) -> float:
        ...
    @property
    def height_ok(self) -> bool:
        ...
    @property
    def lowest_m(self) -> float:
        ...
    @property
    def notes(self) -> list[str]:
        ...
    @property
    def num_points(self) -> int:
        ...
    @property
    def pca(self) -> PcaBox:
        ...
    @property
    def pca_tilt_deg(self) -> float:
        ...
    @property
    def perp_width_m(self) -> float:
        ...
    @property
    def resting(self) -> bool:
        ...
    @property
    def resting_note(self) -> str:
        ...
    @property
    def theta_deg(self) -> float:
        ...
    @property
    def theta_rad(self) -> float:
        ...
    @property
    def undetermined_notes(self) -> list[str]:
        ...
    @property
    def width_m(self) -> float:
        ...
    @property
    def width_ok(self) -> bool:
        ...
    @property
    def yaw_defined(self) -> bool:
        ...
class EstimateResult:
    """
    An estimate, or why there is none
    """
    @property
    def estimate(self) -> ObjectEstimate | None:
        ...
    @property
    def failure(self) -> str:
        ...
class DirectionRun:
    """
    A run of candidate closing directions (method.md §2.3)
    """
    @property
    def first(self) -> int:
        ...
    @property
    def indices(self) -> list[int]:
        ...
    @property
    def last(self) -> int:
        ...
    @property
    def theta_rad(self) -> float:
        ...
    @property
    def width_m(self) -> float:
        ...
class DirectionChoice:
    """
    The chosen closing direction (method.md §2.3) and every run considered; chosen indexes runs (-1 if none)
    """
    @property
    def chosen(self) -> int:
        ...
    @property
    def runs(self) -> list[DirectionRun]:
        ...
    @property
    def theta_rad(self) -> float:
        ...
    @property
    def width_m(self) -> float:
        ...
class BestGrasp:
    """
    Grasp pose: position = contact point, R[:,0] = approach into the object, R[:,2] = closing axis; width [m]; score always 0 (geometric method)
    """
    def __init__(self, R: Mat3Like, position: Vec3Like, width_m: float) -> None:
        ...
    @property
    def R(self) -> Mat3:
        ...
    @property
    def position(self) -> Vec3:
        ...
    @property
    def score(self) -> float:
        ...
    @property
    def width_m(self) -> float:
        ...
class ViewAssessment:
    """
    View quality of one observation (method.md §3); angle_deg = angle(object - camera, -n), NaN when coincident
    """
    @property
    def angle_deg(self) -> float:
        ...
    @property
    def quality(self) -> ViewQuality:
        ...
class Track:
    """
    One tracked object (smoothed estimate, best quality seen)
    """
    @property
    def last_seen_s(self) -> float:
        ...
    @property
    def quality(self) -> ViewQuality:
        ...
    @property
    def smoothed(self) -> ObjectEstimate:
        ...
    @property
    def tid(self) -> int:
        ...
    @property
    def window_size(self) -> int:
        ...
class RobotCollisionModel:
    """
    The robot's kinematic chain (fixed transforms + 7 hinges), collision spheres and self-collision pairs, exported once from the MuJoCo model (motion/core_checker.py).
    """
    def __init__(self, arrays: dict[str, typing.Any]) -> None:
        ...
    def body_poses(self, q: numpy.typing.ArrayLike) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
        """
        World rotations (B, 3, 3) and positions (B, 3) of every body for arm state q (7,).
        """
    @property
    def num_bodies(self) -> int:
        ...
    @property
    def num_spheres(self) -> int:
        ...
class ArmIK:
    """
    Gauss-Newton refinement of arm joints to a flange pose on the exported chain (motion/ik.py's refinement loop in C++): flange_pose, refine_batch, refine_line.
    """
    def __init__(self, chain: dict[str, typing.Any], flange_body: int, q_min_rad: numpy.typing.ArrayLike, q_max_rad: numpy.typing.ArrayLike, iterations: int, tol_m: float, tol_rad: float, accept_m: float, accept_rad: float, limit_eps_rad: float) -> None:
        ...
    def flange_pose(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        Flange pose (4, 4) for arm state q (7,).
        """
    def refine_batch(self, T: numpy.typing.ArrayLike, Q: numpy.typing.ArrayLike) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.bool_]]:
        """
        Refine every seed row of Q (N, 7) towards the flange pose T (4, 4): (refined (N, 7), kept (N,) bool: inside the limits and verified; kept rows are clipped to the limits).
        """
    def refine_line(self, Ts: numpy.typing.ArrayLike, q0: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        Refine the poses Ts (n, 4, 4) in order, each seeded by the previous solution (the first by q0): the solved prefix (k, 7), k < n when pose k could not be refined and verified.
        """
class CollisionScene:
    """
    One perceived planning scene (immutable): distance field of the occupancy map, object boxes, floor, margins, the optional target-cleared region and the optional object points (neighbours modelled by their points; same dict as cleared, inflation 0).
    """
    def __init__(self, collision_margin_m: float, floor_z_m: float, has_env: bool = False, field_m: numpy.typing.ArrayLike | None = None, origin_m: numpy.typing.ArrayLike | None = None, voxel_size_m: float = 1.0, inflation_m: float = 0.0, box_centers_m: numpy.typing.ArrayLike | None = None, box_rotations: numpy.typing.ArrayLike | None = None, box_extents_m: numpy.typing.ArrayLike | None = None, cleared: dict[str, typing.Any] | None = None, points: dict[str, typing.Any] | None = None) -> None:
        ...
    @property
    def num_boxes(self) -> int:
        ...
class StateChecker:
    """
    Validity of arm states (joint limits, self-collision, map, boxes, floor). Thread-safe; the GIL is released while checking.
    """
    allow_target_contact: bool
    def __init__(self, robot: RobotCollisionModel, scene: CollisionScene) -> None:
        ...
    def check(self, q: numpy.typing.ArrayLike) -> bool:
        """
        True if the state q (7,) rad is valid.
        """
    def check_batch(self, Q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.bool_]:
        """
        (N,) bool: validity of each row of Q (N, 7) rad.
        """
    def check_ompl_motion(self, s1: typing.Any, s2: typing.Any, max_step_rad: float) -> bool:
        """
        OMPL motion callback: every state after s1 up to s2 (the start is valid by contract).
        """
    def check_ompl_state(self, state: typing.Any) -> bool:
        """
        OMPL state validity callback: a 7-D RealVectorState.
        """
    def check_segment(self, qa: numpy.typing.ArrayLike, qb: numpy.typing.ArrayLike, max_step_rad: float, include_start: bool = False) -> bool:
        """
        True if every state of the straight joint line (step <= max_step_rad per joint) is valid.
        """
    def first_invalid_on_path(self, waypoints: numpy.typing.ArrayLike, max_step_rad: float) -> tuple[int, int]:
        """
        Dense check of the polyline (M, 7) after its first state: (segment, index) of the first invalid state (index i-1 of the state qa + (qb - qa) i / n), or (-1, -1) when all are valid.
        """
    def set_scene(self, scene: CollisionScene) -> None:
        ...
    def sphere_centres(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
        """
        World sphere centres (S, 3) for q (7,).
        """
    @property
    def checked_states(self) -> int:
        ...
class Tracker:
    """
    method.md §4 tracker. Thread-safe: calls from several threads are serialised by a mutex (the GIL is released while waiting); a view (Perception.tracker) shares its owner's mutex.
    """
    @staticmethod
    def gate_for(centres: Sequence[Vec3Like], frac: float) -> float | None:
        ...
    def __init__(self, params: ObbParams) -> None:
        ...
    def prior_theta(self, centre: Vec3Like, gate: float | None = None) -> float | None:
        ...
    def reset(self) -> None:
        ...
    def retire(self, now_s: float) -> None:
        ...
    def update(self, estimates: Sequence[ObjectEstimate], qualities: Sequence[ViewQuality], now_s: float) -> list[int]:
        ...
    @property
    def last_gate(self) -> float | None:
        ...
    @property
    def tracks(self) -> list[Track]:
        ...
class PerceptionFrame:
    """
    Everything perception produced for one frame
    """
    @property
    def camera_position(self) -> Vec3:
        ...
    @property
    def estimate_labels(self) -> list[int]:
        ...
    @property
    def estimates(self) -> list[ObjectEstimate]:
        ...
    @property
    def failed_labels(self) -> list[int]:
        ...
    @property
    def failures(self) -> list[str]:
        ...
    @property
    def filter(self) -> SceneFilterResult:
        ...
    @property
    def ms_estimate(self) -> float:
        ...
    @property
    def ms_total(self) -> float:
        ...
    @property
    def ms_track(self) -> float:
        ...
    @property
    def tids(self) -> list[int]:
        ...
    @property
    def time_s(self) -> float:
        ...
    @property
    def views(self) -> list[ViewAssessment]:
        ...
class Perception:
    """
    Per-frame entry point: scene filter -> two-pass estimates -> view quality -> tracker, for one camera session. Thread-safe: calls from several threads (also through the scene_filter / tracker views) are serialised by one mutex; the GIL is released while waiting and while processing, so other Python threads keep running.
    """
    def __init__(self, filter_params: SceneFilterParams, obb_params: ObbParams) -> None:
        ...
    def process(self, points: Points, camera_position: Vec3Like, time_s: float, image_width: int = 0, rgb: numpy.ndarray | None = None) -> PerceptionFrame:
        """
        One (N,3) float32/float64 frame in world coordinates with the camera position at capture and the capture time [s].
        """
    def reset(self) -> None:
        ...
    def retire(self, now_s: float) -> None:
        ...
    @property
    def scene_filter(self) -> SceneFilter:
        """
        the scene filter (a view sharing this object's lifetime and mutex)
        """
    @property
    def tracker(self) -> Tracker:
        """
        the tracker (a view sharing this object's lifetime and mutex)
        """
class SceneVolumeParams:
    """
    Parameters of a SceneVolume (config/volume.yaml); ranges: validate()
    """
    def __init__(self) -> None:
        ...
    def validate(self) -> None:
        """
        raise ValueError naming the first parameter out of range
        """
    @property
    def box_min_m(self) -> Vec3:
        """
        world box, lower corner (x, y, z) [m]
        """
    @box_min_m.setter
    def box_min_m(self, arg1: Vec3Like) -> None:
        ...
    @property
    def box_max_m(self) -> Vec3:
        """
        world box, upper corner [m] (rounded up to whole voxels)
        """
    @box_max_m.setter
    def box_max_m(self, arg1: Vec3Like) -> None:
        ...
    @property
    def voxel_m(self) -> float:
        ...
    @voxel_m.setter
    def voxel_m(self, arg1: float) -> None:
        ...
    @property
    def truncation_m(self) -> float:
        ...
    @truncation_m.setter
    def truncation_m(self, arg1: float) -> None:
        ...
    @property
    def logodds_hit(self) -> float:
        ...
    @logodds_hit.setter
    def logodds_hit(self, arg1: float) -> None:
        ...
    @property
    def logodds_miss(self) -> float:
        ...
    @logodds_miss.setter
    def logodds_miss(self, arg1: float) -> None:
        ...
    @property
    def logodds_min(self) -> float:
        ...
    @logodds_min.setter
    def logodds_min(self, arg1: float) -> None:
        ...
    @property
    def logodds_max(self) -> float:
        ...
    @logodds_max.setter
    def logodds_max(self, arg1: float) -> None:
        ...
class VolumeIntegration:
    """
    What one SceneVolume.integrate() call did
    """
    @property
    def voxels_in_view(self) -> int:
        """
        voxels whose centre projected into the image (up to the far bound)
        """
    @property
    def voxels_free(self) -> int:
        """
        of those: free evidence
        """
    @property
    def voxels_occupied(self) -> int:
        """
        of those: occupied evidence
        """
    @property
    def valid_pixels(self) -> int:
        """
        depth pixels finite, > 0 and <= max_range_m
        """
    @property
    def ms(self) -> float:
        """
        wall time of the call [ms]
        """
class VolumeCounts:
    """
    Voxel states counted over a query box
    """
    @property
    def unknown(self) -> int:
        ...
    @property
    def free(self) -> int:
        ...
    @property
    def occupied(self) -> int:
        ...
    @property
    def outside(self) -> int:
        """
        lattice cells of the query box outside the volume
        """
class SceneVolume:
    """
    Log-odds occupancy over a world box, carved by every depth ray: each place is VOXEL_UNKNOWN (never seen), VOXEL_FREE, VOXEL_OCCUPIED, or VOXEL_OUTSIDE the box. Thread-safe: calls are serialised by a mutex (the GIL is released meanwhile).
    """
    def __init__(self, params: SceneVolumeParams) -> None:
        ...
    def integrate(self, depth: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64], K: Mat3Like, T_world_camera: numpy.typing.ArrayLike, max_range_m: float) -> VolumeIntegration:
        """
        Integrate one depth image (H, W) float32 [m along the optical axis; NaN, <= 0 or > max_range_m: no measurement] taken with intrinsics K (3, 3) from the optical frame T_world_camera (4, 4): voxels in front of the measured surface by more than truncation_m gain free evidence, those within +-truncation_m occupied evidence, those behind nothing.
        """
    def classify(self, points: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.int8]:
        """
        int8 state of each point (N, 3) [m, world]: VOXEL_UNKNOWN, VOXEL_FREE, VOXEL_OCCUPIED; VOXEL_OUTSIDE outside the box and for NaN rows.
        """
    def occupied_centres(self, box_min: Vec3Like, box_max: Vec3Like) -> numpy.typing.NDArray[numpy.float64]:
        """
        (M, 3) centres of the occupied voxels whose centre lies in the box [m].
        """
    def states_in_box(self, box_min: Vec3Like, box_max: Vec3Like) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.int8]]:
        """
        (centres (M, 3), states (M,) int8) of every voxel whose centre lies in the box.
        """
    def count_states(self, box_min: Vec3Like, box_max: Vec3Like) -> VolumeCounts:
        """
        VolumeCounts over the lattice cells whose centre lies in the box.
        """
    def visible(self, points: numpy.typing.ArrayLike, K: Mat3Like, width: int, height: int, T_world_camera: numpy.typing.ArrayLike, min_range_m: float, max_range_m: float) -> numpy.typing.NDArray[numpy.bool_]:
        """
        (N,) bool: would a camera (K, width x height px) at T_world_camera see each point? Its depth within [min_range_m, max_range_m], inside the image, and no OCCUPIED voxel on the line from the camera centre to it (UNKNOWN voxels do not block).
        """
    def reset(self) -> None:
        """
        forget everything: every voxel UNKNOWN
        """
    def reset_box(self, box_min: Vec3Like, box_max: Vec3Like) -> None:
        """
        forget the voxels whose centre lies in the box
        """
    @property
    def params(self) -> SceneVolumeParams:
        """
        a copy of the parameters
        """
    @property
    def shape(self) -> list[int]:
        """
        voxels along x, y, z
        """
    @property
    def box_min_m(self) -> Vec3:
        """
        lower corner of the grid [m]
        """
    @property
    def box_max_m(self) -> Vec3:
        """
        upper corner of the grid [m] (box_min_m + shape * voxel_m)
        """
    @property
    def memory_bytes(self) -> int:
        """
        bytes of the voxel array
        """
    @property
    def frames_integrated(self) -> int:
        """
        integrate() calls since construction or the last reset()
        """
def add_quadratic_depth_noise(z: numpy.typing.NDArray[numpy.float32], noise: numpy.typing.NDArray[numpy.float32], ref_range: float, sigma_at_ref: float) -> None:
    """
    In place on noise (H, W) float32, holding standard normal draws: noise = noise * (((z / ref_range) ** 2) * sigma_at_ref) + z, float32 operations in this order.
    """
def angle_dist_mod_pi(a_rad: float, b_rad: float) -> float:
    ...
def anisotropy_ratio(ext: Sequence[float]) -> float:
    ...
def assess_view(object: Vec3Like, camera_position: Vec3Like, n: Vec3Like, nadir_angle_max_deg: float) -> ViewAssessment:
    ...
def best_grasp_from_estimate(estimate: ObjectEstimate, plane: Plane) -> BestGrasp | None:
    ...
def camera_above_flange_target(object: Vec3Like, plane: Plane, ready_camera_world: Pose, camera_in_flange: Pose) -> Pose:
    """
    Flange pose that puts the camera above the object (method.md §3).
    """
def camera_above_pose(object: Vec3Like, plane: Plane, ready_camera_world: Pose) -> Pose:
    ...
def choose_direction(ext: Sequence[float], width_tol_m: float, theta_prev: float | None = None) -> DirectionChoice:
    ...
def choose_table(planes: Sequence[PlaneCandidate], dominance: float) -> int:
    """
    method.md §1.3: index of the table (dominance, then height), -1 if none.
    """
def circular_median_mod_pi(angles_rad: Sequence[float], reference_rad: float) -> float:
    ...
def depth_to_world_points(depth: numpy.typing.NDArray[numpy.float32], invalid: numpy.typing.NDArray[numpy.bool_], x: numpy.typing.NDArray[numpy.float32], y: numpy.typing.NDArray[numpy.float32], R: numpy.typing.NDArray[numpy.float32], t: numpy.typing.NDArray[numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
    """
    depth = NaN where invalid (in place), then the (H*W, 3) float32 world points ((R[i,0] x + R[i,1] y) + R[i,2]) depth + t[i], row v*W + u for pixel (u, v); R (3, 3) and t (3,) float32: the camera's world pose.
    """
def distance_field(occupied: numpy.typing.NDArray[numpy.bool_], voxel_m: float) -> numpy.typing.NDArray[numpy.float32]:
    """
    (nx, ny, nz) float32: for each voxel of a C-ordered bool grid, the distance [m] to the nearest True voxel, float32(sqrt(k) * voxel_m) of the exact squared distance k in voxels (+inf everywhere when there is none).
    """
def direction_runs(ext: Sequence[float], width_tol_m: float) -> list[DirectionRun]:
    ...
def estimate_object(points: Points, plane: Plane, params: ObbParams, theta_prev: float | None = None, band: float | None = None, max_abs_coordinate_m: float = 1000.0) -> EstimateResult:
    """
    method.md §2: estimate one cluster above the plane (rows with a NaN/Inf or a |coordinate| > max_abs_coordinate_m are dropped). No estimate (failure text) for fewer than 3 points, a failed PCA, or a cluster whose top is below the plane.
    """
def estimate_with_priors(clusters: Sequence[Points], plane: Plane, params: ObbParams, tracker: Tracker, band: float | None = None, max_abs_coordinate_m: float = 1000.0) -> list[EstimateResult]:
    """
    method.md §4 two-pass estimation of one frame's clusters (rows with a NaN/Inf or a |coordinate| > max_abs_coordinate_m are dropped).
    """
def euclidean_clusters(points: Points, eps_m: float, min_points: int, min_extent_m: float, max_extent_m: float, voxel_m: float = 0.0, max_abs_coordinate_m: float = 1000.0) -> ClusterResult:
    """
    method.md §1.4: Euclidean clusters (PCL semantics) with extent filters; labels for every row (LABEL_INVALID for NaN/Inf rows and rows with a |coordinate| > max_abs_coordinate_m).
    """
def extent_along(a: Sequence[float], b: Sequence[float], theta_rad: float) -> float:
    ...
def extract_planes(points: Points, params: SceneFilterParams, seed: int = 0) -> list[PlaneCandidate]:
    """
    method.md §1.2: sequential plane extraction on the rows that are finite and within params.max_abs_coordinate_m; counts are on the whole cloud.
    """
def fill_standard_normal(out: numpy.typing.NDArray[numpy.float32], seed: typing.SupportsInt) -> None:
    """
    In place on out (H, W) float32: standard normal draws of the stream of seed (an unsigned 64-bit integer), row by row; the same seed gives the same draws (the depth camera's noise, one seed per frame).
    """
def first_per_voxel(points: numpy.typing.NDArray[numpy.float64], owner: numpy.typing.NDArray[numpy.int64], voxel_m: float) -> numpy.typing.NDArray[numpy.int64]:
    """
    Positions (int64) of the first point of each distinct (voxel, owner) pair of an (N, 3) float64 cloud of finite points with (N,) int64 owners, in increasing order of the pair's key ((ix * dy + iy) * dz + iz) * n_owner + owner - min(owner), voxel indices counted from the cloud's minimum per axis: np.unique(key, return_index=True)[1].
    """
def fit_plane_ransac(points: Points, params: SceneFilterParams, seed: int = 0) -> PlaneFit | None:
    """
    method.md §1.1: one horizontal-constrained RANSAC plane (PCL sample consensus) with least-squares refinement and the post-refinement tilt re-check, on the rows that are finite and within params.max_abs_coordinate_m. None if no model.
    """
def in_plane_basis(n: Vec3Like) -> tuple[Vec3, Vec3]:
    """
    Deterministic (u, v) with u x v = n.
    """
def mask_invalid_and_grazing(depth: numpy.typing.NDArray[numpy.float32], invalid: numpy.typing.NDArray[numpy.bool_], x: numpy.typing.NDArray[numpy.float32], y: numpy.typing.NDArray[numpy.float32], ray_norm2: numpy.typing.NDArray[numpy.float32], fx: float, fy: float, cos2_max: float) -> None:
    """
    In place, on an (H, W) float32 depth and its (H, W) bool invalid mask: depth = NaN where invalid, then invalid |= grazing (a surface seen at more than the angle whose cos^2 is cos2_max). x (W,), y (H,): (u - cx) / fx and (v - cy) / fy; ray_norm2 (H, W): 1 + x^2 + y^2; all float32.
    """
def median(values: Sequence[float]) -> float:
    """
    Median; an even count gives the mean of the two middle values.
    """
def metric_depth(raw: numpy.typing.NDArray[numpy.float32], c_coef: float, d_coef: float) -> numpy.typing.NDArray[numpy.float32]:
    """
    (H, W) float32 metres along the optical axis from a perspective render's (H, W) float32 depth buffer (rows bottom to top): float(d_coef / (raw + c_coef)) in float64, rows flipped to top to bottom (mujoco.Renderer's linearisation).
    """
def pad_contact_ends(xyz: numpy.typing.NDArray[numpy.float32], column: numpy.typing.NDArray[numpy.int64], x0: numpy.typing.NDArray[numpy.float64], closing: numpy.typing.NDArray[numpy.float32], closing_column: numpy.typing.NDArray[numpy.int64], z_tcp: numpy.typing.NDArray[numpy.float64], y_lo: numpy.typing.NDArray[numpy.float32], y_hi: numpy.typing.NDArray[numpy.float32], y_mid: numpy.typing.NDArray[numpy.float32], inner: numpy.typing.NDArray[numpy.float32], outer: numpy.typing.NDArray[numpy.float32], strip_half_width_m: float, half_length_m: float, contact_depth_m: float, cos_cone: float, finger_half_width_m: float) -> dict:
    """
    {'upper', 'lower': {x_lo, x_hi, normal_sum (float32), count, facing (int64)}, 'blocked_upper', 'blocked_lower'}: per frame the contact patches at the material's ends and the points in each finger's way (grasp_core/pad_contacts.hpp). closing (Q, N) float32: |n.c| of the points' normals per closing axis, closing_column (K,) int64.
    """
def pad_depth_bounds(xyz: numpy.typing.NDArray[numpy.float32], column: numpy.typing.NDArray[numpy.int64], x0: numpy.typing.NDArray[numpy.float64], strip_half_width_m: float, palm_half_width_m: float) -> tuple[numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.float32]]:
    """
    (z_first, z_last, z_palm) float32 (K,): per frame the smallest and largest Z of the points with |X - x0| <= strip_half_width_m (float64) and the smallest Z of those within palm_half_width_m (inf / -inf: none). xyz: (3, C, N) float32, the points' X, Y, Z in each of C columns; column (K,) int64: each frame's column; x0 (K,) float64.
    """
def pad_material(xyz: numpy.typing.NDArray[numpy.float32], column: numpy.typing.NDArray[numpy.int64], x0: numpy.typing.NDArray[numpy.float64], strip_half_width_m: float, z_tcp: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64], half_length_m: float) -> tuple[numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.float32], numpy.typing.NDArray[numpy.int64]]:
    """
    (y_lo, y_hi float32, count int64) (K,): per frame the smallest and largest Y and the count of the points in the pads' strip with |Z - z_tcp| <= half_length_m, computed in z_tcp's type (float32 or float64).
    """
def pca_box(points: Points, max_abs_coordinate_m: float = 1000.0) -> PcaBox | None:
    """
    PCA box of the rows that are finite and within max_abs_coordinate_m, or None (fewer than 3 points, coincident, collinear).
    """
def pca_box_failure(points: Points, max_abs_coordinate_m: float = 1000.0) -> str:
    """
    Why pca_box() gives None ('' when it succeeds).
    """
def pca_tilt_deg(box: PcaBox, n: Vec3Like) -> float:
    """
    angle(PCA minor axis, n) [deg]
    """
def planes_close(a: Plane, b: Plane, tol_deg: float, tol_m: float) -> bool:
    """
    method.md §1.5 closeness: normal angle <= tol_deg and height diff <= tol_m
    """
def points_in_grid_cells(points: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64], center: Sequence[float], axes: numpy.typing.NDArray[numpy.float64], half: Sequence[float], cell_m: float, nu: int, nv: int, lo: Sequence[float], hi: Sequence[float]) -> tuple[numpy.typing.NDArray[numpy.int64], numpy.typing.NDArray[numpy.int64]]:
    """
    (rows, cells): the positions (M,) int64 of the points of an (N, 3) float32/float64 cloud with x/y within [lo, hi] and a finite z whose cell of the rotated grid (floor((d0 axes[0, j] + d1 axes[1, j] + half[j]) / cell_m), d = xy - center) lies in nu x nv, in their order, and those cells (M, 2) int64.
    """
def scan_angle_rad(t: int, n_theta: int) -> float:
    ...
def slice_median_top(d: Sequence[float], sigma_m: float, slice_sigmas: float, iters: int) -> float:
    ...
def squared_distance_transform(occupied: numpy.typing.NDArray[numpy.bool_]) -> numpy.typing.NDArray[numpy.int64]:
    """
    (nx, ny, nz) int64: for each voxel of a C-ordered bool grid, the exact squared Euclidean distance in voxels to the nearest True voxel (-1 everywhere when there is none).
    """
def thin_owned_rows(points: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64], labels: numpy.typing.NDArray[numpy.int32], owner_of_label: Sequence[int], environment_emitted: bool, environment_owner: int, untracked_owner: int, environment_label: int, voxel_m: float) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.int64]]:
    """
    (points (M, 3) float64, owner (M,) int64): the rows of an (N, 3) float32/float64 frame cloud with (N,) int32 scene-filter labels that have an owner — an object group g >= 0 owned by owner_of_label[g] (untracked_owner past its end), the environment label owned by environment_owner when environment_emitted — and finite coordinates, thinned to the first row of each (voxel, owner) pair in first_per_voxel's key order.
    """
def thin_matmul(a: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64], b: numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64]) -> numpy.typing.NDArray[numpy.float32] | numpy.typing.NDArray[numpy.float64]:
    """
    a (M, K) @ b (K, N), both C-ordered float32 or both float64, on the calling thread, each element summed in order k = 0, 1, ... without fused multiply-add: the same values on every machine and thread count.
    """
def top_down_rotation(R_box: Mat3Like, n: Vec3Like) -> Mat3 | None:
    """
    [n, normalize(closing x n), closing] or None
    """
def tray_spot_cells(contents: numpy.typing.NDArray[numpy.float64], heights: numpy.typing.NDArray[numpy.float64], inside: numpy.typing.NDArray[numpy.bool_], rim_m: float, cell_m: float, object_xy: numpy.typing.NDArray[numpy.float64], object_r: numpy.typing.NDArray[numpy.float64], under: numpy.typing.NDArray[numpy.int64], hand_xy: numpy.typing.NDArray[numpy.float64], hand_r: numpy.typing.NDArray[numpy.float64], hand_limit: numpy.typing.NDArray[numpy.float64], spacing_m: float, tolerance_m: float) -> tuple[numpy.typing.NDArray[numpy.bool_], numpy.typing.NDArray[numpy.float64]]:
    """
    (ok (nu, nv) bool, support (nu, nv) float64) of a tray grid (contents, heights: (nu, nv) float64; inside: (nu, nv) bool) for one TCP rotation: where the object (discs object_xy (M, 2), object_r (M,) in the grid's axes, grown by spacing_m; the cells under its points: under (J, 2) int64 offsets) and the hand (discs hand_xy, hand_r, each with the highest content allowed under it, hand_limit) fit with the TCP above a cell, and the height of what the object stands on there.
    """
def voxelize_points(points: numpy.typing.NDArray[numpy.float64], lo: numpy.typing.NDArray[numpy.float64], hi: numpy.typing.NDArray[numpy.float64], voxel_m: float, pad_voxels: int, max_voxels: int) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.int64], numpy.typing.NDArray[numpy.int64], numpy.typing.NDArray[numpy.bool_] | None]:
    """
    (kept (M, 3) float64, first_index (3,) int64, shape (3,) int64, occupied): the finite rows of an (N, 3) float64 cloud with lo <= p <= hi on every axis (input order), the first voxel and the size of the grid of their voxels floor((p - lo) / voxel_m) padded by pad_voxels, and that bool grid with their voxels True; occupied is None when no row is kept or the grid would have more than max_voxels voxels.
    """
def width_scan(a: Sequence[float], b: Sequence[float], n_theta: int) -> list[float]:
    """
    ext(theta_t) for t = 0..n_theta-1 [m]
    """
def wrap_mod_pi(x_rad: float) -> float:
    ...
LABEL_ENVIRONMENT: int = -1
LABEL_INVALID: int = -2
VOXEL_FREE: int = 1
VOXEL_OCCUPIED: int = 2
VOXEL_OUTSIDE: int = 3
VOXEL_UNKNOWN: int = 0
