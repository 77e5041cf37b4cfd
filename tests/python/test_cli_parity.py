"""The CLI and Python on the same inputs give the same numbers: both call the same library
functions, so the comparisons are exact up to the CLI's printed precision."""
import json
import os
import subprocess

import numpy as np
import pytest

import robcal

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
REF = os.path.join(ROOT, "tests", "data", "irb120-published")
TOOL = os.path.join(REF, "tool.yaml")
CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")


def cli_json(*args):
    out = subprocess.run([CLI, *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def test_fk_and_ik():
    robot = robcal.load_robot("abb-irb120")
    q = [10, 20, 30, 40, 50, 60]
    c = cli_json("fk", "--robot", "abb-irb120", "--joints", ",".join(map(str, q)))
    p = robcal.fk(robot, q)
    np.testing.assert_allclose(c["position_mm"], p["position_mm"], rtol=0, atol=1e-8)
    np.testing.assert_allclose(c["quaternion_wxyz"], p["quaternion_wxyz"], rtol=0, atol=1e-11)
    pose = [300, 100, 400, 0, 0, 1, 0]
    c = cli_json("ik", "--robot", "abb-irb120", "--pose", ",".join(map(str, pose)))
    p = robcal.ik(robot, pose[:3], pose[3:])
    assert c["method"] == p["method"]
    assert [s["config"] for s in c["solutions"]] == [s["config"] for s in p["solutions"]]
    for a, b in zip(c["solutions"], p["solutions"]):
        np.testing.assert_allclose(a["joints_deg"], b["joints_deg"], rtol=0, atol=1e-8)
    assert c["status"] == p["status"] == "solved" and c["robot"] == p["robot"]


def test_fk_euler_and_limits():
    robot = robcal.load_robot("kuka-kr6-r900-sixx")
    q = [10, -80, 95, 40, 50, 60]
    c = cli_json("fk", "--robot", "kuka-kr6-r900-sixx", "--joints", ",".join(map(str, q)))
    p = robcal.fk(robot, q, check_limits=True)
    assert list(c["euler_deg"]) == list(p["euler_deg"]) == ["A", "B", "C"]
    for label, value in c["euler_deg"].items():
        assert value == pytest.approx(p["euler_deg"][label], abs=1e-9)
    # The Euler angles are the quaternion's rotation (Z-Y-X, as KUKA writes A, B, C).
    a, b, cc = np.radians([p["euler_deg"][k] for k in "ABC"])
    w, x, y, z = p["quaternion_wxyz"]
    assert np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z)) == pytest.approx(a, abs=1e-12)
    assert np.arcsin(2 * (w * y - z * x)) == pytest.approx(b, abs=1e-12)
    assert np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y)) == pytest.approx(cc, abs=1e-12)
    outside = [10, 200, 30, 40, 50, 60]
    cli = subprocess.run([CLI, "fk", "--robot", "abb-irb120", "--joints",
                          ",".join(map(str, outside))], capture_output=True, text=True)
    assert cli.returncode == 2 and "J2=200.000 outside" in cli.stderr
    with pytest.raises(robcal.InputError, match="J2=200.000 outside"):
        robcal.fk(robcal.load_robot("abb-irb120"), outside, check_limits=True)
    robcal.fk(robcal.load_robot("abb-irb120"), outside)  # unchecked by default


def test_ik_unreachable_refused_when_required():
    robot = robcal.load_robot("abb-irb120")
    pose = [3000, 100, 400, 0, 0, 1, 0]
    cli = subprocess.run([CLI, "ik", "--robot", "abb-irb120", "--pose",
                          ",".join(map(str, pose))], capture_output=True, text=True)
    assert cli.returncode == 2 and "pose unreachable for ABB IRB 120" in cli.stderr
    with pytest.raises(robcal.InputError, match="pose unreachable for ABB IRB 120"):
        robcal.ik(robot, pose[:3], pose[3:], require_solution=True)
    assert robcal.ik(robot, pose[:3], pose[3:])["status"] == "unreachable"


def test_robots_and_robot_show():
    c = cli_json("robots")
    p = robcal.robot_catalogue()
    assert c == p and [r["name"] for r in p] == robcal.builtin_robots()
    c = cli_json("robot", "show", "fanuc-lrmate200ic")
    robot = robcal.load_robot("fanuc-lrmate200ic")
    p = robcal.robot_description(robot)
    assert c == p
    np.testing.assert_allclose(p["joint_limits_deg"], robot.joint_limits_deg, atol=1e-9)


