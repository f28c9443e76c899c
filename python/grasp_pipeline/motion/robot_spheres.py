"""The robot's collision geometry for planning: spheres fitted to the model's collision geoms.

Every collision geom of the robot MJCF (``contype`` or ``conaffinity`` non-zero) is covered
by spheres, expressed in its body's frame:

* sphere → itself; capsule → spheres of the capsule radius, inflated to
  ``sqrt(r² + (s/2)²)``, along the segment at spacing ``s ≤ r/2``, which covers it exactly;
* cylinder → spheres on the axis, inset by half a spacing from the end faces and inflated to
  cover the rim; box / ellipsoid / mesh (its bounding box) → a grid of cells of at most
  ``sphere_cell_m``, one sphere per cell with the cell's half-diagonal as radius.

Every sphere contains its part of the geom, so "no sphere touches an obstacle" implies
"no geom touches it". Sphere centres are posed with ``mujoco.mj_kinematics`` on the robot-only
model (about 2 µs per state) and one vectorised transform.

Self-collision: links are grouped into rigid groups (a body with a joint plus the jointless
bodies fixed to it; the flange and the hand belong to link 7). Pairs are checked between
groups that are neither the same nor parent/child, minus pairs already in contact in the
ready and the neutral pose (the "default" rule of MoveIt's setup assistant), and minus the
finger/finger pair (the fingers touch when closed).
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from ..robot import description as rm
from .kinematics import ChainKinematics, _quat_to_mat


@dataclass(frozen=True)
class SphereSet:
    """Spheres in body frames: ``body`` (S,) body ids, ``center_local`` (S, 3), ``radius`` (S,),
    ``geom`` (S,) the geom each sphere covers."""

    body: np.ndarray
    center_local: np.ndarray
    radius: np.ndarray
    geom: np.ndarray


def _segment_spheres(r: float, half_len: float, inset: bool) -> tuple[np.ndarray, float]:
    """Centres along z in [-half_len, half_len] and the covering radius."""
    spacing_max = 0.5 * r
    if inset:  # cylinder: centres inset by half a spacing from the flat ends
        length = 2.0 * half_len
        n = max(1, int(np.ceil(length / spacing_max)))
        s = length / n
        z = -half_len + s * (np.arange(n) + 0.5)
        return z, float(np.hypot(r, 0.5 * s))
    length = 2.0 * half_len
    n = max(1, int(np.ceil(length / spacing_max)))
    s = length / n
    z = -half_len + s * np.arange(n + 1)
    return z, float(np.hypot(r, 0.5 * s))


def _box_spheres(half: np.ndarray, cell_m: float) -> tuple[np.ndarray, np.ndarray]:
    n = np.maximum(1, np.ceil(2.0 * half / cell_m).astype(int))
    c = 2.0 * half / n
    axes = [-half[k] + c[k] * (np.arange(n[k]) + 0.5) for k in range(3)]
    g = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    return g, np.full(len(g), 0.5 * float(np.linalg.norm(c)))


def fit_spheres(model: mujoco.MjModel, cell_m: float) -> SphereSet:
    """Cover every collision geom of ``model`` with spheres (body frames)."""
    bodies, centres, radii, geoms = [], [], [], []
    for g in range(model.ngeom):
        if model.geom_contype[g] == 0 and model.geom_conaffinity[g] == 0:
            continue
        b = int(model.geom_bodyid[g])
        if b == 0:
            continue
        gt = int(model.geom_type[g])
        size = np.array(model.geom_size[g], dtype=float)
        if gt == mujoco.mjtGeom.mjGEOM_SPHERE:
            local, rad = np.zeros((1, 3)), np.array([size[0]])
        elif gt in (mujoco.mjtGeom.mjGEOM_CAPSULE, mujoco.mjtGeom.mjGEOM_CYLINDER):
            z, r = _segment_spheres(size[0], size[1], inset=gt == mujoco.mjtGeom.mjGEOM_CYLINDER)
            local = np.stack([np.zeros_like(z), np.zeros_like(z), z], axis=1)
            rad = np.full(len(z), r)
        elif gt in (mujoco.mjtGeom.mjGEOM_BOX, mujoco.mjtGeom.mjGEOM_ELLIPSOID):
            local, rad = _box_spheres(size[:3], cell_m)
        else:  # mesh or anything else: its bounding box in the geom frame
            aabb = np.array(model.geom_aabb[g], dtype=float)
            local, rad = _box_spheres(aabb[3:], cell_m)
            local = local + aabb[:3]
        Rg = _quat_to_mat(model.geom_quat[g])
        centres.append(local @ Rg.T + model.geom_pos[g])
        radii.append(rad)
        bodies.append(np.full(len(rad), b))
        geoms.append(np.full(len(rad), g))
    return SphereSet(np.concatenate(bodies), np.vstack(centres), np.concatenate(radii), np.concatenate(geoms))


class RobotSpheres:
    """Sphere model of the robot, posed for batches of arm states.

    ``finger_opening_m``: finger gap assumed for the finger bodies (each finger moves half).
    Attributes: ``spheres`` (the fit), ``env_mask`` (S,) spheres checked against the
    environment (those on moving links), ``hand_mask`` (S,) spheres of the flange subtree
    (hand, fingers, camera, link 7: may enter the target region during the final approach),
    ``pair_i``, ``pair_j`` the self-collision sphere pairs.
    """

    def __init__(self, model: mujoco.MjModel, cell_m: float, finger_opening_m: float,
                 self_margin_m: float = 0.0) -> None:
        self.model = model
        self.arm_idx = rm.arm_qpos_indices(model)
        self.kin = ChainKinematics(model, self.arm_idx)
        self.robot_spheres = fit_spheres(model, cell_m)
        self.spheres = self.robot_spheres
        self.attached_name: str | None = None
        self.version = 0  # bumped whenever the sphere set changes (attach / detach)
        self.self_margin_m = float(self_margin_m)
        self.fixed_qpos = np.array(model.qpos0, dtype=float)
        self._data = mujoco.MjData(model)
        self.set_finger_opening(finger_opening_m)
        self.group = np.array([self._group(b) for b in range(model.nbody)])
        self._structure()

    def _structure(self) -> None:
        """Masks, self-collision pairs and body count of the current sphere set."""
        sb = self.spheres.body
        self.env_mask = self.kin.moving[sb]
        flange = self.model.body(rm.FLANGE_BODY).id
        link7 = int(self.model.body_parentid[flange])
        self.hand_mask = np.array([self._in_subtree(int(b), link7) for b in sb])
        self._bodies_needed = int(sb.max()) + 1
        self._build_pairs()

    def attach(self, name: str, centres_hand: np.ndarray, radii: np.ndarray) -> None:
        """Carry spheres (``centres_hand`` (M, 3) in the hand body's frame, ``radii`` (M,))
        with the hand: an object held between the fingers, checked like the hand itself
        (against the environment, and against the arm's other links)."""
        c = np.asarray(centres_hand, dtype=float).reshape(-1, 3)
        r = np.asarray(radii, dtype=float).reshape(-1)
        if len(c) != len(r) or not (np.all(np.isfinite(c)) and np.all(np.isfinite(r)) and np.all(r > 0)):
            raise ValueError("attach: centres (M, 3) and positive radii (M,) of one length expected")
        hand = self.model.body(rm.HAND_BODY).id
        base = self.robot_spheres
        geom = int(self.model.ngeom)  # a geom id of its own, past the model's geoms
        self.spheres = SphereSet(np.r_[base.body, np.full(len(r), hand)], np.vstack([base.center_local, c]),
                                 np.r_[base.radius, r], np.r_[base.geom, np.full(len(r), geom)])
        self.attached_name = str(name)
        self.version += 1
        self._structure()

    def detach(self) -> str | None:
        """Drop the attached spheres; returns the name of what was attached (None: nothing)."""
        name = self.attached_name
        if name is None:
            return None
        self.spheres = self.robot_spheres
        self.attached_name = None
        self.version += 1
        self._structure()
        return name

    # ------------------------------------------------------------------ structure
    def _in_subtree(self, b: int, root: int) -> bool:
        while b > 0:
            if b == root:
                return True
            b = int(self.model.body_parentid[b])
        return False

    def _group(self, b: int) -> int:
        while b > 0 and self.model.body_jntnum[b] == 0 and self.model.body_parentid[b] > 0:
            b = int(self.model.body_parentid[b])
        return b

    def set_finger_opening(self, gap_m: float) -> None:
        """Finger gap (pad to pad) used for posing the finger spheres."""
        q = self.fixed_qpos
        for name in rm.FINGER_JOINT_NAMES:
            j = self.model.joint(name)
            lo, hi = self.model.jnt_range[j.id]
            q[j.qposadr[0]] = float(np.clip(0.5 * gap_m, lo, hi))
        self.finger_opening_m = float(gap_m)
        self._data.qpos[:] = q

    def _build_pairs(self) -> None:
        m = self.model
        sb = self.spheres.body
        grp = self.group[sb]
        parent_grp = {g: self._group(int(m.body_parentid[g])) for g in set(self.group.tolist()) if g > 0}
        fingers = {m.body(n).id for n in rm.FINGER_BODIES}
        allowed = np.ones((m.nbody, m.nbody), dtype=bool)
        for a in range(m.nbody):
            for b in range(m.nbody):
                ga, gb = self.group[a], self.group[b]
                if ga == gb or parent_grp.get(ga) == gb or parent_grp.get(gb) == ga:
                    allowed[a, b] = False
                if a in fingers and b in fingers:
                    allowed[a, b] = False
        I, J = np.triu_indices(len(sb), k=1)
        keep = allowed[sb[I], sb[J]] & (grp[I] != grp[J])
        I, J = I[keep], J[keep]
        # drop body pairs already touching in the ready / neutral poses ("default" collisions)
        self.disabled_default: list[tuple[str, str]] = []
        for q in (rm.READY_Q, rm.NEUTRAL_Q):
            c = self.centres(np.asarray(q)[None])[0]
            d = np.linalg.norm(c[I] - c[J], axis=1) - self.spheres.radius[I] - self.spheres.radius[J]
            hit = d < self.self_margin_m
            for a, b in {(int(sb[i]), int(sb[j])) for i, j in zip(I[hit], J[hit])}:
                self.disabled_default.append((m.body(a).name, m.body(b).name))
                rm_mask = ((sb[I] == a) & (sb[J] == b)) | ((sb[I] == b) & (sb[J] == a))
                I, J = I[~rm_mask], J[~rm_mask]
        # group sphere pairs by geom pair (for the two-level check)
        sg = self.spheres.geom
        ng = int(m.ngeom) + 1  # one more: an attached object's spheres
        a, b = np.minimum(sg[I], sg[J]), np.maximum(sg[I], sg[J])
        key = a * ng + b
        order = np.argsort(key, kind="stable")
        I, J, key = I[order], J[order], key[order]
        self.pair_i, self.pair_j = I, J
        self.pair_rsum = self.spheres.radius[I] + self.spheres.radius[J]
        ukeys, self.bp_start, self.bp_count = np.unique(key, return_index=True, return_counts=True)
        geoms = np.unique(sg)
        slot = {int(x): k for k, x in enumerate(geoms)}
        self.bp_a = np.array([slot[int(k // ng)] for k in ukeys], dtype=int)
        self.bp_b = np.array([slot[int(k % ng)] for k in ukeys], dtype=int)
        # bounding sphere of each geom's spheres: centre = mean of the sphere centres (a
        # weighted sum of posed centres, so it is posed for free; all in one body frame)
        kmax = max(int(np.sum(sg == x)) for x in geoms)
        members = np.zeros((len(geoms), kmax), dtype=int)
        weights = np.zeros((len(geoms), kmax))
        brad = np.zeros(len(geoms))
        for k, x in enumerate(geoms):
            idx = np.nonzero(sg == x)[0]
            members[k, :len(idx)] = idx
            members[k, len(idx):] = idx[0]
            weights[k, :len(idx)] = 1.0 / len(idx)
            loc = self.spheres.center_local[idx]
            cen = loc.mean(axis=0)
            brad[k] = np.max(np.linalg.norm(loc - cen, axis=1) + self.spheres.radius[idx])
        self._bound_members, self._bound_weights = members, weights
        self.bp_rsum = brad[self.bp_a] + brad[self.bp_b]

    # ------------------------------------------------------------------ posing
    def body_poses(self, Q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Body rotations (N, nbody, 3, 3) and positions (N, nbody, 3) by ``mj_kinematics``."""
        Q = np.atleast_2d(np.asarray(Q, dtype=float))
        n = len(Q)
        R = np.empty((n, self.model.nbody, 9))
        p = np.empty((n, self.model.nbody, 3))
        d, m = self._data, self.model
        qpos = d.qpos
        for k in range(n):
            qpos[self.arm_idx] = Q[k]
            mujoco.mj_kinematics(m, d)
            R[k] = d.xmat
            p[k] = d.xpos
        return R.reshape(n, -1, 3, 3), p

    def centres(self, Q: np.ndarray) -> np.ndarray:
        """World sphere centres (N, S, 3) for arm states Q (N, 7)."""
        R, p = self.body_poses(Q)
        sb = self.spheres.body
        return p[:, sb] + np.einsum("nsij,sj->nsi", R[:, sb], self.spheres.center_local)

    def self_clearance_min(self, C: np.ndarray) -> np.ndarray:
        """(N,) smallest signed clearance over the self-collision pairs (inf if none is near).

        Two levels: the bounding spheres of each checked body pair first, then the sphere
        pairs of the body pairs whose bounding spheres overlap (within the margin).
        """
        n = len(C)
        out = np.full(n, np.inf)
        if len(self.bp_a) == 0:
            return out
        bc = C[:, self._bound_members]  # (N, B, K, 3) padded members -> bounding centres
        ctr = np.einsum("nbkj,bk->nbj", bc, self._bound_weights)
        d = np.linalg.norm(ctr[:, self.bp_a] - ctr[:, self.bp_b], axis=-1) - self.bp_rsum
        n_idx, bp_idx = np.nonzero(d < self.self_margin_m)
        if len(n_idx) == 0:
            return out
        counts = self.bp_count[bp_idx]
        total = int(counts.sum())
        starts = np.repeat(self.bp_start[bp_idx] - np.cumsum(counts) + counts, counts)
        flat = starts + np.arange(total)
        states = np.repeat(n_idx, counts)
        i, j = self.pair_i[flat], self.pair_j[flat]
        dd = np.linalg.norm(C[states, i] - C[states, j], axis=-1) - self.pair_rsum[flat]
        # ``states`` is sorted (np.nonzero is row-major): one reduceat per state
        first = np.concatenate([[0], np.nonzero(np.diff(states))[0] + 1])
        out[states[first]] = np.minimum.reduceat(dd, first)
        return out

    def describe(self) -> str:
        names = {}
        for b in np.unique(self.spheres.body):
            names[self.model.body(int(b)).name] = int(np.sum(self.spheres.body == b))
        return (f"{len(self.spheres.radius)} spheres {names}; {len(self.pair_i)} self-collision pairs; "
                f"disabled default pairs {sorted(set(self.disabled_default))}")


def hand_spheres_in_tcp(model: mujoco.MjModel, cell_m: float, finger_opening_m: float
                        ) -> tuple[np.ndarray, np.ndarray]:
    """The planner's spheres of the hand and the fingers (opened to ``finger_opening_m``),
    in the TCP frame (x across the closing axis, y the closing axis, z the approach, into the
    object): centres (S, 3) and radii (S,). What a grasp's final approach must keep clear."""
    hand = model.body(rm.HAND_BODY).id
    spheres = fit_spheres(model, cell_m)
    data = mujoco.MjData(model)
    for name in rm.FINGER_JOINT_NAMES:
        j = model.joint(name)
        lo, hi = model.jnt_range[j.id]
        data.qpos[j.qposadr[0]] = float(np.clip(0.5 * finger_opening_m, lo, hi))
    mujoco.mj_kinematics(model, data)
    R_h, p_h = data.xmat[hand].reshape(3, 3), data.xpos[hand]
    site = model.site(rm.TCP_SITE).id
    R_t = R_h.T @ data.site_xmat[site].reshape(3, 3)
    p_t = R_h.T @ (data.site_xpos[site] - p_h)
    keep = [k for k, b in enumerate(spheres.body)
            if int(b) == hand or int(model.body_parentid[int(b)]) == hand]
    out = []
    for k in keep:
        b = int(spheres.body[k])
        c_world = data.xmat[b].reshape(3, 3) @ spheres.center_local[k] + data.xpos[b]
        out.append(R_t.T @ (R_h.T @ (c_world - p_h) - p_t))
    return np.array(out).reshape(-1, 3), spheres.radius[keep].copy()
