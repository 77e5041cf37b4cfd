"""The hexapod commands and their Python functions on the same inputs give the same numbers (the
CLI's JSON is rounded to 1e-9 mm, the uncertainties to 1e-4 σ): dkp, poses, uncertainty,
device-validation, world-frame, place, session, export-poses; and `model import|export`,
`program` beside them."""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

import robcal
import robcal.hexapod as hexapod

ROOT = pathlib.Path(__file__).resolve().parents[2]
CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")


def cli_json(*args, stdin=None):
    out = subprocess.run([CLI, *args, "--json"], check=True, capture_output=True, text=True,
                         input=stdin)
    return json.loads(out.stdout)


def numbers(values):
    return ",".join(repr(float(v)) for v in np.ravel(values))



def simulated_session(plan, folder):
    """The plan's session run to the end with simulated readings (seed 5): its folder."""
    folder.mkdir()
    plan.save(str(folder / "plan.json"))
    sim = hexapod.simulate_readings(plan, seed=5, validation=0)
    assert sim["legs_out_of_range"] == 0
    done = hexapod.session(str(folder / "plan.json"), str(folder / "journal.jsonl"),
                           sim["text"].splitlines())
    assert done["status"] == "complete"
    return folder

def test_dkp():
    pose = hexapod.enumerate_poses()[7]
    legs = hexapod.leg_lengths(hexapod.triangle_from_sides([300, 300, 300]), pose["tool_cups"])
    c = cli_json("hexapod", "dkp", "--base-mm", "300", "--tool-mm", "150", "--legs", numbers(legs))
    p = hexapod.solve_dkp([300] * 3, [150] * 3, legs)
    assert sorted(s["mode"] for s in c["solutions"]) == sorted(p)
    for s in c["solutions"]:
        np.testing.assert_allclose(s["tool_cups_mm"], p[s["mode"]], rtol=0, atol=1e-9)
    # One of the modes is the pose the legs were taken from.
    assert min(np.abs(p[m] - pose["tool_cups"]).max() for m in p) < 1e-9


def test_poses_and_uncertainty():
    c = cli_json("hexapod", "poses", "--angle-deg", "30", "--distance-mm", "50")
    p = hexapod.enumerate_poses(angle_deg=30, distance_mm=50)
    assert c["enumerated"] == 72 and c["kept"] == len(p) == len(c["poses"])
    for a, b in zip(c["poses"], p):
        assert (a["label"], a["mode"], a["rotation_deg"]) == (b["label"], b["mode"],
                                                             b["rotation_deg"])
        assert a["base_roles"] == [r + 1 for r in b["base_roles"]]
        np.testing.assert_allclose(a["tool_cups_mm"], b["tool_cups"], rtol=0, atol=1e-9)
    c = cli_json("hexapod", "uncertainty", "--samples", "2000", "--seed", "3")
    p = hexapod.uncertainty(samples=2000, seed=3)
    assert [m["mode"] for m in c["modes"]] == [m["mode"] for m in p]
    for a, b in zip(c["modes"], p):
        np.testing.assert_allclose([x["norm_sigma"] for x in a["cups"]], b["norm_sigma"], rtol=0,
                                   atol=5e-5)
        np.testing.assert_allclose([x["monte_carlo_norm_sigma"] for x in a["cups"]],
                                   b["monte_carlo_norm_sigma"], rtol=0, atol=5e-5)
    with pytest.raises(robcal.InputError, match="--samples"):
        hexapod.uncertainty(samples=10)


