"""Synthetic scenes for the grasp sampler's tests: meshes on a table (z = 0) seen by cameras.

Points are sampled on the meshes' surfaces and kept where a camera sees them (its first ray
hit is the point: trimesh's ray casting); ``unknown(points)`` answers, like a scene volume,
whether no camera's ray ever passed through a point (hidden behind what was seen).
"""

from __future__ import annotations

import types

import numpy as np
import trimesh

from grasp_pipeline.motion.perceived_scene import PerceivedScene
from grasp_pipeline.orchestration.config import GraspFitConfig
from grasp_pipeline.orchestration.grasping.opening import max_grasp_width_m
from grasp_pipeline.orchestration.grasping.source import GraspRequest
from grasp_pipeline.orchestration.scene.scene_cloud import ENVIRONMENT, SceneCloud
from grasp_pipeline.orchestration.scene.tracks import track_box

UP = np.array([0.0, 0.0, 1.0])
TABLE = trimesh.creation.box((1.0, 1.0, 0.02), trimesh.transformations.translation_matrix([0.5, 0.0, -0.01]))


def _first_hit(mesh: trimesh.Trimesh, cam: np.ndarray, pts: np.ndarray, chunk: int = 256) -> np.ndarray:
    """Distance from ``cam`` to the first surface along the ray towards each point (inf:
    none) — Möller–Trumbore against every triangle, in numpy."""
    tri = mesh.triangles
    v0, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    out = np.full(len(pts), np.inf)
    for s in range(0, len(pts), chunk):
        d = pts[s:s + chunk] - cam
        d = d / np.linalg.norm(d, axis=1, keepdims=True)
        p = np.cross(d[:, None, :], e2[None])
        det = np.einsum("rtk,tk->rt", p, e1)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            inv = 1.0 / det
            t0 = cam - v0
            u = np.einsum("tk,rtk->rt", t0, p) * inv
            q = np.cross(t0, e1)
            v = np.einsum("rk,tk->rt", d, q) * inv
            t = np.einsum("tk,tk->t", e2, q)[None, :] * inv
            hit = (np.abs(det) > 1e-12) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t > 1e-9)
        out[s:s + chunk] = np.where(hit, t, np.inf).min(axis=1)
    return out


class Scene:
    """Objects (owner id → mesh in world) on the table, seen from ``cameras`` (positions)."""

    def __init__(self, objects: dict, cameras, step_m: float = 0.003, seed: int = 0) -> None:
        self.objects = objects
        self.cameras = [np.asarray(c, float) for c in cameras]
        self.all = trimesh.util.concatenate([TABLE, *objects.values()])
        rng = np.random.default_rng(seed)
        pts, own = [], []
        for tid, mesh in objects.items():
            n = max(200, int(mesh.area / step_m ** 2))
            p, _ = trimesh.sample.sample_surface(mesh, n, seed=int(rng.integers(1 << 30)))
            pts.append(p)
            own.append(np.full(len(p), tid))
        X, Y = np.meshgrid(np.arange(0.3, 0.75, step_m), np.arange(-0.2, 0.2, step_m))
        pts.append(np.column_stack([X.ravel(), Y.ravel(), np.zeros(X.size)]))
        own.append(np.full(X.size, ENVIRONMENT))
        pts, own = np.vstack(pts), np.concatenate(own)
        seen = np.zeros(len(pts), bool)
        for cam in self.cameras:
            seen |= _first_hit(self.all, cam, pts) >= np.linalg.norm(pts - cam, axis=1) - 1e-4
        self.cloud = SceneCloud(pts[seen], own[seen], UP, 0.0, 0.01)

    def unknown(self, points: np.ndarray) -> np.ndarray:
        """True where no camera saw through or onto the point."""
        pts = np.asarray(points, float).reshape(-1, 3)
        known = pts[:, 2] < 0.0
        for cam in self.cameras:
            known |= _first_hit(self.all, cam, pts) >= np.linalg.norm(pts - cam, axis=1) - 2e-3
        return ~known

    def track(self, tid: int):
        """A stand-in for a core track: an upright box around the object's seen points."""
        pts = self.cloud.of(tid)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        c = 0.5 * (lo + hi)
        c[2] = 0.5 * hi[2]
        ext = [hi[0] - lo[0], hi[1] - lo[1], hi[2]]
        e = types.SimpleNamespace(center=c, R_box=np.eye(3), extents=ext, height_m=hi[2],
                                  width_m=min(ext[:2]), perp_width_m=max(ext[:2]))
        return types.SimpleNamespace(tid=tid, smoothed=e)

    def request(self, tid: int, unknown: bool = True) -> GraspRequest:
        tracks = [self.track(t) for t in self.objects if len(self.cloud.of(t))]
        env = self.cloud.points[self.cloud.owner == ENVIRONMENT]
        scene = PerceivedScene(env, [track_box(t) for t in tracks], [t.tid for t in tracks],
                               T_world_camera=_pose(self.cameras[0]),
                               plane=types.SimpleNamespace(n=UP, c=0.0),
                               object_points=[self.cloud.of(t.tid) for t in tracks])
        return GraspRequest(anchor_xy=tuple(tracks[0].smoothed.center[:2]), target=self.track(tid),
                            published=None, scene=scene, max_width_m=max_grasp_width_m(GraspFitConfig()), cloud=self.cloud,
                            unknown=self.unknown if unknown else None)


def _pose(position) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = position
    return T


def placed(parts, R=np.eye(3), position=(0.5, 0.0, 0.0)) -> trimesh.Trimesh:
    """The union of convex ``parts`` rotated by ``R`` about the origin, then moved so the
    lowest point is on the table at ``position`` (x, y)."""
    mesh = trimesh.util.concatenate(parts)
    T = np.eye(4)
    T[:3, :3] = R
    mesh.apply_transform(T)
    lo = mesh.bounds[0]
    mesh.apply_translation([position[0] - 0.5 * (mesh.bounds[0][0] + mesh.bounds[1][0]),
                            position[1] - 0.5 * (mesh.bounds[0][1] + mesh.bounds[1][1]), -lo[2] + position[2]])
    return mesh
