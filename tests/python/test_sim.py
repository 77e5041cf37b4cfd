"""Virtual instruments and the simulator from Python: the same statistics as the C++ tests."""
import math

import numpy as np
import pytest

import robcal


def test_tracker_noise_matches_sigma():
    tracker = robcal.LaserTracker()
    tracker.sigma_mm = np.array([0.02, 0.05, 0.07])
    truth = np.array([1000.0, 200.0, 300.0])
    readings = robcal.read_points(tracker, truth, 20000, 7)
    errors = readings - truth
    assert readings.shape == (20000, 3)
    np.testing.assert_allclose(errors.std(axis=0, ddof=1) / tracker.sigma_mm, 1.0, atol=0.03)
    assert np.all(np.abs(errors.mean(axis=0)) < 4 * tracker.sigma_mm / math.sqrt(20000))
    # Seeded: the same seed gives the same readings.
    np.testing.assert_array_equal(readings, robcal.read_points(tracker, truth, 20000, 7))


def test_smr_cone_edge():
    tracker = robcal.LaserTracker()
    tracker.position_mm = np.array([2000.0, 0.0, 0.0])
    for angle, visible in [(0, True), (29.9, True), (30.1, False), (180, False)]:
        a = math.radians(angle)
        axis = np.array([math.cos(a), math.sin(a), 0.0])
        assert robcal.smr_visible(tracker, np.zeros(3), axis) == visible, angle


def test_ballbar_window():
    ballbar = robcal.Ballbar()
    ballbar.nominal_length_mm = 300.0
    assert robcal.ballbar_readable(ballbar, 300.9)
    assert not robcal.ballbar_readable(ballbar, 301.1)
    assert ballbar.sigma_mm == pytest.approx(0.00051)


def test_negative_count_is_a_value_error():
    with pytest.raises(ValueError):
        robcal.read_points(robcal.LaserTracker(), np.zeros(3), -1, 1)


def test_simulated_readings_are_truth_plus_noise():
    exact = robcal.simulate("laser-tracker", "published", 200, 9, 0.0)
    noisy = robcal.simulate("laser-tracker", "published", 200, 9, 0.05)
    # Same seed: same configurations and targets; only the noise differs.
    np.testing.assert_array_equal(exact["joints_deg"], noisy["joints_deg"])
    assert exact["target"] == noisy["target"]
    errors = noisy["position_mm"] - exact["position_mm"]
    assert errors.shape == (200, 3)
    assert abs(errors.std(ddof=1) / 0.05 - 1) < 0.1
    # Joints within the published test ranges (docs/method/05-observability.md §2).
    assert np.all(exact["joints_deg"][:, 1] >= 0) and np.all(np.abs(exact["joints_deg"][:, 0]) <= 90)


def test_simulate_rejects_bad_arguments():
    with pytest.raises(ValueError):
        robcal.simulate("laser-tracker", "imagined", 5, 1, 0.0)
    with pytest.raises(ValueError):
        robcal.simulate("laser-tracker", "published", 0, 1, 0.0)
