"""The demo, the campaign's import and frames and the guided session from Python: the same
library functions as the CLI (same documents, same files), arrays in and out, and the numbers
against independent expectations."""
import json
import math
import os
import subprocess

import numpy as np
import pytest

import robcal

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")
CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")


def run(*args, stdin=None):
    return subprocess.run([CLI, *args], check=True, capture_output=True, text=True, input=stdin)


def rows_of(path):
    """config,target,j1..j6,x,y,z rows of a measurement CSV (comments skipped)."""
    lines = [l.strip().split(",") for l in open(path) if l.strip() and not l.startswith("#")]
    return lines[1:]


def test_demo_same_summary_and_files_as_the_cli(tmp_path):
    c = json.loads(run("demo", "--seed", "2", "--count", "40", "--validation", "200", "--json",
                       "--out", str(tmp_path / "cli")).stdout)
    p = robcal.demo(out=str(tmp_path / "py"), seed=2, count=40, validation=200)
    arrays = {"errors_mm", "errors_vs_truth_mm"}
    assert {k: v for k, v in c.items() if k != "out"} == \
        {k: v for k, v in p.items() if k not in arrays | {"out"}}
    for name in ("plan.csv", "calibration/measurements.csv", "models/full.yaml"):
        assert open(tmp_path / "cli" / name).read() == open(tmp_path / "py" / name).read(), name
    # The per-row errors are the summaries' rows.
    for label, errors in p["errors_mm"].items():
        assert errors.shape == (200,)
        assert p["vs_measurements"][label]["mean_mm"] == pytest.approx(np.mean(errors), rel=1e-12)
        assert p["vs_truth"][label]["max_mm"] == pytest.approx(max(p["errors_vs_truth_mm"][label]),
                                                               rel=1e-12)
    assert np.mean(p["errors_mm"]["full"]) < np.mean(p["errors_mm"]["nominal"]) / 10
    # Without `out`, nothing is written and the numbers are the same.
    q = robcal.demo(seed=2, count=40, validation=200)
    assert q["out"] == "" and q["vs_truth"] == p["vs_truth"]


@pytest.fixture(scope="module")
def campaign(tmp_path_factory):
    """A simulated tracker campaign as an SA-style export (metres, names, reversed) and a log."""
    root = tmp_path_factory.mktemp("campaign")
    run("simulate", "--random", "20", "--seed", "2", "--out", str(root / "sim"))
    rows = rows_of(root / "sim" / "measurements.csv")
    with open(root / "log.csv", "w") as log:
        log.write("config;j1;j2;j3;j4;j5;j6\n")
        for r in rows:
            log.write(";".join([r[0], *r[2:8]]) + "\n")
    with open(root / "export.txt", "w") as out:
        out.write("// SA Version 2023.1\n")
        for r in reversed(rows):
            out.write("A::Robot %s %s %s\n" % (r[0], r[1], " ".join(
                "%.17g" % (float(v) / 1000) for v in r[8:11])))
    return root, rows


