"""Typed results of the pipeline: a scan, a grasp, a pick, a whole run.

Plain dataclasses, written to JSON only by :mod:`grasp_pipeline.report.serialize` (the one
serializer: valid JSON, ``null`` for undefined numbers). Units in the field names; times in
simulated seconds unless named ``wall``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Optional, TypedDict

#: ``RunReport.status`` values.
STATUS_RUNNING = "running"
STATUS_COMPLETE = "complete"
STATUS_FAILED = "failed"
STATUS_INTERRUPTED = "interrupted"


@dataclass
class TrackSummary:
    """One tracked object as the report shows it."""

    tid: int
    quality: str
    pca_tilt_deg: float
    center: list
    extents: list
    theta_deg: float
    grasp_ok: bool
    notes: list = field(default_factory=list)


@dataclass
class ProbeResult:
    """One object's probe in the active scan."""

    index: int
    rough_center: list
    tid: Optional[int] = None
    nadir: bool = False
    message: str = ""
    view_angles_deg: dict = field(default_factory=dict)
    closer_look: str = ""   # why the segment was looked at again from closer above ("": not)


@dataclass
class SideViewResult:
    """(ours) The side view before a pick: how much of the target's shell was unknown (worst
    face, and per face), the view taken (None: none), and what it cost."""

    tid: int
    unknown_before: float = 0.0
    unknown_after: Optional[float] = None
    faces_before: dict = field(default_factory=dict)
    faces_after: dict = field(default_factory=dict)
    view: Optional[dict] = None     # azimuth_deg, elevation_deg, distance_m, expected_fraction
    moved: bool = False
    message: str = ""
    sim_s: float = 0.0              # simulated time it took [s]
    cpu_s: float = 0.0              # CPU time of the main thread [s]


@dataclass
class ScanOutcome:
    """What the scan task returns."""

    probes: list = field(default_factory=list)   # ProbeResult
    completed: bool = False
    returned_to_start: bool = False
    joint_error_rad: Optional[float] = None
    failure: str = ""
    start_q: Optional[list] = None


@dataclass
class GraspOutcome:
    """What the grasp action returns."""

    success: bool = False
    failed_stage: Optional[str] = None
    message: str = ""
    stall_gap_m: Optional[float] = None
    placed: bool = False
    stages: list = field(default_factory=list)  # (stage, sim time at entry [s])
    width_m: Optional[float] = None
    release_time_s: Optional[float] = None  # when the gripper opened to place / recover
    candidate: Optional[int] = None          # which grasp candidate was executed (0-based)
    grasp: Optional[dict] = None             # the executed grasp: kind, tilt_deg, score, source


@dataclass
class ViewReport:
    """The perceived scene at one moment of the run (rough view, after the scan)."""

    tracks: list = field(default_factory=list)   # TrackSummary
    scores: list = field(default_factory=list)   # ground-truth scores (evaluation), per object
    snapshot: Optional[str] = None


@dataclass
class ScanReport(ViewReport):
    trigger: str = ""
    completed: bool = False
    returned_to_start: bool = False
    joint_error_rad: Optional[float] = None
    failure: str = ""
    probes: list = field(default_factory=list)   # ProbeResult


@dataclass
class PickResult:
    """One pick of the run (selection → grasp → place), with its evaluation."""

    anchor: list
    success: bool = False
    failed_stage: Optional[str] = None
    message: str = ""
    lift_m: float = 0.0
    held_s: float = 0.0
    placed: bool = False
    stages: list = field(default_factory=list)
    stall_gap_m: Optional[float] = None
    width_m: Optional[float] = None
    selected: str = ""
    object: Optional[str] = None
    reprobed: Optional[bool] = None
    side_view: Optional[SideViewResult] = None   # (ours) the look at the target's sides
    grasp_source: str = ""
    wall_s: Optional[float] = None   # wall-clock time of the whole pick [s]
    snapshots: list = field(default_factory=list)   # PNGs written for this pick (failures)
    declined: bool = False   # no grasp after a closer look: not attempted (clearing a table)
    grasp: Optional[dict] = None   # the executed grasp: kind, tilt_deg, score, source


@dataclass
class PickResolution:
    """What one ``--pick`` description resolved to (the perceived object, in words)."""

    description: str
    tid: int
    described: str        # "the red mug"
    colour: str
    shape: str
    size: str             # small, large or "" (relative to the objects seen)
    center: list          # perceived box centre [m]
    extents: list         # (width, perp_width, height) [m]
    distance_m: float     # horizontal, from the robot base


@dataclass
class RunReport:
    """The whole run; ``status`` says whether it completed, failed or was interrupted."""

    scene: dict
    settings: dict
    status: str = STATUS_RUNNING
    error: Optional[str] = None
    plane: Optional[dict] = None
    rough: Optional[ViewReport] = None
    scan: Optional[ScanReport] = None
    targets_skipped: list = field(default_factory=list)
    picks: list = field(default_factory=list)        # PickResult
    motion_plans: list = field(default_factory=list)
    video: Optional[str] = None
    recording: Optional[str] = None    # the Rerun recording (.rrd) with --rerun
    warnings: list = field(default_factory=list)
    timings: dict = field(default_factory=dict)
    extra: dict = field(default_factory=dict)
    end_reason: Optional[str] = None   # with --declutter: why the round of picks ended
    resolved: list = field(default_factory=list)   # PickResolution of each --pick description
    object_notes: dict = field(default_factory=dict)  # object model -> source, loader notes, warnings

    @property
    def all_picked(self) -> bool:
        return bool(self.picks) and all(p.success for p in self.picks)

    def to_dict(self) -> dict[str, Any]:
        from .report.serialize import to_jsonable

        return to_jsonable(self)


# ---- benchmark records: TypedDicts, since they cross process pipes (pickled) and are
# ---- aggregated as mappings; written by the same serializer.

class SceneScanSummary(TypedDict):
    completed: bool
    failure: str
    nadir: int


class SceneRecord(TypedDict):
    """One scene of ``bench grasp``: facts, per-object outcome and errors, picks, timings."""

    index: int
    seed: int
    objects: int
    picks: int
    error: Optional[str]
    run_error: Optional[str]
    scan: Optional[SceneScanSummary]
    object_rows: list
    pick_rows: list
    timings: dict


class MotionRecord(TypedDict, total=False):
    """One motion of ``bench planning``: planned (and executed) or its error."""

    scene: str
    kind: str
    ok: bool
    planning_ms: float
    planning_cpu_ms: float
    method: str
    toppra_ms: float
    duration_s: float
    error: str