def test_reidentify_base_on_a_calibrated_model(tmp_path):
    model = str(tmp_path / "model.yaml")
    cli_json("calibrate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements",
             os.path.join(REF, "calibration.csv"), "--level", "kinematic", "--out", model)
    moved = os.path.join(REF, "validation.csv")
    c = cli_json("calibrate", "--model", model, "--level", "base", "--measurements", moved,
                 "--out", str(tmp_path / "moved.yaml"))
    p = robcal.calibrate(None, None, moved, level="base", model=model)
    by_name = {u.name: u for u in p.parameters}
    assert c["reidentified"]["what"] == "base" and len(c["reidentified"]["values"]) == 6
    for v in c["reidentified"]["values"]:
        assert v["value"] == pytest.approx(by_name[v["name"]].value, rel=0, abs=1e-11)
        assert v["std"] == pytest.approx(by_name[v["name"]].std, rel=1e-12)
    # The saved model keeps the calibration and records the re-identification, as the CLI's.
    p.save(str(tmp_path / "saved.yaml"))
    saved = robcal.load_calibrated_robot(str(tmp_path / "saved.yaml"))
    assert saved.level == "kinematic"
    assert saved.parameters == robcal.load_calibrated_robot(str(tmp_path / "moved.yaml")).parameters


def test_calibrate_and_validate(tmp_path):
    model = str(tmp_path / "model.yaml")
    c = cli_json("calibrate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements",
                 os.path.join(REF, "calibration.csv"), "--out", model)
    p = robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv"))
    # The CLI prints these to 1e-9 mm.
    assert c["rms_mm"] == pytest.approx(p.rms_mm, rel=0, abs=5.1e-10)
    assert c["sigma_mm"] == pytest.approx(p.sigma_mm, rel=0, abs=5.1e-10)
    table = p.parameter_table
    assert [x["name"] for x in c["parameters"]] == table["name"]
    np.testing.assert_allclose([x["value"] for x in c["parameters"]], table["value"], rtol=1e-12,
                               atol=1e-12)
    np.testing.assert_allclose([x["std"] for x in c["parameters"]], table["std"], rtol=1e-12,
                               atol=1e-15)
    validation = os.path.join(REF, "validation.csv")
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", TOOL, "--model", model,
                 "--measurements", validation)
    p = robcal.validate("abb-irb120", TOOL, validation, model=model)
    assert same_document(c, p)


def test_hexapod_plan_is_the_same_file(tmp_path):
    out = str(tmp_path / "plan.json")
    c = cli_json("hexapod", "plan", "--robot", "fanuc-lrmate200ic", "--placement", "450,0,300,15",
                 "--table-z-mm", "-10", "--out", out)
    plan = robcal.hexapod.plan("fanuc-lrmate200ic", placement=(450, 0, 300, 15), table_z_mm=-10)
    assert json.loads(plan.to_json()) == c
    assert open(out).read() == plan.to_json()
    read = robcal.hexapod.read_plan(out)
    assert read.to_json() == plan.to_json()
    assert len(plan) == c["configurations_measurable"] == plan.joints_deg.shape[0]
    np.testing.assert_allclose(plan.joints_deg, [x["joints_deg"] for x in c["configurations"]],
                               rtol=0, atol=5e-7)
    assert "hexapod.Plan" in repr(plan)
    # The CLI's other cell options: tilt, gauge and cup diameter.
    c = cli_json("hexapod", "plan", "--placement", "450,0,300,0", "--tilt-deg", "15",
                 "--gauge-range-mm", "3", "--gauge-sigma-mm", "0.002", "--cup-diameter-mm", "40")
    tilted = robcal.hexapod.plan(placement=(450, 0, 300, 0), tilt_deg=15, gauge_range_mm=3,
                                 gauge_sigma_mm=0.002, cup_diameter_mm=40)
    assert json.loads(tilted.to_json()) == c
    assert tilted.to_json() != robcal.hexapod.plan(placement=(450, 0, 300, 0)).to_json()


