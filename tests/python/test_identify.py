"""Identification from Python: the reference data set from files and from arrays, the model
file round trip, cross-validation, and bad input as ValueError."""
import csv
import os

import numpy as np
import pytest

import robcal

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
REF = os.path.join(ROOT, "tests", "data", "irb120-published")
TOOL = os.path.join(REF, "tool.yaml")


def read_points(name):
    with open(os.path.join(REF, name)) as f:
        rows = list(csv.DictReader(f))
    joints = np.array([[float(r[f"j{i}"]) for i in range(1, 7)] for r in rows])
    targets = [r["target"] for r in rows]
    positions = np.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in rows])
    return joints, targets, positions


def mean_validation_error(robot):
    joints, targets, positions = read_points("validation.csv")
    errors = [np.linalg.norm(robot.position(q, robot.targets[t]) - p)
              for q, t, p in zip(joints, targets, positions)]
    return float(np.mean(errors)), float(np.max(errors))


def test_full_calibration_from_files_reaches_the_independent_fit():
    result = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), level="full")
    assert result.status.converged
    assert result.identified_count == 30
    dropped = [p for p in result.parameters if p.status == "dropped"]
    assert [p.name for p in dropped] == ["link3.d"]
    assert "link2.d" in dropped[0].reason
    mean, worst = mean_validation_error(result.robot)
    # Independent fit (README of the data set): 0.0343 mean, 0.0812 max.
    assert mean == pytest.approx(0.0343, abs=5e-4)
    assert worst == pytest.approx(0.0812, abs=1e-3)


def test_calibration_from_arrays_matches_the_file_path():
    joints, targets, positions = read_points("calibration.csv")
    from_arrays = robcal.calibrate_points("abb-irb120", TOOL, joints, targets, positions, level="kinematic")
    from_file = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), level="kinematic")
    a, b = from_arrays.robot.parameters, from_file.robot.parameters
    assert max(abs(a[k] - b[k]) for k in a) < 1e-9
    mean, _ = mean_validation_error(from_arrays.robot)
    assert mean == pytest.approx(0.436, abs=2e-3)  # independent fit: 0.436 (no compliance)


def test_saved_model_loads_back(tmp_path):
    result = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), level="base")
    path = str(tmp_path / "model.yaml")
    result.save(path)
    robot = robcal.load_calibrated_robot(path)
    assert robot.level == "base"
    assert robot.base_fitted
    for name, value in result.robot.parameters.items():
        assert robot.parameters[name] == pytest.approx(value, abs=1e-12)
    mean, _ = mean_validation_error(robot)
    assert mean == pytest.approx(1.394, abs=2e-3)  # independent fit: 1.394


def test_cross_validation_gives_held_out_errors():
    cv = robcal.cross_validate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), folds=5)
    assert len(cv["errors_mm"]) == 60
    assert 0.02 < cv["mean_mm"] < 0.06


def test_bad_input_is_a_value_error():
    joints, targets, positions = read_points("calibration.csv")
    with pytest.raises(ValueError, match="too few measurements"):
        robcal.calibrate_points("abb-irb120", TOOL, joints[:5], targets[:5], positions[:5])
    with pytest.raises(ValueError, match="matches no parameter"):
        robcal.calibrate_points("abb-irb120", TOOL, joints, targets, positions, fix=["nothing.*"])
    with pytest.raises(ValueError, match="no target 'X'"):
        robcal.calibrate_points("abb-irb120", TOOL, joints, ["X"] * len(targets), positions)
    with pytest.raises(ValueError, match="unknown level"):
        robcal.calibrate_points("abb-irb120", TOOL, joints, targets, positions, level="all")
    with pytest.raises(ValueError):
        robcal.load_calibrated_robot(os.path.join(REF, "tool.yaml"))


def test_another_robots_model_is_refused_unless_forced(tmp_path):
    # The IRB 1600's model on the IRB 120's data: the CLI's guards, not a silent save.
    run = robcal.calibrate("abb-irb1600-6-12", TOOL, os.path.join(REF, "calibration.csv"))
    assert run.problems, "another robot's model passed as plausible"
    assert "check the robot (--robot: is it this arm's model?)" in run.problems[0]
    # The wrong arm's full model absorbs much, yet fits worse than the IRB 120's own (0.0338 mm).
    assert run.rms_mm > 2 * 0.0338
    assert "PROBLEMS" in repr(run)
    path = tmp_path / "other_arm.yaml"
    with pytest.raises(robcal.InputError, match="not written: the fit is not trustworthy"):
        run.save(str(path))
    assert not path.exists()
    run.save(str(path), force=True)
    assert "problems:" in path.read_text()  # the forced model records why it is not trusted


def test_result_carries_warnings_noise_test_and_per_row_residuals():
    data = os.path.join(REF, "calibration.csv")
    run = robcal.calibrate("abb-irb120", TOOL, data, sigma=0.001)
    r = run.result
    # Per-row residuals: their mean, RMS and maximum are the result's.
    rows = sum(1 for _ in open(data)) - 1
    assert r.residuals.shape == (rows,)
    assert float(np.mean(r.residuals)) == pytest.approx(r.mean_mm, rel=1e-12)
    assert float(np.sqrt(np.mean(r.residuals ** 2))) == pytest.approx(r.rms_mm, rel=1e-12)
    assert float(np.max(r.residuals)) == pytest.approx(r.max_mm, rel=1e-12)
    # 1 µm is far below the tracker's noise: the χ² test fails and the misfit is cross-validated.
    t = r.noise_test
    assert t.tested and not t.consistent and t.instrument_sigma_mm == 0.001
    assert t.chi_square == pytest.approx(r.sigma_mm ** 2 * t.dof / 0.001 ** 2, rel=1e-9)
    cv = run.cross_validation
    assert cv["run_because_of_misfit"] and cv["folds"] == 5
    assert cv["mean_mm"] == pytest.approx(float(np.mean(cv["errors_mm"])), rel=1e-12)
    assert isinstance(run.warnings, list)
    with pytest.raises(robcal.InputError, match="--sigma"):
        robcal.calibrate("abb-irb120", TOOL, data, sigma=-1)
