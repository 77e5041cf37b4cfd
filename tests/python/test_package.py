"""The installed package: version, shipped robot data, the located InputError, constructors from
files, dicts and arrays that agree with each other, and batched calls equal to row-by-row ones."""
import os
import re

import numpy as np
import pytest

import robcal

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
REF = os.path.join(ROOT, "tests", "data", "irb120-published")
TOOL = os.path.join(REF, "tool.yaml")


@pytest.mark.skipif("ROBCAL_INSTALLED" not in os.environ, reason="run by run_installed.sh")
def test_imports_the_installed_package_with_its_robot_data():
    installed = os.path.realpath(os.environ["ROBCAL_INSTALLED"])
    assert os.path.realpath(robcal.__file__).startswith(installed + os.sep)
    data = os.path.join(os.path.dirname(robcal.__file__), "data")
    assert os.environ["ROBCAL_DATA_DIR"] == data
    assert sorted(f[:-5] for f in os.listdir(os.path.join(data, "robots"))) == sorted(
        robcal.builtin_robots())


def test_version_is_the_projects():
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    assert robcal.__version__ == re.search(r"project\(robcal VERSION ([0-9.]+)", text).group(1)


def test_bad_input_raises_the_located_input_error():
    assert issubclass(robcal.InputError, ValueError)
    with pytest.raises(robcal.InputError) as e:
        robcal.Tool.from_dict({"targets": {"T1": [1, 2]}})
    assert e.value.file == "<dict>"
    assert "targets" in e.value.key and "<dict>" in str(e.value)
    bad = os.path.join(REF, "no-such-file.csv")
    with pytest.raises(robcal.InputError) as e:
        robcal.Measurements.from_file(bad, robcal.Tool.from_file(TOOL))
    assert e.value.file == bad


def test_tool_from_file_dict_and_arrays_agree():
    from_file = robcal.Tool.from_file(TOOL)
    targets = {name: list(p) for name, p in from_file.targets.items()}
    from_arrays = robcal.Tool(targets=targets, mass_kg=from_file.mass_kg, cog_mm=from_file.cog_mm)
    assert from_arrays.to_yaml() == from_file.to_yaml()
    assert "Tool targets" in repr(from_file)
    unknown = robcal.Tool(targets={"A": [0, 0, 10]}, unknown=["B"])
    assert unknown.unknown_targets == ["B"]
    with pytest.raises(robcal.InputError):
        robcal.Tool(targets={"A": [0, 0, 10]}, unknown=["A"])


def test_robot_from_dict_is_the_robot_file():
    robot = robcal.RobotModel.from_file("abb-irb120")
    import json
    # The robot file's YAML has only JSON-representable fields: load it as a dict through JSON.
    text = robot.to_yaml()
    import yaml  # python3-yaml, a test dependency of the Makefile's DEBIAN_PACKAGES
    d = json.loads(json.dumps(yaml.safe_load(text)))
    again = robcal.RobotModel.from_dict(d)
    assert again.to_yaml() == text


def test_calibrated_robot_from_dict_is_the_model_file(tmp_path):
    import json
    yaml = pytest.importorskip("yaml")
    tool = robcal.Tool.from_file(TOOL)
    rows = robcal.Measurements.from_file(os.path.join(REF, "calibration.csv"), tool)
    model = robcal.calibrate(robcal.load_robot("abb-irb120"), rows, level="kinematic").robot
    text = model.to_yaml()
    (tmp_path / "model.yaml").write_text(text)
    from_file = robcal.CalibratedRobot.from_file(str(tmp_path / "model.yaml"))
    again = robcal.CalibratedRobot.from_dict(json.loads(json.dumps(yaml.safe_load(text))))
    assert again.to_yaml() == from_file.to_yaml()  # the file's reader, on the dict
    assert again.level == model.level == "kinematic"
    for name, value in model.parameters.items():  # the file's 17 digits, in mm and deg
        assert again.parameters[name] == pytest.approx(value, rel=1e-14, abs=1e-12), name
    with pytest.raises(robcal.InputError, match="<dict>.*parameters"):
        robcal.CalibratedRobot.from_dict({"robot": {}})