def test_hexapod_setup_and_dkp():
    c = cli_json("hexapod", "setup", "--robot", "fanuc-lrmate200ic", "--placement", "450,0,300,0")
    p = robcal.hexapod.setup("fanuc-lrmate200ic", placement=(450, 0, 300, 0))
    assert c == p and [b["cup"] for b in p["setting_ball"]] == ["B1", "B2", "B3"]
    c = cli_json("hexapod", "setup", "--placement", "450,0,300,0", "--tilt-deg", "20")
    p = robcal.hexapod.setup(placement=(450, 0, 300, 0), tilt_deg=20)
    assert c == p
    # Tilted 20° about the placement's x axis (along B1 B2): B1 and B2 stay level, B3 rises by the
    # triangle's height times sin 20°; the cups stay 300 mm apart.
    b = np.array([x["ball_position_mm"] for x in p["setting_ball"]])
    for i, j in ((0, 1), (1, 2), (2, 0)):
        assert np.linalg.norm(b[i] - b[j]) == pytest.approx(300, abs=1e-6)
    assert b[0, 2] == pytest.approx(b[1, 2], abs=1e-9)
    assert b[2, 2] - b[0, 2] == pytest.approx(300 * np.sqrt(3) / 2 * np.sin(np.radians(20)),
                                              abs=1e-6)


def without_seconds(d):
    return {k: v for k, v in d.items() if k != "seconds"}


def test_simulation_studies(tmp_path):
    c = cli_json("montecarlo", "--runs", "30", "--validation", "150", "--seed", "4")
    p = robcal.montecarlo(runs=30, validation=150, seed=4)
    assert without_seconds(c) == p
    assert p["failed"] == 0 and 0.5 < p["ratio"] < 1.5
    c = cli_json("plan-study", "--counts", "15", "--seeds", "1", "--candidates", "200",
                 "--task-count", "30")
    p = robcal.plan_study(counts=[15], seeds=1, candidates=200, task_count=30)
    assert c == p
    c = cli_json("experiments", "--seed", "2", "--out", str(tmp_path))
    p = robcal.experiments(seed=2)
    assert without_seconds(c) == p
    with pytest.raises(robcal.InputError, match="--counts"):
        robcal.plan_study(counts=[0])


def test_plan_study_criterion_effects_cell_and_prior(tmp_path):
    cell = tmp_path / "cell.yaml"
    cell.write_text("format: robcal-cell\nname: parity cell\nrobot_base:\n"
                    "  position_mm: [-812.25, 1503.5, -95]\n  rotation_xyz_deg: [0.25, -0.4, -57]\n"
                    "instrument:\n  kind: laser-tracker\n  position_mm: [0, 0, 0]\n"
                    "  range_mm: [0, 35000]\n  cone_half_angle_deg: 30\nfloor_z_mm: -95\n")
    box = "-500,-300,1100,1300,150,350"
    c = cli_json("plan-study", "--counts", "20", "--seeds", "2", "--candidates", "300",
                 "--task-count", "40", "--task-box", box, "--criterion", "i", "--no-guard",
                 "--effects", "mass-error,backlash", "--cell", str(cell), "--prior-count", "30")
    p = robcal.plan_study(counts=[20], seeds=2, candidates=300, task_count=40, task_box=box,
                          criterion="i", guard=False, effects=["mass-error", "backlash"],
                          cell=str(cell), prior_count=30)
    assert c == p
    assert p["cell"] == "parity cell" and p["prior_count"] == 30 and len(p["misfit_mm"]) == 2
    o = p["rows"][0]["optimal"]
    assert o["predicted_rms_with_misfit_mm"] >= o["predicted_rms_mm"] > 0
    with pytest.raises(robcal.InputError, match="--criterion"):
        robcal.plan_study(counts=[20], criterion="published")
    with pytest.raises(robcal.InputError, match="unknown effect .gravity-waves."):
        robcal.plan_study(counts=[20], seeds=1, candidates=200, effects=["gravity-waves"])


def test_plan_misfit(tmp_path):
    out = str(tmp_path / "c.csv")
    c = cli_json("plan", "--count", "12", "--candidates", "300", "--task-count", "40",
                 "--misfit-mm", "0.04", "--out", out)
    p = robcal.plan(count=12, candidates=300, task_count=40, misfit_mm=0.04)
    # One serializer: Python's dict is the CLI's JSON, plus the chosen configurations as arrays.
    assert p.pop("out") == "" and c.pop("out") == out
    joints, targets = p.pop("joints_deg"), p.pop("targets")
    assert set(p.pop("approach_sides")) == {"++++++"} and set(p.pop("payload_names")) == {""}
    assert c == p
    csv = np.loadtxt(out, delimiter=",", skiprows=1, usecols=range(2, 8), comments="#")
    np.testing.assert_allclose(joints, csv, rtol=0, atol=1e-6)
    assert len(targets) == 12
    w = p["predicted_error_with_misfit_mm"]
    assert w["selected"]["rms_mm"] == pytest.approx(
        np.hypot(p["predicted_error_mm"]["selected"]["rms_mm"], 0.04), abs=2e-6)
    assert "predicted_error_with_misfit_mm" not in robcal.plan(count=12, candidates=300,
                                                               task_count=40)


