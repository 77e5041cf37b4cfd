"""The ballbar hexapod of docs/method/07-hexapod.md (mm): fixtures, direct kinematics, the 72 poses, uncertainty,
world frame, planning and its plan file."""
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np
import numpy.typing as npt

Array = npt.NDArray[np.float64]


class Plan:
    """A hexapod measurement plan (`robcal hexapod plan`): the session's configurations and, when
    planned here, the cell and the outcome."""

    joints_deg: Array
    """N×6 controller joints (deg) of the configurations (NaN rows: pose-only plan)."""
    poses: List[str]
    """Pose label of each configuration."""
    labels: List[str]
    """Arm configuration label of each configuration."""
    setting_ball_mm: Optional[Array]
    """Where the robot puts the setting ball for B1..B3, and B4 with a fourth base cup (3×3
    or 4×3, robot frame, mm), or None."""

    def to_json(self) -> str:
        """The plan file's text (what `robcal hexapod plan --out` writes)."""

    def save(self, path: str) -> None:
        """Writes the plan file, whole or not at all."""

    def __len__(self) -> int:
        """Number of configurations."""


def triangle_from_sides(sides_mm: Sequence[float]) -> Array:
    """Cup positions (rows) from d12, d23, d31: c1 at the origin, c2 on x, c3 in the xy plane."""


def tripod(v1: npt.ArrayLike, v2: npt.ArrayLike, v3: npt.ArrayLike, l1: float, l2: float,
           l3: float, sign: int) -> Optional[Array]:
    """Tri of docs/method/07-hexapod.md; None when there is no real solution."""


def solve_dkp(base_sides_mm: Sequence[float], tool_sides_mm: Sequence[float],
              legs_mm: Sequence[float]) -> Dict[str, Any]:
    """Tool cups (rows, base fixture frame) by assembly mode 1..4 from b_ij, t_ij and the legs
    ρ11, ρ12, ρ21, ρ22, ρ23, ρ31."""


def solve_four_cup_dkp(base_mm: Sequence[float], tool_mm: Sequence[float],
                       legs: Sequence[Tuple[int, int, float]]) -> Dict[str, Any]:
    """`robcal hexapod dkp` with a fourth cup: the least-squares cup positions (base fixture
    frame, mm) from the fixtures' distances (d12, d23, d31, and d14, d24, d34 for a fourth cup)
    and the legs as (base cup, tool cup, length mm) with cups 1..4; the CLI's JSON as a dict
    (docs/method/07-hexapod.md §7); InputError naming the bad argument."""


def leg_lengths(base_cups: npt.ArrayLike, tool_cups: npt.ArrayLike) -> List[float]:
    """The six legs of design 1^12 2^123 3^1."""


def enumerate_poses(base_sides_mm: Sequence[float] = ..., tool_sides_mm: Sequence[float] = ...,
                    leg_mm: float = 300.0, angle_deg: float = 0.0,
                    distance_mm: float = 0.0) -> List[Dict[str, Any]]:
    """The poses (72 before pruning) with every leg at leg_mm, pruned at the given distances."""


def uncertainty(base_mm: float = 300.0, tool_mm: float = 150.0, leg_mm: float = 300.0,
                sigma_um: float = 0.51, samples: int = 20000,
                seed: int = 1) -> List[Dict[str, Any]]:
    """Per mode: sensitivity (9×12), σ per axis and norm of each tool cup in multiples of σ,
    analytic and Monte Carlo."""


def fit_world_frame(robot_points: npt.ArrayLike,
                    measured_sides_mm: Sequence[float]) -> Dict[str, Any]:
    """World frame from the base cups: planar least-squares correction; planar = (x mm, y mm,
    φ deg)."""


