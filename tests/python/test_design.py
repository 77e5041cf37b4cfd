"""Configuration design from Python: indices on a hand-computed case, selection quality."""
import numpy as np
import pytest

import robcal


def test_indices_of_a_diagonal_jacobian():
    o = robcal._robcal.observability_indices(np.diag([1.0, 2.0, 4.0]), 1)
    assert o["O1"] == pytest.approx(2.0)
    assert o["O2"] == pytest.approx(0.25)
    assert o["O3"] == pytest.approx(1.0)
    assert o["O4"] == pytest.approx(0.25)
    assert o["O5"] == pytest.approx(4.0 / 7.0)


def test_d_optimal_beats_random_subsets():
    rng = np.random.default_rng(3)
    # 400 candidates of 3 rows over 8 parameters, with very unequal information.
    rows = rng.normal(size=(1200, 8)) * np.repeat(rng.uniform(0.1, 2.0, 400), 3)[:, None]
    chosen = robcal._robcal.select_d_optimal(rows, 3, 12)
    assert len(set(chosen)) == 12
    stacked = lambda s: np.vstack([rows[3 * i:3 * i + 3] for i in s])
    o1 = robcal._robcal.observability_indices(stacked(chosen), 12)["O1"]
    for _ in range(10):
        random = rng.choice(400, 12, replace=False)
        assert o1 > robcal._robcal.observability_indices(stacked(random), 12)["O1"]
    assert robcal._robcal.d_efficiency(rows, 3, chosen) > 0.9


def test_restarts_never_lower_the_determinant():
    rng = np.random.default_rng(5)
    rows = rng.normal(size=(600, 6)) * np.repeat(rng.uniform(0.1, 2.0, 200), 3)[:, None]
    stacked = lambda s: np.vstack([rows[3 * i:3 * i + 3] for i in s])
    log_det = lambda s: np.linalg.slogdet(stacked(s).T @ stacked(s))[1]
    single = robcal._robcal.select_d_optimal(rows, 3, 8, restarts=0)
    for seed in (1, 2, 3):
        restarted = robcal._robcal.select_d_optimal(rows, 3, 8, restarts=4, seed=seed)
        assert len(set(restarted)) == 8
        # The first descent is among those compared, so restarts can only keep or improve it
        # (up to the selection's ridge of 1e-6 on a unit-scaled matrix).
        assert log_det(restarted) >= log_det(single) - 1e-5


def test_bad_input_raises_value_error():
    with pytest.raises(ValueError):
        robcal._robcal.select_d_optimal(np.ones((10, 3)), 3, 2)


def test_plan_returns_joint_arrays_and_selects_among_given_ones():
    task_box = "-500,-300,1100,1300,150,350"
    r = robcal.plan(count=10, candidates=300, task_count=40, task_box=task_box)
    assert r["joints_deg"].shape == (10, 6)
    assert r["criterion"] == "I-optimal"
    assert r["near_edge"]["selected"] <= r["near_edge"]["limit"] == 2
    e = r["predicted_error_mm"]
    assert 0 < e["selected"]["mean_mm"] < e["random"]["mean_mm"]
    # Among the user's configurations: every chosen row is one of them.
    given = robcal.plan(count=30, candidates=300, criterion="d", task_count=40)["joints_deg"]
    chosen = robcal.plan(count=12, candidate_joints_deg=given, criterion="d", task_count=40)
    assert chosen["candidates"] == 30
    for row in chosen["joints_deg"]:
        assert np.min(np.max(np.abs(given - row), axis=1)) < 1e-9
    with pytest.raises(robcal.InputError, match="--criterion|criterion"):
        robcal.plan(count=12, criterion="x")


def test_plan_for_backlash_varies_the_approach_sides():
    r = robcal.plan(count=30, candidates=600, identify=["backlash"], task_count=40)
    assert r["approach"] == "varied" and r["identify"] == ["backlash"]
    assert len(r["approach_sides"]) == 30 and all(len(s) == 6 for s in r["approach_sides"])
    assert any("-" in s for s in r["approach_sides"])
    assert "joint1.backlash" not in r["dropped"]
    below = robcal.plan(count=30, candidates=600, identify=["backlash"], approach="below",
                        task_count=40)
    assert set(below["approach_sides"]) == {"++++++"}
    assert "joint1.backlash" in below["dropped"]
    with pytest.raises(robcal.InputError, match="payloads"):
        robcal.plan(count=12, payloads="varied")
