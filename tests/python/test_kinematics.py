"""Robot library and kinematics from Python: the IRB 120 home pose and IK round trips."""
import math
import random

import numpy as np
import pytest

import robcal


def test_builtin_robots_load():
    names = robcal.builtin_robots()
    assert "abb-irb120" in names
    ortho_parallel = set()
    for name in names:
        robot = robcal.load_robot(name)
        assert robot.joint_limits_deg.shape == (6, 2)
        if robot.is_ortho_parallel:
            ortho_parallel.add(name)
    assert {"abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"} <= ortho_parallel
    # Offset wrists (UR) and the CRX are not ortho-parallel with a spherical wrist.
    assert not {"universal-robots-ur10e", "fanuc-crx10ia-l"} & ortho_parallel


def test_unknown_robot_is_a_value_error():
    with pytest.raises(ValueError, match="no-such-robot"):
        robcal.load_robot("no-such-robot")


def test_irb120_home_pose():
    robot = robcal.load_robot("abb-irb120")
    pose = robcal.fk(robot, [0, 0, 0, 0, 0, 0])
    np.testing.assert_allclose(pose["position_mm"], [374.0, 0.0, 630.0], atol=1e-9)
    # Flange z along base +x: a +90° turn about y, q = (cos 45°, 0, sin 45°, 0).
    h = math.sqrt(0.5)
    np.testing.assert_allclose(pose["quaternion_wxyz"], [h, 0.0, h, 0.0], atol=1e-12)


@pytest.mark.parametrize("name", ["abb-irb120", "fanuc-lrmate200ic", "kuka-kr6-r900-sixx"])
def test_ik_round_trip(name):
    robot = robcal.load_robot(name)
    limits = robot.joint_limits_deg
    rng = random.Random(20261122)
    for _ in range(50):
        joints = [rng.uniform(lo + 1, hi - 1) for lo, hi in limits]
        if abs(math.sin(math.radians(joints[4]))) < 0.1:
            continue  # near the wrist singularity θ4 comes from the seed
        pose = robcal.fk(robot, joints)
        result = robcal.ik(robot, pose["position_mm"], pose["quaternion_wxyz"])
        assert result["status"] == "solved"
        best = min(np.max(np.abs(s["joints_deg"] - joints)) for s in result["solutions"])
        assert best < 1e-7, (joints, best)
        for s in result["solutions"]:  # every solution reaches the same pose
            back = robcal.fk(robot, s["joints_deg"])
            np.testing.assert_allclose(back["position_mm"], pose["position_mm"], atol=1e-8)
            assert abs(abs(np.dot(back["quaternion_wxyz"], pose["quaternion_wxyz"])) - 1) < 1e-12


def test_unreachable_pose_is_a_status():
    robot = robcal.load_robot("abb-irb120")
    result = robcal.ik(robot, [2000.0, 0.0, 500.0], [1.0, 0.0, 0.0, 0.0])
    assert result["status"] == "unreachable"
    assert result["solutions"] == []


def test_bad_joint_count_is_a_value_error():
    robot = robcal.load_robot("abb-irb120")
    with pytest.raises(ValueError, match="6 joint values"):
        robcal.fk(robot, [0, 0, 0])


@pytest.mark.parametrize("name", ["abb-irb120", "universal-robots-ur10e"])
def test_ik_batch_inverts_fk_batch_along_a_path(name):
    robot = robcal.load_robot(name)
    limits = robot.joint_limits_deg
    # A smooth joint path well inside the limits and away from the wrist singularity.
    t = np.linspace(0, 1, 40)[:, None]
    start = limits[:, 0] * 0.3 + limits[:, 1] * 0.7
    end = limits[:, 0] * 0.6 + limits[:, 1] * 0.4
    joints = (1 - t) * start + t * end
    joints[:, 4] = np.clip(joints[:, 4], 30, 80)
    poses = robcal.fk_batch(robot, joints)
    far = np.vstack([poses["position_mm"], [[5000.0, 0.0, 0.0]]])
    quaternions = np.vstack([poses["quaternion_wxyz"], [[1.0, 0.0, 0.0, 0.0]]])
    r = robcal.ik_batch(robot, far, quaternions, seed_joints_deg=joints[0])
    # UR joints span two turns: more solutions than kept ("truncated"), the path's among them.
    assert set(r["status"][:-1]) <= {"solved", "truncated"} and r["status"][-1] == "unreachable"
    assert np.isnan(r["joints_deg"][-1]).all() and r["config"][-1] == ""
    # Seeded at the path's start, each row follows the path: its own joints (its configuration
    # label may change along the way, the joints do not jump).
    np.testing.assert_allclose(r["joints_deg"][:-1], joints, rtol=0, atol=1e-7)
    # And each row is that pose's ik solution of the same branch.
    one = robcal.ik(robot, poses["position_mm"][7], poses["quaternion_wxyz"][7])
    mine = [s for s in one["solutions"] if s["config"] == r["config"][7]]
    assert min(np.max(np.abs(s["joints_deg"] - r["joints_deg"][7])) for s in mine) < 1e-9
    with pytest.raises(robcal.InputError, match="N×3 positions"):
        robcal.ik_batch(robot, far[:, :2], quaternions)