def test_hexapod_simulate():
    c = cli_json("hexapod", "simulate", "--seed", "3", "--validation", "300", "--no-leg-fit")
    p = robcal.hexapod.simulate(seed=3, validation=300, leg_fit=False)
    assert c == p
    assert p["final"]["validation"]["absolute"]["mean_mm"] < p["nominal"]["absolute"]["mean_mm"]
    with pytest.raises(robcal.InputError, match="--validation"):
        robcal.hexapod.simulate(validation=1)


def test_report(tmp_path):
    model = str(tmp_path / "model.yaml")
    robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv")).save(model)
    validation = os.path.join(REF, "validation.csv")
    calibration = os.path.join(REF, "calibration.csv")
    try:
        c = cli_json("report", "--model", model, "--measurements", validation, "--calibration",
                     calibration, "--out", str(tmp_path / "cli.html"))
    except subprocess.CalledProcessError as e:
        if "Chart.js" in e.stderr:
            pytest.skip("Chart.js (libjs-chart.js) is not installed")
        raise
    p = robcal.report(model, [validation], calibration=calibration,
                      out=str(tmp_path / "py.html"))
    assert p.pop("warnings") == []
    # Who ran the report and when differ by design (command line, date); what was read may not.
    cp, pp = c.pop("provenance"), p.pop("provenance")
    for key in ("files", "robot", "level", "robcal_version"):
        assert cp.get(key) == pp.get(key), key
    assert c == p
    written = json.load(open(tmp_path / "py.json"))
    written.pop("provenance")
    assert written == c
    with pytest.raises(robcal.InputError, match="--out"):
        robcal.report(model, [validation], out=str(tmp_path / "x.txt"))


def test_hexapod_replan(tmp_path):
    s1 = tmp_path / "s1"
    s1.mkdir()
    run = lambda *a: subprocess.run([CLI, *a], check=True, capture_output=True, text=True)  # noqa
    plan = robcal.hexapod.plan("fanuc-lrmate200ic", placement=(450, 0, 300, 0))
    plan.save(str(s1 / "plan.json"))
    run("hexapod", "simulate-readings", "--plan", str(s1 / "plan.json"), "--seed", "5", "--out",
        str(tmp_path / "r1.txt"), "--tool-out", str(tmp_path / "tool.yaml"))
    # The file's plan (joints to 1e-6°), as the CLI reads it.
    sim = robcal.hexapod.simulate_readings(robcal.hexapod.read_plan(str(s1 / "plan.json")), seed=5,
                                           validation=50)
    assert sim["text"] == open(tmp_path / "r1.txt").read()
    assert sim["tool"].to_yaml() == open(tmp_path / "tool.yaml").read()
    assert len(sim["validation"]) == 50 and sim["legs_out_of_range"] > 10
    c = cli_json("hexapod", "simulate-readings", "--plan", str(s1 / "plan.json"), "--seed", "5",
                 "--out", str(tmp_path / "r2.txt"))
    keys = ("seed", "readings", "legs_out_of_range")
    assert {k: c[k] for k in keys} == {k: sim[k] for k in keys}
    assert sim["readings"] == len(sim["text"].splitlines()) and sim["seed"] == 5
    with open(tmp_path / "r1.txt") as readings:
        subprocess.run([CLI, "hexapod", "session", "--plan", str(s1 / "plan.json"), "--journal",
                        str(s1 / "journal.jsonl")], stdin=readings, check=True,
                       capture_output=True)
    c = cli_json("hexapod", "calibrate", "--session", str(s1), "--tool",
                 str(tmp_path / "tool.yaml"), "--out", str(tmp_path / "prelim.yaml"))
    p = robcal.hexapod.calibrate([str(s1)], tool=str(tmp_path / "tool.yaml"),
                                 out=str(tmp_path / "py-prelim.yaml"))
    assert p.pop("model").level == "full" and len(p.pop("poses")) == c["rows"]
    assert "Tool" in repr(p.pop("tool"))
    assert {k: v for k, v in c.items() if k != "output"} == {
        k: v for k, v in p.items() if k != "output"}
    assert open(tmp_path / "prelim.yaml").read() == open(tmp_path / "py-prelim.yaml").read()
    legs = robcal.hexapod.calibrate([str(s1)], tool=str(tmp_path / "tool.yaml"), fit="legs")
    assert legs["fit"] == "legs" and legs["converged"] and legs["rms_mm"] < 0.01
    with pytest.raises(robcal.InputError, match="--fit"):
        robcal.hexapod.calibrate([str(s1)], fit="lines")
    c = cli_json("hexapod", "replan", "--session", str(s1), "--model",
                 str(tmp_path / "prelim.yaml"), "--out", str(tmp_path / "cli.json"))
    p = robcal.hexapod.replan([str(s1)], str(tmp_path / "prelim.yaml"), str(tmp_path / "py.json"))
    assert c["replanned"] > 10 and c["replanned"] == p["replanned"]
    assert {k: v for k, v in c.items() if k != "plan"} == {k: v for k, v in p.items() if k != "plan"}
    assert open(tmp_path / "cli.json").read() == open(tmp_path / "py.json").read()
    assert len(robcal.hexapod.read_plan(str(tmp_path / "py.json"))) == p["replanned"]