def plan(robot: str = "fanuc-lrmate200ic", base_sides_mm: Sequence[float] = ...,
         tool_sides_mm: Sequence[float] = ..., leg_mm: float = 300.0,
         placement: Tuple[float, float, float, float] = ..., tilt_deg: float = 0.0,
         tool_offset_mm: float = 100.0, ball_offset_mm: float = 100.0, table_z_mm: float = 0.0,
         angle_deg: float = 30.0, distance_mm: float = 50.0, gauge_range_mm: float = 1.0,
         gauge_sigma_mm: float = 0.00051, cup_diameter_mm: float = 25.0,
         cell: Optional[str] = None,
         tool_cup4_mm: Optional[Tuple[float, float, float]] = None,
         base_cup4_mm: Optional[Tuple[float, float, float]] = None) -> Plan:
    """Plans a hexapod measurement (`robcal hexapod plan`): placement = (x, y, z mm, yaw deg) of
    the base cups' centroid in the robot frame, tilt_deg of the pivoting platform, the gauge's
    range and σ, the cup diameter (colliding poses refused), a cell file (its floor and
    keep-out boxes respected), a fourth tool cup by its distances (d14, d24, d34) to T1..T3
    (`--tool-cup4-mm`: its legs within half the gauge range are measured too) and a fourth base
    cup by its distances to B1..B3 (`--base-cup4-mm`: placed by the robot, its legs likewise)."""


def read_plan(path: str) -> Plan:
    """Reads a plan file (written by `robcal hexapod plan` or `replan`, or by hand)."""


def setup(robot: str = "fanuc-lrmate200ic", placement: Tuple[float, float, float, float] = ...,
          tilt_deg: float = 0.0, side_mm: float = 300.0,
          ball_offset_mm: float = 100.0,
          base_cup4_mm: Optional[Tuple[float, float, float]] = None) -> Dict[str, Any]:
    """Where to put the setting ball for each base cup (`robcal hexapod setup`): the CLI's JSON
    as a dict, setting_ball holding per cup its position (robot frame, mm) and the
    configurations reaching it (labels, joints_deg); B4 too with a fourth base cup by its
    distances to B1..B3 (`--base-cup4-mm`)."""


def simulate(robot: str = "fanuc-lrmate200ic", placement: Tuple[float, float, float, float] = ...,
             tool_offset_mm: float = 100.0, ball_offset_mm: float = 100.0,
             table_z_mm: float = 0.0, angle_deg: float = 30.0, distance_mm: float = 50.0,
             seed: int = 1, validation: int = 10000, threads: int = 2, leg_fit: bool = True,
             relative: bool = False,
             tool_cup4_mm: Optional[Tuple[float, float, float]] = None,
             base_cup4_mm: Optional[Tuple[float, float, float]] = None) -> Dict[str, Any]:
    """Simulated end to end (`robcal hexapod simulate`): placement, planning, ballbar readings,
    preliminary and final calibration, laser-tracker validation; a fourth tool cup by its
    distances (d14, d24, d34) to T1..T3 (`--tool-cup4-mm`), a fourth base cup by its distances
    to B1..B3 (`--base-cup4-mm`); the CLI's JSON as a dict."""


def place(robot: str = "fanuc-lrmate200ic", x_mm: Sequence[float] = ..., y_mm: Sequence[float] = ...,
          z_mm: Sequence[float] = ..., yaw_deg: Sequence[float] = ...,
          tilt_deg: Sequence[float] = ..., level: str = "kinematic", validation: int = 2000,
          seed: int = 1, best: int = 5, measured: Sequence[str] = ...,
          base_sides_mm: Sequence[float] = ..., tool_sides_mm: Sequence[float] = ...,
          leg_mm: float = 300.0, tool_offset_mm: float = 100.0, ball_offset_mm: float = 100.0,
          table_z_mm: float = 0.0, angle_deg: float = 30.0, distance_mm: float = 50.0,
          gauge_range_mm: float = ..., gauge_sigma_mm: float = ..., cup_diameter_mm: float = ...,
          cell: Optional[str] = None,
          tool_cup4_mm: Optional[Tuple[float, float, float]] = None,
          identify: Sequence[str] = ...,
          base_cup4_mm: Optional[Tuple[float, float, float]] = None,
          task_box: Optional[str] = None) -> Dict[str, Any]:
    """Placement search (`robcal hexapod place`): the grid's placements ranked by predicted
    accuracy, and the best pairs; with `measured` (plan files of the placements already
    measured) the grid's placements ranked as the next one ('next'); the fixtures, offsets,
    pruning, gauge (range and σ, mm), cup diameter, cell file and fourth cups as plan()'s
    (the CLI's flags); `identify`: opt-in groups or patterns predicted for too (`--identify`);
    `task_box` "xmin,xmax,ymin,ymax,zmin,zmax" (mm, robot frame): the task region the
    predictions are over (`--task-box`; default the whole workspace); the CLI's JSON as a dict."""


