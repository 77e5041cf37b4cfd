"""The measurement campaign and validation helpers: the CLI and Python on the same inputs give
the same files and numbers (one library workflow behind both)."""
import os
import re
import subprocess

import numpy as np
import pytest

import robcal

CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")


def read_rows(path):
    return [line.strip().split(",") for line in open(path)
            if line.strip() and not line.startswith("#")][1:]


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A plan of 10 simulated configurations and the operator's answers: the reference R1
    first and before every 4th configuration, R7 skipped, one answer refused (two numbers)."""
    root = tmp_path_factory.mktemp("session")
    subprocess.run([CLI, "simulate", "--random", "10", "--seed", "7", "--out", str(root / "ss")],
                   check=True, capture_output=True)
    rows = read_rows(root / "ss" / "measurements.csv")
    plan = root / "plan.csv"
    plan.write_text("config,target,j1,j2,j3,j4,j5,j6\n" +
                    "".join(",".join(r[:8]) + "\n" for r in rows))
    xyz = [" ".join(r[8:11]) for r in rows]
    answers = [xyz[0] + " 20.5"]
    for c, answer in enumerate(xyz):
        if c > 0 and c % 4 == 0:
            answers.append(f"{xyz[0]} {21 + c / 4}")
        if c == 2:
            answers.append("1 2")  # refused: asked again
        answers.append("skip" if c == 6 else answer)
    answers.append(xyz[0])
    return root, str(plan), answers, rows


def test_session(campaign, tmp_path):
    root, plan, answers, rows = campaign
    common = ["--configs", plan, "--reference", "R1", "--every", "4"]
    cli = subprocess.run([CLI, "session", *common, "--journal", str(tmp_path / "jc"), "--out",
                          str(tmp_path / "c.csv")], input="\n".join(answers) + "\n",
                         capture_output=True, text=True, check=True)
    py = robcal.point_session(plan, str(tmp_path / "jp"), str(tmp_path / "p.csv"), answers,
                              reference="R1", every=4)
    assert py["status"] == "complete" and py["steps"] == py["answered"] == 14
    assert (tmp_path / "c.csv").read_text() == (tmp_path / "p.csv").read_text() == py["csv"]
    assert "session complete: 9 configurations read, 1 missing (R7)" in cli.stdout
    assert py["read"] == 9 and py["missing"] == ["R7"] and len(py["measurements"]) == 9
    # The prompts and the refusal are the CLI's, up to the readings' time stamps.
    assert cli.stdout.startswith(py["transcript"])
    assert len(py["refused"]) == 1 and py["refused"][0] + "; try again" in cli.stderr
    printed = re.findall(r"drift (\S+): (\S+) mm at \S+?(?:, (\S+) °C)?\n", cli.stdout)
    assert [(d["key"], f"{d['drift_mm']:.4f}") for d in py["drift"]] == \
        [(k, v) for k, v, _ in printed]
    assert [d["temperature_c"] for d in py["drift"]] == [22.0, 23.0, None]
    # The positions are the typed ones (the simulated readings), to the printed digits.
    got = py["measurements"].to_dict()
    want = [r for r in rows if r[0] != "R7"]
    np.testing.assert_allclose(got["position_mm"], [[float(v) for v in r[8:11]] for r in want],
                               rtol=0, atol=1e-12)


def test_session_paused_and_resumed(campaign, tmp_path):
    _, plan, answers, _ = campaign
    journal, out = str(tmp_path / "j"), str(tmp_path / "s.csv")
    first = robcal.point_session(plan, journal, out, answers[:5], reference="R1", every=4)
    assert first["status"] == "paused-end-of-input" and first["answered"] == 4  # one refused
    assert not os.path.exists(out)
    with pytest.raises(robcal.InputError, match="pass --resume"):
        robcal.point_session(plan, journal, out, answers[5:], reference="R1", every=4)
    # The CLI resumes the journal Python wrote: both write the one journal format.
    cli = subprocess.run([CLI, "session", "--configs", plan, "--reference", "R1", "--every", "4",
                          "--journal", journal, "--resume", "--out", out],
                         input="\n".join(answers[5:]) + "\n", capture_output=True, text=True,
                         check=True)
    assert cli.stdout.startswith(f"resumed {journal}: 4 of 14 steps answered\n")
    whole = robcal.point_session(plan, str(tmp_path / "j2"), str(tmp_path / "w.csv"), answers,
                                 reference="R1", every=4)
    assert open(out).read() == whole["csv"]


def test_session_refusals_are_the_clis(campaign, tmp_path):
    _, plan, _, _ = campaign
    for flags, kwargs, message in [
            (["--every", "4"], {"every": 4}, "drift checks need the reference"),
            (["--reference", "R99"], {"reference": "R99"}, "configuration 'R99' is not in")]:
        cli = subprocess.run([CLI, "session", "--configs", plan, *flags, "--journal",
                              str(tmp_path / "j"), "--out", str(tmp_path / "o.csv")],
                             capture_output=True, text=True)
        assert cli.returncode == 2 and message in cli.stderr
        with pytest.raises(robcal.InputError, match=re.escape(message)):
            robcal.point_session(plan, str(tmp_path / "j"), str(tmp_path / "o.csv"), [], **kwargs)
        assert not os.path.exists(tmp_path / "j")


def test_import_in_a_world_frame(campaign, tmp_path):
    """An instrument moved to instrument_T_world = Trans(p)·Rz(γ) read m_I = R·m_W + p; imported
    with the `frames world` file, the CLI and Python write the world positions back."""
    _, _, _, rows = campaign
    g = np.radians(-37.5)
    R = np.array([[np.cos(g), -np.sin(g), 0], [np.sin(g), np.cos(g), 0], [0, 0, 1]])
    p = np.array([120.0, -340.5, 18.25])
    frame = tmp_path / "world.yaml"
    frame.write_text("frame: {position_mm: [120, -340.5, 18.25], rotation_xyz_deg: [0, 0, -37.5], "
                     "sigma: {position_mm: [0, 0, 0], rotation_xyz_deg: [0, 0, 0]}, "
                     "sigma_noise_mm: 0, rms_mm: 0}\n")
    world = np.array([[float(v) for v in r[8:11]] for r in rows])
    export = tmp_path / "export.csv"
    export.write_text("config,target,x,y,z\n" + "".join(
        f"{r[0]},{r[1]},{m[0]!r},{m[1]!r},{m[2]!r}\n"
        for r, m in zip(rows, world @ R.T + p)))
    log = tmp_path / "log.csv"
    log.write_text("config,j1,j2,j3,j4,j5,j6\n" + "".join(",".join([r[0], *r[2:8]]) + "\n"
                                                        for r in rows))
    out = tmp_path / "c.csv"
    subprocess.run([CLI, "import", "--export", str(export), "--joints", str(log), "--join", "name",
                    "--world-frame", str(frame), "--out", str(out)], check=True,
                   capture_output=True)
    py = robcal.import_measurements(str(export), str(log), join="name", world_frame=str(frame))
    assert out.read_text() == py["csv"] and py["world_frame"] == str(frame)
    np.testing.assert_allclose(py["measurements"].to_dict()["position_mm"], world, rtol=0,
                               atol=1e-9)


REF = os.path.join(os.path.dirname(__file__), "..", "data", "irb120-published")
TOOL = os.path.join(REF, "tool.yaml")
REGION = [300, -150, 300, 500, 150, 520]


def cli_json(*args, cwd=None):
    import json
    out = subprocess.run([CLI, *args, "--json"], check=True, capture_output=True, text=True,
                         cwd=cwd)
    return json.loads(out.stdout)


def test_iso9283_plan_and_analyse(tmp_path):
    (tmp_path / "c").mkdir()
    (tmp_path / "p").mkdir()
    c = cli_json("iso9283", "plan", "--robot", "abb-irb120", "--region",
                 ",".join(map(str, REGION)), "--cycles", "3", "--vap-approach", "40",
                 "--program", "krl", cwd=tmp_path / "c")
    p = robcal.iso9283_plan_files("abb-irb120", REGION[:3], REGION[3:], cycles=3,
                                  vap_approach_mm=40, program="krl",
                                  out_poses=str(tmp_path / "p" / "iso9283-poses.csv"),
                                  out_cycles=str(tmp_path / "p" / "iso9283-cycles.csv"),
                                  out_vap_cycles=str(tmp_path / "p" / "iso9283-vap-cycles.csv"),
                                  program_dir=str(tmp_path / "p" / "iso9283-programs"))
    assert [os.path.relpath(f, tmp_path / "p") for f in p["files"]] == c["files"]
    assert {k: v for k, v in p.items() if k != "files"} == \
        {k: v for k, v in c.items() if k != "files"}
    for f in c["files"]:
        assert (tmp_path / "c" / f).read_bytes() == (tmp_path / "p" / f).read_bytes(), f
    # The array-level iso9283_plan gives the same poses.
    nominal = robcal.CalibratedRobot.nominal(robcal.load_robot("abb-irb120"))
    arrays = robcal.iso9283_plan(nominal, REGION[:3], REGION[3:], cycles=3)
    for a, b in zip(arrays["poses"], p["poses"]):
        np.testing.assert_allclose(a["joints_deg"], b["joints_deg"], rtol=0, atol=1e-12)
    with pytest.raises(robcal.InputError, match="pulses per degree"):
        robcal.iso9283_plan_files("abb-irb120", REGION[:3], REGION[3:], program="jbi",
                                  out_poses=str(tmp_path / "x.csv"))
    assert not os.path.exists(tmp_path / "x.csv")
    # Measured cycles 0.05 mm off in x: AP 0.05 mm for every pose, by both.
    poses = os.path.join(tmp_path, "c", "iso9283-poses.csv")
    rows = [r.split(",") for r in open(poses).read().splitlines()[1:]]
    meas = tmp_path / "meas.csv"
    meas.write_text("pose,cycle,x,y,z\n" + "".join(
        f"{r[0]},{k},{float(r[1]) + 0.05},{float(r[2]) + 0.001 * k},{r[3]}\n"
        for k in range(1, 4) for r in rows))
    c = cli_json("iso9283", "analyse", "--poses", poses, "--measurements", str(meas),
                 "--min-cycles", "3")
    p = robcal.iso9283_analyse(poses, str(meas), min_cycles=3)
    assert {k: v for k, v in c.items() if k not in ("measurements", "min_cycles")} == p
    assert all(abs(x["AP_mm"] - np.hypot(0.05, 0.002)) < 1e-9 for x in p["poses"])


def test_axis_test(tmp_path):
    subprocess.run([CLI, "axis-test", "plan", "--joint", "3", "--home", "0,10,10,0,45,0",
                    "--range", "-20,40", "--steps", "7", "--approach", "3", "--out",
                    str(tmp_path / "c.csv")], check=True, capture_output=True)
    p = robcal.axis_test_plan(3, [0, 10, 10, 0, 45, 0], -20, 40, steps=7, approach_deg=3,
                              out=str(tmp_path / "p.csv"))
    assert (tmp_path / "c.csv").read_text() == (tmp_path / "p.csv").read_text() == p["csv"]
    assert p["moves"] == 14 and p["csv"].count(",below,") == 7
    # A circle of radius 250 mm about an axis through (10, 0), 0.03° between the two sides.
    f = tmp_path / "axis.csv"
    lines = ["joint_deg,side,x,y,z"]
    for k in range(9):
        q = -20 + 60 * k / 8
        for side, b in (("below", 0.0), ("above", 0.03)):
            a = np.radians(q + b)
            lines.append(f"{q},{side},{250 * np.cos(a) + 10},{250 * np.sin(a)},400")
    f.write_text("\n".join(lines) + "\n")
    c = cli_json("axis-test", "analyse", "--measurements", str(f))
    p = robcal.axis_test_analyse(str(f))
    assert c == p
    assert p["backlash_deg"] == pytest.approx(0.03, abs=1e-9)
    assert p["radius_mm"] == pytest.approx(250, abs=1e-9)


def test_ballbar_path(tmp_path):
    args = ["--robot", "abb-irb120", "--tool", TOOL, "--target", "1", "--centre", "400,0,300",
            "--length", "100", "--elevations", "-30,0,30", "--points", "8"]
    c = cli_json("ballbar-path", *args, "--out", str(tmp_path / "c.csv"))
    p = robcal.ballbar_path("abb-irb120", TOOL, "1", [400, 0, 300], 100, str(tmp_path / "p.csv"),
                            elevations_deg=[-30, 0, 30], points=8)
    assert (tmp_path / "c.csv").read_text() == (tmp_path / "p.csv").read_text()
    assert c["points"] == p["points"] == 24 and p["joints_deg"].shape == (24, 6)
    # The commanding model predicts its own readings: exactly the bar's length.
    assert c["largest_predicted_offset_mm"] == p["largest_predicted_offset_mm"] < 1e-9
    written = np.array([[float(v) for v in r.split(",")[2:]]
                        for r in (tmp_path / "p.csv").read_text().splitlines()[1:]])
    np.testing.assert_allclose(written, p["joints_deg"], rtol=0, atol=1e-9)
    with pytest.raises(robcal.InputError, match="12 of 12 path points fail the checks"):
        robcal.ballbar_path("abb-irb120", TOOL, "1", [3000, 0, 300], 100, str(tmp_path / "x.csv"))
    assert not os.path.exists(tmp_path / "x.csv")


def test_report_with_provenance_and_iso9283(tmp_path):
    import json
    model = str(tmp_path / "model.yaml")
    robcal.calibrate("abb-irb120", TOOL, os.path.join(REF, "calibration.csv")).save(model)
    validation = os.path.join(REF, "validation.csv")
    instrument = tmp_path / "instrument.yaml"
    instrument.write_text("instrument: laser-tracker\nposition_mm: [0, 0, 0]\n"
                          "sigma_mm: [0.022, 0.022, 0.022]\ncone_half_angle_deg: 30\n")
    plan = robcal.iso9283_plan_files("abb-irb120", REGION[:3], REGION[3:], cycles=30,
                                     out_poses=str(tmp_path / "poses.csv"),
                                     out_cycles=str(tmp_path / "cycles.csv"))
    meas = tmp_path / "iso.csv"
    meas.write_text("pose,cycle,x,y,z\n" + "".join(
        f"{x['name']},{k},{x['position_mm'][0] + 0.02},{x['position_mm'][1]},"
        f"{x['position_mm'][2] + 0.001 * (k % 3)}\n"
        for k in range(1, 31) for x in plan["poses"]))
    args = ["--instrument", str(instrument), "--seed", "17", "--iso9283-poses",
            str(tmp_path / "poses.csv"), "--iso9283-measurements", str(meas)]
    try:
        c = cli_json("report", "--model", model, "--measurements", validation, *args,
                     "--out", str(tmp_path / "cli.html"))
    except subprocess.CalledProcessError as e:
        if "Chart.js" in e.stderr:
            pytest.skip("Chart.js (libjs-chart.js) is not installed")
        raise
    p = robcal.report(model, [validation], instrument=str(instrument), seed=17,
                      iso9283_poses=str(tmp_path / "poses.csv"),
                      iso9283_measurements=str(meas), out=str(tmp_path / "py.html"))
    assert p.pop("warnings") == []
    cp, pp = c.pop("provenance"), p.pop("provenance")
    for key in ("files", "robot", "level", "robcal_version", "seed", "instrument",
                "instrument_sigma_mm"):
        assert cp.get(key) == pp.get(key), key
    assert pp["seed"] == 17 and pp["instrument_sigma_mm"] == pytest.approx(0.022, rel=1e-12)
    assert c == p and "iso9283" in json.dumps(p)


def test_simulate_writes_the_clis_files(tmp_path):
    cell = os.path.join(os.path.dirname(__file__), "..", "..", "data", "cells",
                        "default-tracker.yaml")
    c = cli_json("simulate", "--random", "8", "--seed", "5", "--cell", cell, "--effects",
                 "backlash", "--noise-mm", "0.03", "--out", str(tmp_path / "c"))
    p = robcal.simulate(count=8, seed=5, cell=cell, effects=["backlash"], noise_mm=0.03,
                        out=str(tmp_path / "p"))
    summary = p["summary"]
    assert {k: v for k, v in summary.items() if k != "files"} == \
        {k: v for k, v in c.items() if k != "files"}
    for name in ("measurements.csv", "tool.yaml", "instrument.yaml"):
        assert (tmp_path / "c" / name).read_text() == (tmp_path / "p" / name).read_text(), name
    rows = read_rows(tmp_path / "p" / "measurements.csv")
    np.testing.assert_allclose(p["position_mm"], [[float(v) for v in r[8:11]] for r in rows],
                               rtol=0, atol=1e-9)
    with pytest.raises(robcal.InputError, match="--approach"):
        robcal.simulate(count=3, approach="sideways")
