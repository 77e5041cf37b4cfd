"""The opt-in groups' conditions (issue 19) from Python and the CLI: simulate --clock, calibrate
--warmup-tau-s, compensate --warmup-time-s / --warm and a targets file's time_s column, import
--configs. Both call the same library functions, so the numbers and files are the same."""
import csv
import json
import os
import subprocess

import numpy as np
import pytest

import robcal

CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")


def cli_json(*args):
    out = subprocess.run([CLI, *args, "--json"], check=True, capture_output=True, text=True)
    return json.loads(out.stdout)


def cli_refusal(*args):
    out = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert out.returncode == 2, out.stderr
    return out.stderr


def column(path, name):
    with open(path) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return [row[name] for row in rows]


@pytest.fixture(scope="module")
def warming(tmp_path_factory):
    """A warming IRB 120 (the simulator's thermal drift) measured 80 times by the CLI, each row
    recording its time instead of the arm's temperature, and a model calibrated with the warm-up
    group by the CLI."""
    root = tmp_path_factory.mktemp("warming")
    summary = cli_json("simulate", "--effects", "thermal", "--clock", "--random", "80", "--seed",
                       "6", "--noise-mm", "0.01", "--out", str(root / "sim"))
    files = summary["files"]
    model = str(root / "model.yaml")
    cli_json("calibrate", "--robot", "abb-irb120", "--tool", files["tool"], "--measurements",
             files["measurements"], "--identify", "warmup", "--out", model)
    return summary, model


def test_simulate_clock(warming, tmp_path):
    summary, _ = warming
    p = robcal.simulate(effects=["thermal"], clock=True, count=80, seed=6, noise_mm=0.01,
                        out=str(tmp_path))
    assert {k: v for k, v in p["summary"].items() if k != "files"} == \
        {k: v for k, v in summary.items() if k != "files"}
    measurements = summary["files"]["measurements"]
    assert open(p["summary"]["files"]["measurements"]).read() == open(measurements).read()
    times = np.array([float(t) for t in column(measurements, "time_s")])
    np.testing.assert_array_equal(p["time_s"], times)
    assert np.isnan(p["temperature_c"]).all()
    assert p["time_s"][0] == 0 and np.all(np.diff(p["time_s"]) > 0)
    # Without the clock the rows record the arm's temperature instead.
    thermometer = robcal.simulate(effects=["thermal"], count=80, seed=6, noise_mm=0.01)
    assert np.isnan(thermometer["time_s"]).all()
    assert np.all(thermometer["temperature_c"] >= 20) and thermometer["temperature_c"][-1] > 21


def test_calibrate_warmup_tau(warming, tmp_path):
    summary, _ = warming
    tool, rows = summary["files"]["tool"], summary["files"]["measurements"]
    out = str(tmp_path / "tau.yaml")
    c = cli_json("calibrate", "--robot", "abb-irb120", "--tool", tool, "--measurements", rows,
                 "--identify", "warmup", "--warmup-tau-s", "1200", "--out", out)
    p = robcal.calibrate("abb-irb120", tool, rows, identify=["warmup"], warmup_tau_s=1200)
    assert c["rms_mm"] == pytest.approx(p.rms_mm, rel=0, abs=5.1e-10)
    table = p.parameter_table
    assert [x["name"] for x in c["parameters"]] == table["name"]
    np.testing.assert_allclose([x["value"] for x in c["parameters"]], table["value"], rtol=1e-12,
                               atol=1e-12)
    # The time constant reaches the fit: the growths differ from those of the default 1800 s,
    # and the model keeps it for compensation.
    default = robcal.calibrate("abb-irb120", tool, rows, identify=["warmup"])
    growth = [i for i, n in enumerate(table["name"]) if n == "link3.warmup_growth"][0]
    assert abs(table["value"][growth] - default.parameter_table["value"][growth]) > 1e-4
    p.save(str(tmp_path / "py.yaml"))
    assert "warmup_time_constant_s: 1200" in open(out).read()
    assert open(tmp_path / "py.yaml").read().count("warmup_time_constant_s: 1200") == 1
    message = "warm-up time constant 0.5 s: expected seconds in [1, 1e6]"
    assert message in cli_refusal("calibrate", "--robot", "abb-irb120", "--tool", tool,
                                  "--measurements", rows, "--identify", "warmup",
                                  "--warmup-tau-s", "0.5", "--out", str(tmp_path / "x.yaml"))
    with pytest.raises(robcal.InputError, match=r"warm-up time constant 0\.5 s"):
        robcal.calibrate("abb-irb120", tool, rows, identify=["warmup"], warmup_tau_s=0.5)


def targets_file(path, model, times=None):
    """12 poses the calibrated model reaches (world frame), with a time_s column when given."""
    comp = robcal.Compensator.from_model(model)
    rng = np.random.default_rng(19)
    lines = ["name,x,y,z,qw,qx,qy,qz" + (",time_s" if times else "")]
    for k in range(12):
        pose = comp.tcp_pose(rng.uniform([-60, 20, -40, -90, 30, -90], [60, 70, 30, 90, 90, 90]))
        cells = [f"p{k}", *(f"{v:.9f}" for v in pose["position_mm"]),
                 *(f"{v:.12f}" for v in pose["quaternion_wxyz"])]
        if times:
            cells.append(times[k % len(times)])
        lines.append(",".join(cells))
    path.write_text("\n".join(lines) + "\n")
    return str(path)


