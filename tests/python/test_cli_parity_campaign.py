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
