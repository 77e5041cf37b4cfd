"""Measurement files and validation statistics from Python (mirrors tests/test_validate.cpp)."""
import itertools
import math
import pathlib

import numpy as np
import pytest

import robcal._robcal as rc

DATA = pathlib.Path(__file__).resolve().parents[1] / "data" / "irb120-published"
TOOL = str(DATA / "tool.yaml")


def test_read_points_file():
    m = rc.read_measurements(str(DATA / "validation.csv"), TOOL)
    assert m["kind"] == "points"
    assert m["joints_deg"].shape == (1000, 6)
    assert m["position_mm"].shape == (1000, 3)
    assert set(m["target"]) == {"1", "2", "3"}
    assert m["warnings"] == []
    # Same numbers as the file itself (joints come back in degrees).
    first = (DATA / "validation.csv").read_text().splitlines()[1].split(",")
    assert m["config"][0] == first[0]
    np.testing.assert_allclose(m["joints_deg"][0], [float(v) for v in first[2:8]], rtol=1e-15)
    np.testing.assert_array_equal(m["position_mm"][0], [float(v) for v in first[8:11]])


def test_bad_file_raises_value_error_with_line_and_column(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("config,target,j1,j2,j3,j4,j5,j6,x,y,z\n1,9,0,0,0,0,0,0,1,2,3\n")
    with pytest.raises(ValueError, match=r"bad.csv:2:2 \(target\): unknown target '9'"):
        rc.read_measurements(str(bad), TOOL)


def test_error_statistics_by_hand():
    s = rc.error_statistics([1.0, 2.0, 3.0, 4.0])
    assert s["count"] == 4
    assert s["mean_mm"] == 2.5
    assert s["std_mm"] == pytest.approx(math.sqrt(1.25), abs=1e-15)
    assert s["mean_plus_3std_mm"] == pytest.approx(2.5 + 3 * math.sqrt(1.25), abs=1e-15)
    assert (s["min_mm"], s["max_mm"]) == (1.0, 4.0)
    assert rc.error_statistics([0.5, 1.5], unit="deg") == {
        "count": 2, "mean_deg": 1.0, "std_deg": 0.5, "mean_plus_3std_deg": 2.5,
        "min_deg": 0.5, "max_deg": 1.5}


def test_pairwise_matches_naive_loop_and_is_thread_independent():
    rng = np.random.default_rng(4)
    measured = rng.uniform(-800, 800, (200, 3))
    modelled = measured * 1.0003 + rng.normal(0, 0.05, (200, 3))
    naive = [
        abs(np.linalg.norm(measured[i] - measured[j]) - np.linalg.norm(modelled[i] - modelled[j]))
        for i, j in itertools.combinations(range(200), 2)
    ]
    one = rc.pairwise_distance_errors(measured, modelled, threads=1)
    two = rc.pairwise_distance_errors(measured, modelled, threads=2)
    assert one == two
    assert one["pairs"] == len(naive) == 200 * 199 // 2
    # Each pair error is good to a relative 3e-7 (single-precision denominator).
    assert one["mean_mm"] == pytest.approx(np.mean(naive), rel=3e-7)
    assert one["std_mm"] == pytest.approx(np.std(naive), abs=6e-7 * np.mean(naive))
    assert one["max_mm"] == pytest.approx(max(naive), rel=3e-7)
    assert sum(one["histogram"]["counts"]) == one["pairs"]
    assert one["histogram"]["upper"] >= max(naive)
    with pytest.raises(ValueError):
        rc.pairwise_distance_errors(measured[:, :2], modelled[:, :2])


def test_validate_nominal_robot_with_fitted_base():
    with pytest.raises(ValueError, match="no world frame"):
        rc.validate("abb-irb120", TOOL, str(DATA / "validation.csv"))
    r = rc.validate("abb-irb120", TOOL, str(DATA / "validation.csv"), fit_base=True)
    assert r["points"] == 1000
    errors = np.array(r["position_errors_mm"])
    assert r["position_error_mm"]["mean_mm"] == pytest.approx(errors.mean(), abs=1e-12)
    assert r["position_error_mm"]["std_mm"] == pytest.approx(errors.std(), abs=1e-12)
    assert 0.8 < r["position_error_mm"]["mean_mm"] < 3.5  # docs/method/11-published-results.md: 1–5 mm before calibration
    assert [t["target"] for t in r["per_target"]] == ["1", "2", "3"]
    assert r["distance_error_mm"]["pairs"] == 499500


def test_validate_takes_units_and_euler_like_calibrate(tmp_path):
    mm = rc.validate("abb-irb120", TOOL, str(DATA / "validation.csv"), fit_base=True)
    lines = (DATA / "validation.csv").read_text().splitlines()
    metres = [lines[0]]
    for line in lines[1:]:
        f = line.split(",")
        metres.append(",".join(f[:8] + [repr(float(v) / 1000) for v in f[8:11]]))
    path = tmp_path / "validation_m.csv"
    path.write_text("\n".join(metres) + "\n")
    m = rc.validate("abb-irb120", TOOL, str(path), fit_base=True, units="m")
    assert m["position_error_mm"]["mean_mm"] == pytest.approx(mm["position_error_mm"]["mean_mm"],
                                                           abs=1e-9)
    with pytest.raises(rc.InputError, match="--euler: 'ZZY' is not a rotation order"):
        rc.validate("abb-irb120", TOOL, str(path), fit_base=True, units="m", euler="ZZY")
