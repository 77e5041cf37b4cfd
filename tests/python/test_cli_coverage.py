"""Every CLI command has its Python function (issue 14 item 3): the commands `robcal --help` and
each command's --help list are the keys of PYTHON below, each naming an attribute of the
package, so that a new command without its Python function (or a binding without its command)
shows here."""
import os
import re
import subprocess

import pytest

import robcal
import robcal.hexapod

CLI = os.environ.get("ROBCAL_CLI")
pytestmark = pytest.mark.skipif(not CLI, reason="ROBCAL_CLI names the robcal program")

PYTHON = {
    "robots": "robot_catalogue",
    "robot show": "robot_description",
    "fk": "fk",
    "ik": "ik",
    "plan": "plan",
    "plan-study": "plan_study",
    "program": "write_measurement_program",
    "import": "import_measurements",
    "frames base": "frames_base",
    "frames tool": "frames_tool",
    "frames point": "frames_point",
    "frames world": "frames_world",
    "session": "point_session",
    "simulate": "simulate",
    "calibrate": "calibrate",
    "validate": "validate",
    "iso9283 plan": "iso9283_plan_files",
    "iso9283 analyse": "iso9283_analyse",
    "axis-test plan": "axis_test_plan",
    "axis-test analyse": "axis_test_analyse",
    "ballbar-path": "ballbar_path",
    "compensate": "Compensator.compensate_targets",
    "compensate-program": "Compensator.compensate_program",
    "hexapod dkp": "hexapod.solve_dkp",
    "hexapod poses": "hexapod.enumerate_poses",
    "hexapod uncertainty": "hexapod.uncertainty",
    "hexapod device-validation": "hexapod.device_validation",
    "hexapod world-frame": "hexapod.fit_world_frame",
    "hexapod setup": "hexapod.setup",
    "hexapod plan": "hexapod.plan",
    "hexapod place": "hexapod.place",
    "hexapod design": "hexapod.design",
    "hexapod simulate": "hexapod.simulate",
    "hexapod calibrate": "hexapod.calibrate",
    "hexapod replan": "hexapod.replan",
    "hexapod simulate-readings": "hexapod.simulate_readings",
    "hexapod session": "hexapod.session",
    "hexapod export-poses": "hexapod.export_poses",
    "model import": "model_import",
    "model export": "model_export",
    "report": "report",
    "demo": "demo",
    "montecarlo": "montecarlo",
    "experiments": "experiments",
}


def commands(path=()):
    """The command paths under `robcal PATH`, leaves only ("iso9283 plan", not "iso9283")."""
    text = subprocess.run([CLI, *path, "--help"], capture_output=True, text=True,
                          check=True).stdout
    if path and "Subcommands:" not in text:
        return [" ".join(path)]
    body = text.split("Subcommands:", 1)[1] if path else text
    names = re.findall(r"^  ([a-z][a-z0-9-]*)  ", body, re.M)
    return [leaf for name in names for leaf in commands((*path, name))]


def test_every_cli_command_has_a_python_function():
    cli = set(commands())
    assert cli == set(PYTHON), (sorted(cli - set(PYTHON)), sorted(set(PYTHON) - cli))
    for command, name in PYTHON.items():
        obj = robcal
        for part in name.split("."):
            obj = getattr(obj, part, None)
            assert obj is not None, f"{command}: robcal.{name} does not exist"
        assert (obj.__doc__ or "").strip(), f"robcal.{name} has no docstring"