def design(plans: Sequence[str], count: int = 0, level: str = "kinematic", validation: int = 2000,
           seed: int = 1, out: Sequence[str] = ...,
           identify: Sequence[str] = ..., task_box: Optional[str] = None) -> Dict[str, Any]:
    """Which configurations to measure at each of several planned placements (`robcal hexapod
    design`): plans = plan files written by plan(), count = configurations in all (0: as many as
    the first plan offers); `out` = one reduced plan file per plan (none written for a placement
    with nothing chosen); `identify` and `task_box` as place()'s; the CLI's JSON as a dict."""


def device_validation(base_sides_mm: Tuple[float, float, float] = ...,
                      tool_sides_mm: Tuple[float, float, float] = ..., leg_mm: float = 300.0,
                      gauge_range_mm: float = 1.0, gauge_sigma_mm: float = 0.00051,
                      reference_sigma_mm: float = 0.005, poses: int = 2000,
                      seed: int = 1) -> Dict[str, Any]:
    """The hexapod against an independent instrument (`robcal hexapod device-validation`): per
    assembly mode, GUM and simulated scatter; the CLI's JSON as a dict."""


def replan(sessions: Sequence[str], model: str, out: str,
           plan: Optional[str] = None) -> Dict[str, Any]:
    """Re-plans the configurations to retry of measured sessions on a preliminary calibrated
    model (`robcal hexapod replan`), writes the new plan to `out`, returns the CLI's JSON."""


def simulate_readings(plan: Plan, robot: str = "fanuc-lrmate200ic", payload: Optional[Any] = None,
                      seed: int = 1, validation: int = 1000) -> Dict[str, Any]:
    """Simulated readings of a planned session (`robcal hexapod simulate-readings`): the CLI's
    JSON as a dict (seed, readings, legs_out_of_range) with text (the session's input), tool (the
    tool fixture as a Tool) and validation (tracker Measurements on cup T1) in place of the
    files; `payload` is a Tool whose payload the robot carries (default 2.6 kg at (50, 25, 100)
    mm)."""


def session(plan: str, journal: str, answers: Sequence[str], resume: bool = False,
            out: Optional[str] = None) -> Dict[str, Any]:
    """The guided session (`robcal hexapod session`) fed `answers` (lines: a reading in mm, 'out',
    'quit'; e.g. simulate_readings' text.splitlines()) instead of a terminal; every reading
    journalled at once, `resume` continues a journal. The CLI's JSON as a dict (status complete or
    paused-…, replayed, answered, result when complete: also written to `out`) plus transcript
    (the prompts and messages) and refused (answers asked again)."""


def export_poses(sessions: Sequence[str], out: str, legs_out: Optional[str] = None,
                 tool_out: Optional[str] = None, tool: Optional[str] = None,
                 plan: Optional[str] = None) -> Dict[str, Any]:
    """Writes a session's readings as a poses measurement CSV `out` (for calibrate), and the raw
    legs CSV and the tool file when given (`robcal hexapod export-poses`); `tool`: the tool file
    whose payload the robot carried. The CLI's JSON as a dict plus tool_fixture (Tool) and
    measurements (the poses as Measurements)."""


def calibrate(sessions: Sequence[str], robot: str = "fanuc-lrmate200ic",
              tool: Optional[str] = None, level: str = "full", fit: str = "poses",
              relative: bool = False, orientation_weight_mm: float = 100.0, seed: int = 1,
              plan: Optional[str] = None, out: Optional[str] = None,
              identify: Sequence[str] = ...) -> Dict[str, Any]:
    """Calibrates from measured sessions (`robcal hexapod calibrate`; sessions of several
    base-fixture placements together with fit='legs'): the CLI's JSON as a dict
    plus model (CalibratedRobot), tool (the tool fixture) and poses (Measurements); with `out` the
    calibrated model file is written."""
