"""The planning world with the held object attached: a carry whose straight path would sweep the
object through a neighbour is planned around it; the environment where the object stood is
cleared when it is lifted."""

import numpy as np
import pytest

from grasp_pipeline.motion.occupancy import OrientedBox
from grasp_pipeline.motion.planning_world import PERCEIVED_PREFIX, PlanningWorld
from grasp_pipeline.motion.perceived_scene import PerceivedScene
from grasp_pipeline.robot import description as rm


def _tcp_down(x, y, z):
    T = np.eye(4)
    T[:3, :3] = np.array([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]])
    T[:3, 3] = (x, y, z)
    return T


def _held_points(T_tcp, depth=0.12, width=0.05, step=0.01):
    """A width x width x depth block hanging from the TCP (between the fingers and below)."""
    g = np.arange(-width / 2, width / 2 + 1e-9, step)
    X, Y, Z = np.meshgrid(g, g, np.arange(0.0, depth + 1e-9, step), indexing="ij")
    local = np.c_[X.ravel(), Y.ravel(), Z.ravel()]  # TCP frame: z along the approach (down)
    return local @ T_tcp[:3, :3].T + T_tcp[:3, 3]


def _dense(wp, step=np.radians(0.5)):
    out = [wp[:1]]
    for a, b in zip(wp[:-1], wp[1:]):
        n = max(1, int(np.ceil(np.max(np.abs(b - a)) / step)))
        out.append(a + (b - a) * (np.arange(1, n + 1)[:, None] / n))
    return np.vstack(out)


@pytest.fixture()
def carry(planner):
    """Two carry poses 0.4 m apart at z = 0.40 and a neighbour between them whose top (0.34)
    the empty hand passes above but a block hanging 0.12 m below the TCP does not."""
    world = PlanningWorld(planner)
    neighbour = OrientedBox(np.array([0.5, 0.0, 0.27]), np.eye(3), np.array([0.12, 0.12, 0.14]))
    world.add_object("placed/0", neighbour)
    world.commit()
    T_a, T_b = _tcp_down(0.5, -0.2, 0.40), _tcp_down(0.5, 0.2, 0.40)
    qa = planner.solve_ik(T_a, rm.READY_Q).q
    qb = planner.solve_ik(T_b, qa).q
    yield world, T_a, qa, qb
    world.detach()
    planner.set_scene(np.zeros((0, 3)))


def test_a_carry_is_planned_around_a_neighbour_the_held_object_would_sweep(planner, carry):
    world, T_a, qa, qb = carry
    v = planner.validator
    straight = _dense(np.vstack([qa, qb]))
    assert np.all(v.check_batch(straight)), "the empty hand passes straight over the neighbour"
    n = world.attach("object/7", _held_points(T_a), T_a)
    world.commit()
    assert n > 0 and world.attached == "object/7"
    assert v.is_valid(qa) and v.is_valid(qb)
    assert not np.all(v.check_batch(straight)), "the straight path sweeps the held object through it"
    path = planner.plan_path_to_joints(qa, qb)
    assert np.all(v.check_batch(_dense(path.waypoints)))
    # the held object's spheres keep clear of the neighbour all along the way
    box = world.objects["placed/0"].box
    held = planner.robot.spheres.geom == planner.model.ngeom
    for q in _dense(path.waypoints)[::10]:
        C = planner.robot.centres(q[None])[0][held]
        assert np.all(box.distance_m(C) > planner.robot.spheres.radius[held])
    assert world.detach() == "object/7"
    world.commit()
    assert np.all(v.check_batch(straight)), "released, the hand may go straight again"


def test_lifting_the_held_object_clears_its_stray_environment_points(planner):
    """Points of the object that no track took (environment) stay where it stood; once it is
    held they are gone from the planner's world, the table's are kept."""
    world = PlanningWorld(planner)
    box = OrientedBox(np.array([0.5, 0.0, 0.25]), np.eye(3), np.array([0.05, 0.05, 0.10]))
    stray = np.array([[0.52, 0.02, 0.28], [0.49, -0.02, 0.24]])
    table = np.array([[0.5, 0.0, 0.2], [0.6, 0.1, 0.2], [0.51, 0.01, 0.208]])  # within the band
    plane = type("Plane", (), {"n": np.array([0.0, 0.0, 1.0]), "c": -0.2})()
    world.set_perceived(PerceivedScene(np.vstack([stray, table]), [box], [3], plane=plane, band_m=0.01))
    world.commit()
    T = _tcp_down(0.5, 0.0, 0.28)
    world.attach(f"{PERCEIVED_PREFIX}3", _held_points(T, depth=0.08), T)
    assert f"{PERCEIVED_PREFIX}3" not in world.objects
    assert np.allclose(np.sort(world.environment, axis=0), np.sort(table, axis=0))
    world.detach()


def test_the_held_spheres_in_the_tcp_frame_are_the_attached_ones(planner):
    """What the tray's spot choice uses (held_spheres_in_tcp) is what the planner carries."""
    from grasp_pipeline.motion.planning_world import held_spheres_in_tcp

    world = PlanningWorld(planner)
    q = np.array(rm.READY_Q, float)
    T = planner.ik.fk_tcp(q)
    pts = _held_points(T, depth=0.07)
    world.attach("object/1", pts, T)
    held = planner.robot.spheres.geom == planner.model.ngeom
    attached = planner.robot.centres(q[None])[0][held]
    c, r = held_spheres_in_tcp(planner.model, (pts - T[:3, 3]) @ T[:3, :3])
    assert np.allclose(np.sort(c @ T[:3, :3].T + T[:3, 3], axis=0), np.sort(attached, axis=0), atol=1e-9)
    assert np.allclose(np.sort(r), np.sort(planner.robot.spheres.radius[held]))
    world.detach()


def test_the_parts_of_a_held_object_inside_a_neighbour_where_it_hangs_are_trimmed(planner):
    """In a pile the held points are filled down to the table, through the object below: once
    lifted, those parts still lie in that neighbour; the rest of the model is kept."""
    world = PlanningWorld(planner)
    T = _tcp_down(0.5, 0.0, 0.35)
    q = planner.solve_ik(T, rm.READY_Q).q
    world.add_object("object/2", OrientedBox(np.array([0.5, 0.0, 0.22]), np.eye(3), np.array([0.1, 0.1, 0.1])))
    n_all = world.attach("object/1", _held_points(T, depth=0.12), T)  # reaches down to z = 0.23
    world.commit()
    assert not planner.validator.is_valid(q)
    n = world.trim_attached(q)
    world.commit()
    assert 0 < n < n_all and world.attached == "object/1"
    assert planner.validator.is_valid(q)
    world.detach()
