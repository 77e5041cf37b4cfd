"""The ballbar hexapod from Python: the same checks as the C++ tests (round trip, Tri hand case,
pose count, uncertainty against Monte Carlo, world frame, ill-posed input)."""
import math

import numpy as np
import pytest

import robcal

hexapod = robcal._robcal.hexapod


def rotation(axis, angle):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def test_tripod_hand_case():
    up = hexapod.tripod([0, 0, 0], [4, 0, 0], [0, 4, 0], 3.0, math.sqrt(17), 3.0, 1)
    down = hexapod.tripod([0, 0, 0], [4, 0, 0], [0, 4, 0], 3.0, math.sqrt(17), 3.0, -1)
    np.testing.assert_allclose(up, [1, 2, 2], atol=1e-12)
    np.testing.assert_allclose(down, [1, 2, -2], atol=1e-12)
    assert hexapod.tripod([0, 0, 0], [4, 0, 0], [0, 4, 0], 1.0, 1.0, 1.0, 1) is None


def test_dkp_round_trip_finds_the_pose():
    base_sides = [305.0, 296.0, 301.0]
    tool_sides = [151.0, 148.0, 152.0]
    base = hexapod.triangle_from_sides(base_sides)
    tool_local = hexapod.triangle_from_sides(tool_sides)
    tool = tool_local @ rotation([1, -2, 0.5], 2.4).T + np.array([120.0, 90.0, 260.0])
    legs = hexapod.leg_lengths(base, tool)
    solutions = hexapod.solve_dkp(base_sides, tool_sides, legs)
    errors = [np.abs(cups - tool).max() for cups in solutions.values()]
    assert min(errors) < 1e-9
    assert sorted(errors)[1] > 1.0  # the other modes are other poses


def test_ill_posed_legs_raise():
    with pytest.raises(ValueError, match="ρ11"):
        hexapod.solve_dkp([300, 300, 300], [150, 150, 150], [100, 300, 100, 300, 300, 100])
    with pytest.raises(ValueError, match="triangle inequality"):
        hexapod.triangle_from_sides([300, 100, 150])


def test_seventy_two_poses_every_leg_at_300():
    poses = hexapod.enumerate_poses()
    assert len(poses) == 72
    assert sorted({p["mode"] for p in poses}) == [1, 2, 3, 4]
    assert len(hexapod.enumerate_poses(angle_deg=60, distance_mm=100)) < 72


def test_uncertainty_analytic_matches_monte_carlo():
    modes = hexapod.uncertainty(samples=20000, seed=5)
    assert [m["mode"] for m in modes] == [1, 2, 3, 4]
    for m in modes:
        np.testing.assert_allclose(m["monte_carlo_norm_sigma"], m["norm_sigma"], rtol=0.02)
        np.testing.assert_allclose(
            m["norm_sigma"], np.sqrt((m["sensitivity"] ** 2).reshape(3, 3, 12).sum(axis=(1, 2))))
    worst = max(m["norm_sigma"].max() for m in modes)
    assert 2.5 < worst < 4.0  # published: about 3.2 σ


def test_world_frame_keeps_the_measured_triangle_closest_to_the_robot_points():
    sides = [300.004, 299.991, 300.012]
    q = hexapod.triangle_from_sides(sides)
    moved = q @ rotation([1, 2, 0.5], 0.3).T + np.array([450.0, -120.0, 80.0])
    fit = hexapod.fit_world_frame(moved, sides)
    assert fit["converged"]
    assert fit["rms_mm"] < 1e-9
    np.testing.assert_allclose(fit["corrected"], moved, atol=1e-9)
    # Robot points off by a few tenths: the corrected triangle keeps the ballbar's sides.
    noisy = moved + np.array([[0.2, -0.1, 0.0], [-0.1, 0.05, 0.02], [0.0, 0.1, -0.03]])
    fit = hexapod.fit_world_frame(noisy, sides)
    c = fit["corrected"]
    measured = [np.linalg.norm(c[0] - c[1]), np.linalg.norm(c[1] - c[2]), np.linalg.norm(c[2] - c[0])]
    np.testing.assert_allclose(measured, sides, atol=1e-9)
    assert 0 < fit["rms_mm"] < 0.3


