"""Compensation from Python: calibrated IK round trips on the reference truth (a calibrated
IRB 120 with compliance) and program filtering, mirroring tests/test_compensate*.cpp."""
import os
import pathlib

import numpy as np
import pytest

import robcal

ROOT = pathlib.Path(__file__).resolve().parents[2]
TRUTH = ROOT / "tests/data/irb120-published/truth.yaml"
PROGRAMS = ROOT / "tests/data/programs"


def angle_deg(qa, qb):
    """Rotation angle between two unit quaternions (w, x, y, z), accurate near zero."""
    w = float(np.dot(qa, qb))
    v = qa[0] * qb[1:] - qb[0] * qa[1:] - np.cross(qa[1:], qb[1:])
    return np.degrees(2 * np.arctan2(np.linalg.norm(v), abs(w)))


@pytest.fixture(scope="module")
def truth():
    return robcal.Compensator.from_truth(str(TRUTH))


def test_round_trip_both_methods(truth):
    rng = np.random.default_rng(7)
    solved = 0
    for _ in range(200):
        joints = rng.uniform([-90, 0, -60, -150, 15, -180], [90, 90, 50, 150, 100, 180])
        pose = truth.tcp_pose(joints)
        config = truth.config_of(joints)
        a = truth.solve(pose["position_mm"], pose["quaternion_wxyz"], config, joints)
        b = truth.solve(pose["position_mm"], pose["quaternion_wxyz"], config, joints, "pose-shift")
        if not a["ok"]:
            continue  # the nominal seed of a pose near a joint limit may lie beyond it
        assert b["ok"], b["status"]
        solved += 1
        for r in (a, b):
            reached = truth.tcp_pose(r["joints_deg"])
            assert np.linalg.norm(reached["position_mm"] - pose["position_mm"]) < 1e-6
            assert angle_deg(reached["quaternion_wxyz"], pose["quaternion_wxyz"]) < 1e-6
        np.testing.assert_allclose(a["joints_deg"], joints, atol=1e-6)
        np.testing.assert_allclose(a["joints_deg"], b["joints_deg"], atol=1e-6)
        # The nominal target is what the nominal model puts at the corrected joints.
        nominal = truth.nominal_tcp_pose(a["joints_deg"])
        np.testing.assert_allclose(a["nominal_target"]["position_mm"], nominal["position_mm"], atol=1e-9)
    assert solved > 150


def test_unreachable_is_a_status(truth):
    r = truth.solve(np.array([5000.0, 0, 0]), np.array([1.0, 0, 0, 0]), "front-up-noflip")
    assert not r["ok"]
    assert "no nominal solution" in r["status"]
    with pytest.raises(ValueError):
        truth.solve(np.zeros(3), np.array([1.0, 0, 0, 0]), "sideways")


def test_nominal_model_leaves_programs_unchanged(tmp_path):
    nominal = robcal.Compensator.nominal("abb-irb120")
    out = tmp_path / "out.mod"
    counts = nominal.compensate_program(str(PROGRAMS / "pick_place.mod"), str(out), joints=True)
    assert (counts["cartesian_points"], counts["joint_points"]) == (6, 2)
    assert counts["uncorrected"] == [] and counts["language"] == "rapid"
    assert out.read_bytes() == (PROGRAMS / "pick_place.mod").read_bytes()


def test_calibrated_model_changes_only_point_lines(tmp_path, truth):
    src = PROGRAMS / "pick_place.mod"
    out = tmp_path / "out.mod"
    truth.compensate_program(str(src), str(out))
    before = src.read_text().splitlines()
    after = out.read_text().splitlines()
    assert len(before) == len(after)
    changed = [i + 1 for i, (a, b) in enumerate(zip(before, after)) if a != b]
    assert changed == [5, 6, 7, 9, 10, 20]
    points = robcal.read_program_points(out.read_text(), "rapid")
    assert [p["name"] for p in points] == ["pHome", "pPick", "pPlace", "pPath{1}", "pPath{2}", ""]


def test_read_krl_points():
    points = robcal.read_program_points((PROGRAMS / "weld_seam.dat").read_text(), "krl", joints=True)
    assert [p["name"] for p in points] == ["XP1", "XP2", "PAPPROACH", "XHOME", "XSEAM[1]"]
    assert points[0]["config"] == [2, 10]
    np.testing.assert_allclose(points[3]["joints_deg"], [0, -90, 90, 0, 0, 0])