def test_measurements_round_trip_through_dict_arrays_and_csv():
    tool = robcal.Tool.from_file(TOOL)
    rows = robcal.Measurements.from_file(os.path.join(REF, "calibration.csv"), tool)
    d = rows.to_dict()
    assert d["kind"] == "points" and d["joints_deg"].shape == (len(rows), 6)
    again = robcal.Measurements.from_dict(d, tool)
    arrays = robcal.Measurements.points(tool, d["joints_deg"], d["target"], d["position_mm"])
    assert again.to_csv() == arrays.to_csv()
    np.testing.assert_array_equal(again.to_dict()["position_mm"], d["position_mm"])
    np.testing.assert_array_equal(again.to_dict()["joints_deg"], d["joints_deg"])
    with pytest.raises(robcal.InputError, match="kind"):
        robcal.Measurements.from_dict({"kind": "lines"}, tool)


def test_calibration_from_objects_equals_calibration_from_files():
    tool = robcal.Tool.from_file(TOOL)
    rows = robcal.Measurements.from_file(os.path.join(REF, "calibration.csv"), tool)
    a = robcal.calibrate(robcal.load_robot("abb-irb120"), rows, level="full")
    b = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), level="full")
    assert a.rms_mm == b.rms_mm
    np.testing.assert_array_equal(a.parameter_table["value"], b.parameter_table["value"])
    assert "IdentificationResult" in repr(a.result) and "converged" in repr(a.result)
    assert repr(a).startswith("<Calibration ABB IRB 120: rms ") and "PROBLEMS" not in repr(a)
    html = a._repr_html_()
    assert html.count("<tr>") == len(a.parameters) + 1 and "link3.d" in html


def test_covariance_and_parameter_table_agree():
    result = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"), level="full")
    table = result.parameter_table
    cov = result.covariance
    names = result.identified_names
    assert cov.shape == (len(names), len(names)) and len(names) == result.identified_count
    np.testing.assert_allclose(cov, cov.T, rtol=0, atol=1e-15 * np.abs(cov).max())
    # The reported standard deviations are the square roots of the covariance's diagonal, in the
    # same external units (mm, deg).
    index = {n: i for i, n in enumerate(table["name"])}
    std = np.array([table["std"][index[n]] for n in names])
    np.testing.assert_allclose(np.sqrt(np.diag(cov)), std, rtol=1e-9)
    identified = [s == "identified" for s in table["status"]]
    assert sum(identified) == len(names)


def test_batched_kinematics_equal_row_by_row():
    robot = robcal.load_robot("abb-irb120")
    rng = np.random.default_rng(3)
    joints = rng.uniform(-90, 90, size=(25, 6))
    batch = robcal.fk_batch(robot, joints)
    for q, p, quat in zip(joints, batch["position_mm"], batch["quaternion_wxyz"]):
        one = robcal.fk(robot, q)
        np.testing.assert_array_equal(one["position_mm"], p)
        np.testing.assert_array_equal(one["quaternion_wxyz"], quat)
    result = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"))
    model = result.robot
    point = model.targets["1"]
    many = model.positions(joints, point)
    for q, p in zip(joints, many):
        np.testing.assert_array_equal(model.position(q, point), p)


def test_batched_compensation_equals_row_by_row(tmp_path):
    result = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"))
    path = str(tmp_path / "model.yaml")
    result.save(path)
    comp = robcal.Compensator.from_model(path)
    joints = np.array([[10, 20, 30, 40, 50, 60], [-20, 10, 5, 0, 30, 0], [0, 0, 0, 0, 90, 0.0]])
    poses = comp.tcp_poses(joints)
    for q, p in zip(joints, poses["position_mm"]):
        np.testing.assert_array_equal(comp.tcp_pose(q)["position_mm"], p)
    config = comp.config_of(joints[0])
    solved = comp.solve_batch(poses["position_mm"], poses["quaternion_wxyz"], config)
    for r, ok in enumerate(solved["ok"]):
        one = comp.solve(poses["position_mm"][r], poses["quaternion_wxyz"][r], config)
        assert one["ok"] == ok
        if ok:
            np.testing.assert_array_equal(one["joints_deg"], solved["joints_deg"][r])
        else:
            assert np.isnan(solved["joints_deg"][r]).all()
    # The first row was made from joints in `config`: solving its pose gives those joints back.
    assert solved["ok"][0]
    np.testing.assert_allclose(solved["joints_deg"][0], joints[0], atol=1e-6)