def test_import_same_file_as_the_cli_and_arrays(campaign):
    root, rows = campaign
    args = dict(columns="collection,group,target,x,y,z", config_column="group", unit="m",
                join="name")
    run("import", "--export", str(root / "export.txt"), "--joints", str(root / "log.csv"),
        "--columns", args["columns"], "--config-column", "group", "--unit", "m", "--join", "name",
        "--out", str(root / "cli.csv"))
    p = robcal.import_measurements(str(root / "export.txt"), str(root / "log.csv"), **args)
    assert p["csv"] == open(root / "cli.csv").read()
    assert p["rows"] == 20 and p["kind"] == "points" and p["warnings"] == []
    # The joined rows are the simulated ones, in the export's (reversed) order, to 1e-9 mm.
    d = p["measurements"].to_dict()
    expected = np.array([[float(v) for v in r[8:11]] for r in reversed(rows)])
    np.testing.assert_allclose(d["position_mm"], expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(d["joints_deg"], [[float(v) for v in r[2:8]] for r in reversed(rows)],
                               rtol=0, atol=1e-12)
    with pytest.raises(robcal.InputError, match="unknown join 'fuzzy'"):
        robcal.import_measurements(str(root / "export.txt"), str(root / "log.csv"), join="fuzzy")


def sweep(tmp_path, name, joints, tool=None):
    plan = tmp_path / f"{name}.csv"
    target = "T" if tool else "1"
    plan.write_text("config,target,j1,j2,j3,j4,j5,j6\n" + "".join(
        f"{name}{k},{target}," + ",".join(map(str, q)) + "\n" for k, q in enumerate(joints)))
    args = ["simulate", "--configs", str(plan), "--seed", str(len(name) + len(joints)), "--out",
            str(tmp_path / name)]
    run(*(args + (["--tool", tool] if tool else [])))
    return str(tmp_path / name / "measurements.csv")


def arrays_of(path):
    rows = rows_of(path)
    return (np.array([[float(v) for v in r[2:8]] for r in rows]),
            np.array([[float(v) for v in r[8:11]] for r in rows]))


def test_frames_base_and_tool_as_the_cli_and_from_arrays(tmp_path):
    s1 = sweep(tmp_path, "A", [[q, 0, 0, 0, 0, 0] for q in range(-20, 11, 2)])
    s2 = sweep(tmp_path, "B", [[0, q, 0, 0, 0, 0] for q in range(0, 41, 3)])
    c = json.loads(run("frames", "base", "--robot", "abb-irb120", "--joint1", s1, "--joint2", s2,
                       "--out", str(tmp_path / "base.yaml"), "--json").stdout)
    p = robcal.frames_base("abb-irb120", s1, s2)
    assert p["text"] == open(tmp_path / "base.yaml").read()
    assert c["base"] == {k: v for k, v in p["base"].items() if k != "covariance"}
    sigma = np.sqrt(np.diag(p["base"]["covariance"]))
    np.testing.assert_allclose(sigma[:3], p["base"]["sigma_position_mm"], rtol=1e-12)
    np.testing.assert_allclose(np.degrees(sigma[3:]), p["base"]["sigma_rotation_deg"], rtol=1e-12)
    robot = robcal.load_robot("abb-irb120")
    a = robcal.base_from_sweeps(robot, *arrays_of(s1), *arrays_of(s2))
    # The file holds what the arrays hold (17 digits): the same fit.
    np.testing.assert_allclose(a["position_mm"], p["base"]["position_mm"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(a["rotation_xyz_deg"], p["base"]["rotation_xyz_deg"], rtol=0,
                               atol=1e-9)

    tool = tmp_path / "t.yaml"
    tool.write_text('payload: {mass_kg: 2.6, cog_mm: [-23, 0, 100]}\ntargets:\n  "T": [30, 0, 200]\n')
    s5 = sweep(tmp_path, "E", [[-5, 0, 0, 0, q, 0] for q in range(0, 37, 3)], str(tool))
    s6 = sweep(tmp_path, "F", [[-5, 0, 0, 0, 23, q] for q in range(-170, 171, 10)], str(tool))
    c = json.loads(run("frames", "tool", "--robot", "abb-irb120", "--joint5", s5, "--joint6", s6,
                       "--target", "T", "--tool", str(tool), "--out", str(tmp_path / "tool.yaml"),
                       "--json").stdout)
    p = robcal.frames_tool("abb-irb120", s5, s6, target="T", tool=str(tool))
    assert p["text"] == open(tmp_path / "tool.yaml").read()
    assert {k: v for k, v in c.items() if k != "out"} == \
        {k: v for k, v in p.items() if k not in ("covariance", "text")}
    a = robcal.tool_from_sweeps(robot, *arrays_of(s5), *arrays_of(s6))
    np.testing.assert_allclose(a["position_mm"], p["position_mm"], rtol=0, atol=1e-9)
    # The simulated target is at (30, 0, 200) mm; the published truth's link errors are not
    # modelled by the circle fits: within 2 mm.
    np.testing.assert_allclose(p["position_mm"], [30, 0, 200], atol=2)

    # The same target from 12 random configurations with the default cell's base.
    run("simulate", "--tool", str(tool), "--random", "12", "--seed", "9", "--out",
        str(tmp_path / "op"))
    cell = os.path.join(ROOT, "data", "cells", "default-tracker.yaml")
    rows = str(tmp_path / "op" / "measurements.csv")
    c = json.loads(run("frames", "point", "--robot", "abb-irb120", "--cell", cell, "--target", "T",
                       "--measurements", rows, "--out", str(tmp_path / "point.yaml"),
                       "--json").stdout)
    p = robcal.frames_point("abb-irb120", cell, rows, target="T")
    assert p["text"] == open(tmp_path / "point.yaml").read()
    assert {k: v for k, v in c.items() if k != "out"} == \
        {k: v for k, v in p.items() if k not in ("covariance", "text")}
    np.testing.assert_allclose(p["position_mm"], [30, 0, 200], atol=3)


def test_frame_from_nests_recovers_a_known_placement(tmp_path):
    nominal = np.array([[0, 0, 0], [400, 0, 0], [0, 300, 0], [400, 300, 50.0]])
    angle = math.radians(30)
    R = np.array([[math.cos(angle), -math.sin(angle), 0], [math.sin(angle), math.cos(angle), 0],
                  [0, 0, 1]])
    t = np.array([-900.0, 1000.0, -50.0])
    measured = nominal @ R.T + t
    f = robcal.frame_from_nests(measured, nominal)
    np.testing.assert_allclose(f["position_mm"], t, atol=1e-9)
    np.testing.assert_allclose(f["rotation_xyz_deg"], [0, 0, 30], atol=1e-9)
    assert f["rms_mm"] < 1e-9
    (tmp_path / "n.csv").write_text("".join(f"N{i},{x},{y},{z}\n" for i, (x, y, z) in
                                            enumerate(nominal)))
    (tmp_path / "m.csv").write_text("".join(f"N{i},{x!r},{y!r},{z!r}\n" for i, (x, y, z) in
                                            enumerate(measured)))
    c = json.loads(run("frames", "world", "--measured", str(tmp_path / "m.csv"), "--nominal",
                       str(tmp_path / "n.csv"), "--out", str(tmp_path / "w.yaml"), "--json").stdout)
    p = robcal.frames_world(str(tmp_path / "m.csv"), str(tmp_path / "n.csv"))
    assert p["text"] == open(tmp_path / "w.yaml").read()
    assert c["frame"] == {k: v for k, v in p["frame"].items() if k != "covariance"}
    # The instrument (origin of the measured frame) in the nests' frame: −Rᵀt.
    np.testing.assert_allclose(p["instrument_position_mm"], -R.T @ t, atol=1e-9)


def test_session_journal_replays_and_matches_the_cli(tmp_path):
    run("simulate", "--random", "6", "--seed", "7", "--out", str(tmp_path / "ss"))
    rows = rows_of(tmp_path / "ss" / "measurements.csv")
    plan = tmp_path / "plan.csv"
    plan.write_text("config,target,j1,j2,j3,j4,j5,j6\n" + "".join(",".join(r[:8]) + "\n"
                                                                    for r in rows))
    xyz = {r[0]: [float(v) for v in r[8:11]] for r in rows}
    s = robcal.PointSession(str(plan), reference=0, every=3)
    answers = []
    while s.next_step is not None:
        step = s.next_step
        config = rows[step["config"]][0]
        if config == "R5":
            answers.append("skip")
            s.answer("skip", time="2026-11-25T00:00:00Z")
        else:
            # Drift checks read the reference 0.003 mm higher each time.
            p = np.array(xyz[config]) + ([0, 0, 0.003 * len(answers)] if step["drift_check"]
                                         else 0)
            answers.append(" ".join(repr(v) for v in p))
            s.add_reading(p, time="2026-11-25T00:00:00Z", temperature_c=21.5)
    result = s.result()
    assert result["missing"] == ["R5"] and len(result["measurements"]) == 5
    for d in result["drift"]:
        index = [st["key"] for st in s.steps].index(d["key"])
        assert d["drift_mm"] == pytest.approx(0.003 * index, abs=1e-9)
        assert d["temperature_c"] == 21.5
    # A new session resumed from the journal's text (a torn last line dropped) is the same.
    journal = s.journal()
    torn = journal + "R1/1,1.0,2"
    resumed = robcal.PointSession(str(plan), reference=0, every=3)
    assert resumed.replay(torn) == len(journal)
    assert resumed.answered == len(s.steps) and resumed.journal() == journal
    assert resumed.result()["measurements"].to_csv() == result["measurements"].to_csv()
    (tmp_path / "j.txt").write_text(journal)
    assert robcal.PointSession(str(plan), reference=0, every=3).load_journal(
        str(tmp_path / "j.txt")) == len(s.steps)
    # The CLI session with the same answers writes the same measurements.
    run("session", "--configs", str(plan), "--reference", "R1", "--every", "3", "--journal",
        str(tmp_path / "cli.jsonl"), "--out", str(tmp_path / "cli.csv"),
        stdin="\n".join(answers) + "\n")
    cli = robcal.Measurements.from_file(str(tmp_path / "cli.csv"), result["measurements"].tool)
    np.testing.assert_array_equal(cli.to_dict()["position_mm"],
                                  result["measurements"].to_dict()["position_mm"])
    with pytest.raises(robcal.InputError, match="every step is answered"):
        s.add_reading(None)