def test_device_validation_world_frame_and_place():
    c = cli_json("hexapod", "device-validation", "--poses", "200", "--seed", "4")
    assert c == hexapod.device_validation(poses=200, seed=4)
    # The robot placed the cups 0.05 mm off; the sides were measured.
    points = hexapod.triangle_from_sides([300, 300, 300]) + [[400, 10, 200]] * 3
    points[1] += [0.05, -0.03, 0.0]
    c = cli_json("hexapod", "world-frame", "--points", numbers(points), "--sides", "300")
    p = hexapod.fit_world_frame(points, [300, 300, 300])
    np.testing.assert_allclose(c["corrected_cups_mm"], p["corrected"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(c["robot_T_world"]["position_mm"], p["origin_mm"], rtol=0,
                               atol=1e-9)
    assert c["rms_mm"] == pytest.approx(p["rms_mm"], abs=1e-9) and c["converged"]
    np.testing.assert_allclose([c["planar"][k] for k in ("x_mm", "y_mm", "phi_deg")], p["planar"],
                               rtol=0, atol=1e-9)
    c = cli_json("hexapod", "place", "--x-mm", "400,500", "--y-mm", "0", "--z-mm", "300",
                 "--validation", "200", "--best", "2")
    p = hexapod.place(x_mm=[400, 500], y_mm=[0], z_mm=[300], validation=200, best=2)
    assert c == p and len(p["ranked"]) == 2 and p["identify"] == []
    # With the joint-periodic group (--identify): the same ranking both ways, more parameters.
    c = cli_json("hexapod", "place", "--x-mm", "400,500", "--y-mm", "0", "--z-mm", "300",
                 "--validation", "200", "--best", "2", "--identify", "periodic")
    q = hexapod.place(x_mm=[400, 500], y_mm=[0], z_mm=[300], validation=200, best=2,
                      identify=["periodic"])
    assert c == q and q["identify"] == ["periodic"] and q["parameters"] > p["parameters"]
    with pytest.raises(robcal.InputError, match="--best"):
        hexapod.place(x_mm=[400], y_mm=[0], z_mm=[300], best=0)


def test_design_over_two_placements(tmp_path):
    plans = []
    for name, placement in (("a", (500, 300, 150, 0)), ("b", (350, 0, 300, 0))):
        plans.append(str(tmp_path / f"{name}.json"))
        hexapod.plan("fanuc-lrmate200ic", placement=placement, gauge_range_mm=5).save(plans[-1])
    outs = [str(tmp_path / "cli_a.json"), str(tmp_path / "cli_b.json")]
    c = cli_json("hexapod", "design", "--plan", plans[0], "--plan", plans[1], "--count", "40",
                 "--validation", "200", "--out", outs[0], "--out", outs[1])
    py_outs = [str(tmp_path / "py_a.json"), str(tmp_path / "py_b.json")]
    p = hexapod.design(plans, count=40, validation=200, out=py_outs)
    for placement in c["placements"] + p["placements"]:
        placement["written"] = placement["written"] and pathlib.Path(placement["written"]).name[-6:]
    assert c == p and sum(x["chosen"] for x in p["placements"]) == 40
    for cli_out, py_out in zip(outs, py_outs):
        assert os.path.exists(cli_out) == os.path.exists(py_out)
        if os.path.exists(cli_out):
            assert pathlib.Path(cli_out).read_text() == pathlib.Path(py_out).read_text()
    with pytest.raises(robcal.InputError, match="--out"):
        hexapod.design(plans, out=[outs[0]])
    # With the joint-periodic group predicted for too (--identify): the same choice both ways.
    c = cli_json("hexapod", "design", "--plan", plans[0], "--plan", plans[1], "--count", "40",
                 "--validation", "200", "--identify", "periodic")
    p = hexapod.design(plans, count=40, validation=200, identify=["periodic"])
    assert c == p and p["identify"] == ["periodic"]
    assert p["design"]["parameters"] > 40  # the level's and the group's
    with pytest.raises(robcal.InputError, match="--identify"):
        hexapod.design(plans, identify=["nosuch*"])


def test_session_and_export_poses(tmp_path):
    plan = hexapod.plan("fanuc-lrmate200ic", placement=(450, 0, 300, 0))
    for name in ("cli", "py"):
        (tmp_path / name).mkdir()
        plan.save(str(tmp_path / name / "plan.json"))
    sim = hexapod.simulate_readings(plan, seed=5, validation=0)
    lines = sim["text"].splitlines()
    c = cli_json("hexapod", "session", "--plan", str(tmp_path / "cli" / "plan.json"), "--journal",
                 str(tmp_path / "cli" / "journal.jsonl"), stdin=sim["text"])
    # Python: paused half-way, then resumed with the rest.
    half = len(lines) // 2
    py_plan, py_journal = str(tmp_path / "py" / "plan.json"), str(tmp_path / "py" / "journal.jsonl")
    first = hexapod.session(py_plan, py_journal, lines[:half] + ["abc"])
    assert first["status"] == "paused-end-of-input" and first["answered"] == half
    assert first["refused"] == ["'abc' is not a reading: enter a length in mm, 'out' when the "
                                "ballbar does not fit, or 'quit'."]
    p = hexapod.session(py_plan, py_journal, lines[half:], resume=True,
                        out=str(tmp_path / "py" / "result.json"))
    assert p.pop("transcript").startswith(f"Resumed {py_journal}: {half} readings replayed.")
    assert p.pop("refused") == [] and p["replayed"] == half
    assert c == {**p, "replayed": 0}
    assert c["status"] == "complete" and c["answered"] == len(lines)
    assert json.load(open(tmp_path / "py" / "result.json")) == c["result"]
    assert c["result"]["measured"] + c["result"]["retry_after_preliminary_calibration"] == len(plan)
    assert open(tmp_path / "cli" / "journal.jsonl").read() == open(py_journal).read()
    # export-poses of the two sessions: the same files.
    out = {name: {k: str(tmp_path / f"{name}-{k}") for k in ("poses.csv", "legs.csv", "tool.yaml")}
           for name in ("cli", "py")}
    c = cli_json("hexapod", "export-poses", "--session", str(tmp_path / "cli"), "--out",
                 out["cli"]["poses.csv"], "--legs-out", out["cli"]["legs.csv"], "--tool-out",
                 out["cli"]["tool.yaml"])
    p = hexapod.export_poses([str(tmp_path / "py")], out["py"]["poses.csv"],
                             legs_out=out["py"]["legs.csv"], tool_out=out["py"]["tool.yaml"])
    assert len(p.pop("measurements")) == c["configurations_measured"] > 0
    assert "Tool" in repr(p.pop("tool_fixture"))
    for key in ("sessions", "poses", "legs", "tool"):
        c.pop(key), p.pop(key)
    assert c == p
    assert open(out["cli"]["tool.yaml"]).read() == open(out["py"]["tool.yaml"]).read()
    for k in ("poses.csv", "legs.csv"):  # the same rows; the comments name each session
        rows = [[r for r in open(out[name][k]).read().splitlines() if not r.startswith("#")]
                for name in ("cli", "py")]
        assert rows[0] == rows[1] and len(rows[0]) > c["configurations_measured"]


def test_model_import_export_and_program(tmp_path):
    urdf = str(tmp_path / "r.urdf")
    c = cli_json("model", "export", "--robot", "kuka-kr6-r900-sixx", "--out", urdf)
    p = robcal.model_export(robot="kuka-kr6-r900-sixx", out=str(tmp_path / "p.urdf"))
    assert p.pop("text") == open(urdf).read() == open(tmp_path / "p.urdf").read()
    assert {**c, "out": ""} == {**p, "out": ""} and c["format"] == "urdf"
    c = cli_json("model", "import", "--urdf", urdf, "--out", str(tmp_path / "c.yaml"))
    p = robcal.model_import(urdf=urdf)
    assert p.pop("yaml") == open(tmp_path / "c.yaml").read()
    assert {**c, "out": ""} == p and len(p["joints"]) == 6
    configs = tmp_path / "configs.csv"
    configs.write_text("config,target,j1,j2,j3,j4,j5,j6\nc1,,10,20,-10,30,40,50\n"
                       "c2,,-10,25,5,0,30,90\n")
    subprocess.run([CLI, "program", "--lang", "krl", "--configs", str(configs), "--robot",
                    "abb-irb120", "--out", str(tmp_path / "cli")], check=True, capture_output=True)
    paths = robcal.write_measurement_program_files("krl", str(configs), str(tmp_path / "py"),
                                                   robot="abb-irb120")
    for path in paths:
        cli_text = (tmp_path / "cli" / pathlib.Path(path).name).read_text()
        assert cli_text == pathlib.Path(path).read_text()


def test_fourth_tool_cup_plan_session_calibrate(tmp_path):
    # T4 on the circumcircle of T1..T3, opposite T1: a seventh leg in every configuration.
    r = 150 / 3 ** 0.5
    cup4 = (2 * r, r, r)
    plan = hexapod.plan("fanuc-lrmate200ic", placement=(450, 0, 300, 0), gauge_range_mm=5,
                        tool_cup4_mm=cup4)
    cli_plan = str(tmp_path / "cli_plan.json")
    subprocess.run([CLI, "hexapod", "plan", "--placement", "450,0,300,0", "--gauge-range-mm", "5",
                    "--tool-cup4-mm", ",".join(repr(d) for d in cup4), "--out", cli_plan],
                   check=True, capture_output=True)
    plan.save(str(tmp_path / "py_plan.json"))
    assert (tmp_path / "py_plan.json").read_text() == pathlib.Path(cli_plan).read_text()
    legs = [c["legs"] for c in json.loads(plan.to_json())["configurations"]]
    assert legs and all(len(x) == 7 and x[6].endswith("-T4") for x in legs)
    session = simulated_session(plan, tmp_path / "s")
    for fit in ("poses", "legs"):
        c = cli_json("hexapod", "calibrate", "--session", str(session), "--fit", fit, "--out",
                     str(tmp_path / f"cli_{fit}.yaml"))
        p = hexapod.calibrate([str(session)], fit=fit, out=str(tmp_path / f"py_{fit}.yaml"))
        assert c["converged"] and c["configurations_measured"] == len(legs)
        assert c["tool_cup4_mm"] == p["tool_cup4_mm"]
        assert c["rms_mm"] == p["rms_mm"]
    with pytest.raises(robcal.InputError, match="--tool-cup4-mm: tool fixture: the fourth cup T4 "
                                                "is collinear with T1 and T2"):
        hexapod.plan("fanuc-lrmate200ic", tool_cup4_mm=(75, 75, 75 * 3 ** 0.5))


def test_fourth_tool_cup_place_and_simulate():
    # place: the pose σ scaled by the fourth cup's worst-case gain, the same numbers as the CLI.
    r = 150 / 3 ** 0.5
    cup4 = (2 * r, r, r)
    grid = dict(x_mm=[450], y_mm=[0], z_mm=[300], validation=100, best=1)
    three = hexapod.place(**grid)
    four = hexapod.place(**grid, tool_cup4_mm=cup4)
    c = cli_json("hexapod", "place", "--x-mm", "450", "--y-mm", "0", "--z-mm", "300",
                 "--validation", "100", "--best", "1", "--tool-cup4-mm", numbers(cup4))
    assert c == four
    assert 0.98 * three["pose_sigma_mm"] < four["pose_sigma_mm"] < three["pose_sigma_mm"]
    # simulate: a seventh leg read in every configuration measured.
    s = hexapod.simulate(validation=50, leg_fit=False, tool_cup4_mm=cup4)
    assert s["legs_read"] == 7 * s["legs_read_tool_cup4"] > 0
    assert s["tool_cup4_mm"] == list(cup4)
    with pytest.raises(robcal.InputError, match="--tool-cup4-mm: tool fixture: the fourth cup T4 "
                                                "is collinear with T1 and T2"):
        hexapod.simulate(tool_cup4_mm=(75, 75, 75 * 3 ** 0.5))


def test_fourth_base_cup_plan_session_calibrate_place_simulate(tmp_path):
    # B4 on the circumcircle of B1..B3, opposite B1: a leg from it in every configuration, its
    # setting point B1 mirrored through the centroid of B1..B3.
    r = 300 / 3 ** 0.5
    cup4 = (2 * r, r, r)
    plan = hexapod.plan("fanuc-lrmate200ic", placement=(450, 0, 300, 0), gauge_range_mm=5,
                        base_cup4_mm=cup4)
    cli_plan = str(tmp_path / "cli_plan.json")
    subprocess.run([CLI, "hexapod", "plan", "--placement", "450,0,300,0", "--gauge-range-mm", "5",
                    "--base-cup4-mm", numbers(cup4), "--out", cli_plan],
                   check=True, capture_output=True)
    plan.save(str(tmp_path / "py_plan.json"))
    assert (tmp_path / "py_plan.json").read_text() == pathlib.Path(cli_plan).read_text()
    setting = plan.setting_ball_mm
    assert setting.shape == (4, 3)
    setup = hexapod.setup(placement=(450, 0, 300, 0), base_cup4_mm=cup4)
    assert setup == cli_json("hexapod", "setup", "--placement", "450,0,300,0", "--base-cup4-mm",
                             numbers(cup4))
    assert setup["setting_ball"] == json.loads(plan.to_json())["setting_ball"]
    np.testing.assert_allclose(setting[3], 2 * setting[:3].mean(axis=0) - setting[0], atol=1e-6)
    legs = [c["legs"] for c in json.loads(plan.to_json())["configurations"]]
    assert legs and all(len(x) == 7 and x[6].startswith("B4-") for x in legs)
    session = simulated_session(plan, tmp_path / "s")
    c = cli_json("hexapod", "calibrate", "--session", str(session), "--fit", "legs", "--out",
                 str(tmp_path / "cli_legs.yaml"))
    p = hexapod.calibrate([str(session)], fit="legs", out=str(tmp_path / "py_legs.yaml"))
    assert c["converged"] and c["configurations_measured"] == len(legs)
    assert c["base_cup4_mm"] == p["base_cup4_mm"]
    assert c["base_cup4_fitted_mm"] == p["base_cup4_fitted_mm"]
    # place: the same numbers as the CLI, the pose σ lowered by B4's legs.
    grid = dict(x_mm=[450], y_mm=[0], z_mm=[300], validation=100, best=1)
    four = hexapod.place(**grid, base_cup4_mm=cup4)
    assert four == cli_json("hexapod", "place", "--x-mm", "450", "--y-mm", "0", "--z-mm", "300",
                            "--validation", "100", "--best", "1", "--base-cup4-mm", numbers(cup4))
    assert four["pose_sigma_mm"] < hexapod.place(**grid)["pose_sigma_mm"]
    s = hexapod.simulate(validation=50, leg_fit=False, base_cup4_mm=cup4)
    assert s["legs_read"] == 7 * s["legs_read_base_cup4"] > 0
    assert s["base_cup4_mm"] == list(cup4)
    with pytest.raises(robcal.InputError, match="--base-cup4-mm: base fixture: the fourth cup B4 "
                                                "is collinear with B1 and B2"):
        hexapod.plan("fanuc-lrmate200ic", base_cup4_mm=(150, 150, 150 * 3 ** 0.5))