def same_document(cli, python):
    """The CLI's --json document equals Python's dict without its per-row arrays and messages:
    one library function and one serializer behind both."""
    extra = {"position_errors_mm", "orientation_errors_deg", "pose_errors_mm", "length_errors_mm",
             "warnings", "notes"}
    return cli == {k: v for k, v in python.items() if k not in extra}


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    """A ballbar and an optical-CMM (poses) campaign of the published truth, by the CLI."""
    root = tmp_path_factory.mktemp("sim")
    for instrument in ("ballbar", "optical-cmm"):
        subprocess.run([CLI, "simulate", "--instrument", instrument, "--truth", "published",
                        "--random", "40", "--seed", "5", "--out", str(root / instrument)],
                       check=True, capture_output=True)
    return root


def test_validate_classes_and_fitted_base():
    validation = os.path.join(REF, "validation.csv")
    calibration = os.path.join(REF, "calibration.csv")
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements",
                 validation, "--fit-base", "--calibration", calibration, "--threads", "1")
    p = robcal.validate("abb-irb120", TOOL, validation, fit_base=True, calibration=calibration,
                        threads=1)
    assert same_document(c, p)
    assert [t["table"] for t in p["classes"]][-1] == "region"
    errors = p["position_errors_mm"]
    assert errors.shape == (1000,)
    assert p["position_error_mm"]["mean_mm"] == pytest.approx(errors.mean(), rel=1e-13)
    assert p["position_error_mm"]["max_mm"] == errors.max()


def test_validate_poses_pose_error(simulated):
    tool = str(simulated / "optical-cmm" / "tool.yaml")
    rows = str(simulated / "optical-cmm" / "measurements.csv")
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", tool, "--measurements", rows,
                 "--fit-base", "--orientation-weight", "50")
    p = robcal.validate("abb-irb120", tool, rows, fit_base=True, orientation_weight=50)
    assert same_document(c, p)
    assert p["kind"] == "poses" and p["orientation_weight_mm_per_rad"] == 50
    # The pose error of each row, recomputed from its two parts (docs/method/09-validation.md).
    expected = np.hypot(p["position_errors_mm"], 50 * np.radians(p["orientation_errors_deg"]))
    np.testing.assert_allclose(p["pose_errors_mm"], expected, rtol=1e-12)
    assert p["pose_error_mm"]["mean_mm"] == pytest.approx(expected.mean(), rel=1e-12)


