"""ISO 9283 from Python: the plan equals the CLI's files (the same library call), the
multi-directional pre-poses lie 50 mm back along the world axes, and the analysis of cycles
equals the CLI's JSON and the formulas written out."""
import csv
import io
import json
import os
import subprocess

import numpy as np
import pytest

import robcal

CLI = os.environ.get("ROBCAL_CLI")
REGION = ([300, -150, 300], [500, 150, 520])


def plan(**kw):
    robot = robcal.CalibratedRobot.nominal(robcal.load_robot("abb-irb120"))
    return robcal.iso9283_plan(robot, *REGION, **kw)


def test_plan_and_approaches():
    p = plan(cycles=3, vap_approach_mm=50)
    assert p["cube_edge_mm"] == pytest.approx(200)
    np.testing.assert_allclose(p["poses"][0]["position_mm"], [400, 0, 410], atol=1e-12)
    assert [s[1] for s in p["sequence"][:5]] == [0, 4, 3, 2, 1]
    assert len(p["vap_sequence"]) == 3 * 3 * 5 * 2
    for pose, three in zip(p["poses"], p["approaches"]):
        for h, a in enumerate(three):
            back = np.zeros(3)
            back[h] = -50
            np.testing.assert_allclose(np.array(a["position_mm"]) - pose["position_mm"], back,
                                       atol=1e-9)
    assert plan(cycles=3)["approaches"] == []
    with pytest.raises(robcal.InputError, match="--vap-approach"):
        plan(vap_approach_mm=-1)


def measurements(pose_list_csv):
    """30 cycles: every pose 0.05 mm off in x and ±0.01 mm in y (alternating)."""
    out = io.StringIO()
    out.write("pose,cycle,x,y,z\n")
    for row in csv.DictReader(io.StringIO(pose_list_csv)):
        for cycle in range(1, 31):
            dy = 0.01 if cycle % 2 else -0.01
            out.write(f"{row['name']},{cycle},{float(row['x']) + 0.05},"
                      f"{float(row['y']) + dy},{row['z']}\n")
    return out.getvalue()


def test_analyse_against_the_formulas(tmp_path):
    p = plan()
    (tmp_path / "poses.csv").write_text(p["pose_list_csv"])
    (tmp_path / "m.csv").write_text(measurements(p["pose_list_csv"]))
    r = robcal.iso9283_analyse(str(tmp_path / "poses.csv"), str(tmp_path / "m.csv"))
    for f in r["poses"]:
        # AP: the barycentre is 0.05 mm off in x; RP: every l_j = 0.01 mm, S_l = 0.
        assert f["AP_mm"] == pytest.approx(0.05, abs=1e-9)
        assert f["RP_mm"] == pytest.approx(0.01, abs=1e-9)
    assert r["distance"]["AD_mm"] == pytest.approx(0, abs=1e-9)
    with pytest.raises(robcal.InputError, match="at least 31"):
        robcal.iso9283_analyse(str(tmp_path / "poses.csv"), str(tmp_path / "m.csv"),
                               min_cycles=31)


@pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")
def test_same_as_the_cli(tmp_path):
    p = plan(cycles=4, vap_approach_mm=30)
    subprocess.run([CLI, "iso9283", "plan", "--robot", "abb-irb120", "--region",
                    "300,-150,300,500,150,520", "--cycles", "4", "--vap-approach", "30",
                    "--out-poses", str(tmp_path / "p.csv"), "--out-cycles",
                    str(tmp_path / "c.csv"), "--out-vap-cycles", str(tmp_path / "v.csv")],
                   check=True, capture_output=True)
    assert (tmp_path / "p.csv").read_text() == p["pose_list_csv"]
    assert (tmp_path / "c.csv").read_text() == p["cycles_csv"]
    assert (tmp_path / "v.csv").read_text() == p["vap_cycles_csv"]
    (tmp_path / "m.csv").write_text(measurements(p["pose_list_csv"]))
    out = subprocess.run([CLI, "iso9283", "analyse", "--poses", str(tmp_path / "p.csv"),
                          "--measurements", str(tmp_path / "m.csv"), "--json"],
                         check=True, capture_output=True, text=True)
    c = json.loads(out.stdout)
    r = robcal.iso9283_analyse(str(tmp_path / "p.csv"), str(tmp_path / "m.csv"))
    assert c["poses"] == r["poses"] and c["distance"] == r["distance"]