def test_published_54_poses_at_30_degrees_and_50_mm():
    # Tool cups numbered to face the base in every assembly mode (docs/method/07-hexapod.md §3):
    # 18 disjoint pairs are 8.3° and 12 mm apart, so the published rule (30°, 50 mm) keeps
    # 72 − 18 = 54; no other pair is within 30° and 50 mm.
    assert len(hexapod.enumerate_poses(angle_deg=30.0, distance_mm=50.0)) == 54
    assert len(hexapod.enumerate_poses(angle_deg=8.0, distance_mm=1e6)) == 72
    assert len(hexapod.enumerate_poses(angle_deg=30.0, distance_mm=10.0)) == 72


def test_place_ranks_unreachable_last_and_pairs_beat_their_members():
    r = hexapod.place(x_mm=[1500, 450], y_mm=[-200, 200], z_mm=[300], validation=200, best=4)
    ranked = r["ranked"]
    assert [p["configurations"] for p in ranked if p["placement"].startswith("1500")] == [0, 0]
    assert ranked[0]["configurations"] > 0 and ranked[0]["undetermined"] == 0
    for pair in r["pairs"]:
        a, b = (ranked[i - 1]["predicted_mean_mm"] for i in pair["ranks"])
        assert pair["predicted_mean_mm"] < min(a, b)


def test_place_next_after_a_measured_placement(tmp_path):
    plan = hexapod.plan("fanuc-lrmate200ic", placement=(450, 200, 300, 0))
    plan.save(str(tmp_path / "a.json"))
    r = hexapod.place(x_mm=[350, 450], y_mm=[-200, 200], z_mm=[300], validation=200, best=3,
                      measured=[str(tmp_path / "a.json")])
    assert r["measured"]["configurations"] == len(plan)
    assert all(n["placement"] != "450,200,300,0" for n in r["next"])  # overlapping: left out
    assert r["next"][0]["predicted_mean_mm"] < r["measured"]["predicted_mean_mm"]
    with pytest.raises(robcal.InputError, match="overlaps the one of"):
        hexapod.place(measured=[str(tmp_path / "a.json")] * 2)


def test_device_validation_scatter_matches_gum():
    modes = hexapod.device_validation(poses=1000, reference_sigma_mm=0.001, seed=3)["modes"]
    assert [m["mode"] for m in modes] == [1, 2, 3, 4]
    for m in modes:
        assert abs(m["centroid_vs_truth_mm"] / m["centroid_gum_mm"] - 1) < 0.05
        assert abs(m["centroid_vs_reference_mm"] / m["centroid_predicted_mm"] - 1) < 0.05


@pytest.mark.parametrize("kwargs, fragment", [
    (dict(leg_mm=-300.0), "--leg-mm: expected a positive length"),
    (dict(leg_mm=float("nan")), "--leg-mm: expected a positive length"),
    (dict(base_sides_mm=(300, 100, 100)), "--base-mm: sides d12 = 300"),
    (dict(tool_sides_mm=(10, 10, 30)), "--tool-mm: sides d12 = 10"),
])
def test_plan_and_place_check_the_geometry_as_the_cli_does(kwargs, fragment):
    # The library's check_geometry, which `robcal hexapod plan/place` call too.
    with pytest.raises(robcal.InputError, match=fragment):
        hexapod.plan("fanuc-lrmate200ic", **kwargs)
    with pytest.raises(robcal.InputError, match=fragment):
        hexapod.place(x_mm=[450], y_mm=[0], z_mm=[300], validation=200, **kwargs)