def test_validate_ballbar_file(simulated):
    tool = str(simulated / "ballbar" / "tool.yaml")
    rows = str(simulated / "ballbar" / "measurements.csv")
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", tool, "--measurements", rows)
    p = robcal.validate("abb-irb120", tool, rows)
    assert same_document(c, p)
    assert p["kind"] == "distances" and p["ballbar_centre"] == "identified"
    e = p["length_errors_mm"]
    assert p["length_error_mm"]["mean_mm"] == pytest.approx(np.abs(e).mean(), rel=1e-12)
    assert p["length_error_mm"]["signed_mean_mm"] == pytest.approx(e.mean(), abs=1e-12)
    # The identified centre, given back, reproduces the same errors.
    given = robcal.validate("abb-irb120", tool, rows, ballbar_centre=p["ballbar_centre_mm"])
    assert given["ballbar_centre"] == "given"
    np.testing.assert_allclose(given["length_errors_mm"], e, rtol=0, atol=1e-9)
    with pytest.raises(robcal.InputError, match="no positions to fit a world frame"):
        robcal.validate("abb-irb120", tool, rows, fit_base=True)
    with pytest.raises(robcal.InputError, match="expected 1 to 256 threads"):
        robcal.validate("abb-irb120", tool, rows, threads=0)
    # The bar's length and range (--ballbar-length, --ballbar-range): the same check as the CLI's.
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", tool, "--measurements", rows,
                 "--ballbar-length", "150", "--ballbar-range", "5")
    p = robcal.validate("abb-irb120", tool, rows, ballbar_length=150, ballbar_range=5)
    assert same_document(c, p)
    with pytest.raises(robcal.InputError, match="outside the ballbar's range"):
        robcal.validate("abb-irb120", tool, rows, ballbar_length=140, ballbar_range=1)


def test_validate_refuses_a_model_of_another_robot(tmp_path):
    model = str(tmp_path / "model.yaml")
    subprocess.run([CLI, "calibrate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements",
                    os.path.join(REF, "calibration.csv"), "--level", "base", "--out", model],
                   check=True, capture_output=True)
    args = ["--robot", "fanuc-lrmate200ic", "--tool", TOOL, "--model", model, "--measurements",
            os.path.join(REF, "validation.csv")]
    cli = subprocess.run([CLI, "validate", *args], capture_output=True, text=True)
    assert cli.returncode == 2 and "not of the" in cli.stderr
    with pytest.raises(robcal.InputError, match="this is a model of the ABB IRB 120, not of the"):
        robcal.validate("fanuc-lrmate200ic", TOOL, os.path.join(REF, "validation.csv"),
                        model=model)


def test_validate_rows_from_arrays_equals_the_file():
    validation = os.path.join(REF, "validation.csv")
    tool = robcal.Tool.from_file(TOOL)
    d = robcal.Measurements.from_file(validation, tool).to_dict()
    rows = robcal.Measurements.points(tool, d["joints_deg"], d["target"], d["position_mm"])
    nominal = robcal.CalibratedRobot.nominal(robcal.load_robot("abb-irb120"), tool)
    p = robcal.validate_rows(nominal, rows, fit_base=True, name=validation)
    c = cli_json("validate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements",
                 validation, "--fit-base")
    # The joints went through degrees and back: equal to ~1e-13 relative, not bit for bit.
    assert_close(c, {k: v for k, v in p.items() if k in c})
    assert set(p) - set(c) == {"position_errors_mm", "warnings", "notes"}