def test_compensate_warmup_time_and_warm(warming, tmp_path):
    summary, model = warming
    truth = summary["files"]["truth"]
    targets = targets_file(tmp_path / "t.csv", model)
    csvs = []
    for flags, kwargs in ((["--warmup-time-s", "900"], {"warmup_time_s": 900}),
                          (["--warm"], {"warm": True})):
        out = str(tmp_path / "cli.csv")
        c = cli_json("compensate", "--model", model, "--targets", targets, "--out", out,
                     "--check-truth", truth, *flags)
        p = robcal.Compensator.from_model(model, **kwargs).compensate_targets(
            targets, check_truth=truth)
        assert p["csv"] == open(out).read()
        assert {k: v for k, v in c.items() if k != "out"} == \
            {k: p[k] for k in c if k != "out"}
        assert c["closed_loop"]["compensated"]["count"] == 12
        csvs.append(p["csv"])
    # The warm-up reaches the compensation: 900 s and warm correct the targets differently.
    assert csvs[0] != csvs[1]
    with pytest.raises(robcal.InputError, match="give either the warm-up time or --warm"):
        robcal.Compensator.from_model(model, warmup_time_s=900, warm=True)
    with pytest.raises(robcal.InputError, match="expected seconds in"):
        robcal.Compensator.from_model(model, warmup_time_s=-5)


def test_targets_at_their_own_time(warming, tmp_path):
    summary, model = warming
    truth = summary["files"]["truth"]
    targets = targets_file(tmp_path / "t.csv", model, ["0", "600", "warm", ""])
    out = str(tmp_path / "cli.csv")
    c = cli_json("compensate", "--model", model, "--targets", targets, "--out", out,
                 "--warmup-time-s", "900", "--check-truth", truth)
    p = robcal.Compensator.from_model(model, warmup_time_s=900).compensate_targets(
        targets, check_truth=truth)
    assert p["csv"] == open(out).read()
    assert {k: v for k, v in c.items() if k != "out"} == {k: p[k] for k in c if k != "out"}
    assert c["conditions"] == 4
    # Each row's own time, the run's 900 s where its cell is empty; written back in the CSV.
    np.testing.assert_array_equal(p["warmup_time_s"], [0, 600, np.inf, 900] * 3)
    assert column(out, "time_s") == ["0", "600", "warm", "900"] * 3
    # The row's time is the one compensated for: the same target at the run's 900 s differs.
    run = robcal.Compensator.from_model(model, warmup_time_s=900).compensate_targets(
        targets_file(tmp_path / "plain.csv", model))
    assert not np.allclose(p["joints_deg"][0], run["joints_deg"][0], rtol=0, atol=1e-9)
    np.testing.assert_allclose(p["joints_deg"][3], run["joints_deg"][3], rtol=0, atol=1e-9)
    bad = tmp_path / "bad.csv"
    bad.write_text("name,x,y,z,qw,qx,qy,qz,time_s\np1,400,0,500,0,0,1,0,-5\n")
    message = "bad.csv:2:22 (time_s): time -5 s is implausible"
    assert message in cli_refusal("compensate", "--model", model, "--targets", str(bad),
                                  "--out", str(tmp_path / "x.csv"))
    with pytest.raises(robcal.InputError, match=r"bad\.csv:2:22 \(time_s\): time -5 s"):
        robcal.Compensator.from_model(model).compensate_targets(str(bad))


PLAN = """config,target,j1,j2,j3,j4,j5,j6,approach,payload
c3,,10,40,10,20,50,30,+-+-++,gripper
c1,,-20,30,5,10,40,20,-+++++,
c2,,0,35,15,-10,60,10,++++++,empty
"""


def test_import_with_the_plan(tmp_path):
    plan = tmp_path / "plan.csv"
    plan.write_text(PLAN)
    log = tmp_path / "log.csv"
    log.write_text("config,j1,j2,j3,j4,j5,j6\nc1,-20,30,5,10,40,20\nc2,0,35,15,-10,60,10\n"
                   "c3,10,40,10,20,50,30\n")
    export = tmp_path / "export.csv"
    export.write_text("x,y,z\n400,0,500\n410,5,490\n420,10,480\n")
    out = str(tmp_path / "cli.csv")
    c = cli_json("import", "--export", str(export), "--joints", str(log), "--configs", str(plan),
                 "--target", "1", "--out", out)
    p = robcal.import_measurements(str(export), str(log), target="1", configs=str(plan))
    assert p["csv"] == open(out).read()
    assert {k: v for k, v in c.items() if k != "out"} == {k: p[k] for k in c if k != "out"}
    # Joined by the log's configuration names, not the plan's order.
    assert column(out, "config") == ["c1", "c2", "c3"]
    assert column(out, "approach") == ["-+++++", "++++++", "+-+-++"]
    assert column(out, "payload") == ["", "empty", "gripper"]
    lacking = tmp_path / "lacking.csv"
    lacking.write_text("\n".join(PLAN.splitlines()[:3]) + "\n")
    message = f"{log}:3 (config): configuration 'c2' is not in the plan {lacking} (--configs)"
    assert message in cli_refusal("import", "--export", str(export), "--joints", str(log),
                                  "--configs", str(lacking), "--target", "1", "--out",
                                  str(tmp_path / "x.csv"))
    with pytest.raises(robcal.InputError, match="configuration 'c2' is not in the plan"):
        robcal.import_measurements(str(export), str(log), target="1", configs=str(lacking))