def assert_close(a, b, path=""):
    if isinstance(a, dict):
        assert a.keys() == b.keys(), path
        for k in a:
            assert_close(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            assert_close(x, y, f"{path}[{i}]")
    elif isinstance(a, float):
        assert a == pytest.approx(b, rel=1e-11, abs=1e-12), path
    else:
        assert a == b, path


def test_calibrate_guards_and_options(tmp_path):
    data = os.path.join(REF, "calibration.csv")
    out = str(tmp_path / "cli.yaml")
    c = cli_json("calibrate", "--robot", "abb-irb120", "--tool", TOOL, "--measurements", data,
                 "--sigma", "0.005", "--kfold", "4", "--seed", "7", "--out", out)
    p = robcal.calibrate("abb-irb120", TOOL, data, sigma=0.005, kfold=4, seed=7)
    for key, value in (("mean_mm", p.mean_mm), ("rms_mm", p.rms_mm), ("max_mm", p.max_mm)):
        assert c["residual_per_row_mm"][key] == pytest.approx(value, rel=0, abs=5.1e-10)
    assert c["noise_test"]["dof"] == p.noise_test.dof
    assert c["noise_test"]["consistent"] == p.noise_test.consistent is False  # 0.005 mm: misfit
    assert c["noise_test"]["p_value"] == pytest.approx(p.noise_test.p_value, rel=1e-12)
    cv = p.cross_validation
    assert c["cross_validation"]["folds"] == cv["folds"] == 4
    assert c["cross_validation"]["error_mm"]["mean_mm"] == pytest.approx(cv["mean_mm"], abs=5.1e-10)
    assert [f["rows"] for f in c["cross_validation"]["per_fold"]] == [
        f["rows"] for f in cv["per_fold"]]
    assert c["warnings"] == p.warnings and c["problems"] == p.problems == []
    assert c["output"] == out
    # Another robot's model: refused alike, nothing written by either.
    kuka = str(tmp_path / "kuka.yaml")
    cli = subprocess.run([CLI, "calibrate", "--robot", "abb-irb1600-6-12", "--tool", TOOL,
                          "--measurements", data, "--out", kuka, "--json"],
                         capture_output=True, text=True)
    assert cli.returncode == 1 and "not written" in cli.stderr
    document = json.loads(cli.stdout)
    run = robcal.calibrate("abb-irb1600-6-12", TOOL, data)
    assert document["problems"] == run.problems and document["output"] is None
    with pytest.raises(robcal.InputError, match="not written"):
        run.save(kuka)
    assert not os.path.exists(kuka)


FOUR_CUP_BASE = [300, 299.999999969, 299.999999969, 183.303027808, 183.303027808, 183.303027744]
FOUR_CUP_LEGS = [(1, 1, 300), (1, 2, 300), (2, 1, 300), (2, 2, 300), (2, 3, 300),
                 (3, 1, 299.99999998), (4, 2, 243.541821319), (4, 3, 276.389661692)]


def test_hexapod_four_cup_dkp():
    # A fourth base cup 60 mm over the centroid, its two legs at the lengths of the three-cup
    # configuration with every leg at 300 mm (tests/cli/hexapod_options.sh).
    legs = ",".join(f"B{b}-T{t}={length}" for b, t, length in FOUR_CUP_LEGS)
    c = cli_json("hexapod", "dkp", "--base-mm", ",".join(map(str, FOUR_CUP_BASE)), "--tool-mm",
                 "150", "--legs", legs)
    p = robcal.hexapod.solve_four_cup_dkp(FOUR_CUP_BASE, [150, 150, 150], FOUR_CUP_LEGS)
    assert c == p
    # Independently: the closed-form three-cup cascade on the same configuration.
    three = robcal.hexapod.solve_dkp([300, 300, 300], [150, 150, 150], [300] * 6)[1]
    first = p["solutions"][0]
    assert first["rms_residual_mm"] < 1e-6
    np.testing.assert_allclose(first["tool_cups_mm"], three, rtol=0, atol=1e-6)
    with pytest.raises(robcal.InputError, match="legs"):
        robcal.hexapod.solve_four_cup_dkp(FOUR_CUP_BASE, [150, 150, 150], [(5, 1, 300)])
    with pytest.raises(robcal.InputError, match="base_mm"):
        robcal.hexapod.solve_four_cup_dkp([300, 300], [150, 150, 150], FOUR_CUP_LEGS)


def test_hexapod_place_with_cell_and_gauge(tmp_path):
    cell = tmp_path / "cell.yaml"
    cell.write_text("format: robcal-cell\nname: shelf above the fixture\n"
                    "robot_base: {position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}\n"
                    "instrument: {kind: laser-tracker, position_mm: [-2000, 0, 500]}\n"
                    "floor_z_mm: -10\nlink_radius_mm: 40\nkeep_out:\n"
                    "  - {name: shelf, min_mm: [300, -100, 650], max_mm: [600, 100, 900]}\n")
    c = cli_json("hexapod", "place", "--x-mm", "450", "--y-mm", "0,200", "--z-mm", "300",
                 "--validation", "200", "--best", "2", "--gauge-range-mm", "5",
                 "--gauge-sigma-mm", "0.002", "--leg-mm", "302", "--cell", str(cell))
    p = robcal.hexapod.place(x_mm=[450], y_mm=[0, 200], z_mm=[300], validation=200, best=2,
                             gauge_range_mm=5, gauge_sigma_mm=0.002, leg_mm=302, cell=str(cell))
    assert without_seconds(c) == without_seconds(p)
    # The options reach the search: the default gauge and no cell give other predictions.
    default = robcal.hexapod.place(x_mm=[450], y_mm=[0, 200], z_mm=[300], validation=200, best=2)
    assert [r["predicted_mean_mm"] for r in default["ranked"]] != \
        [r["predicted_mean_mm"] for r in p["ranked"]]
