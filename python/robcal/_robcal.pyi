"""Type stubs of the extension robcal._robcal: millimetres and degrees in and out, quaternions
(w, x, y, z). Bad input raises InputError (a ValueError naming the file, line, column or key)."""
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import hexapod as hexapod

ArrayLike = npt.ArrayLike
Array = npt.NDArray[np.float64]

__version__: str
"""The project's version (CMake's project version)."""


class InputError(ValueError):
    """Bad input: the message names the file, line and column or key and says what was expected."""

    file: str
    """The file (or "<dict>", "<arrays>") the bad input came from; empty for flags."""
    line: int
    """1-based line, 0 when unknown."""
    column: int
    """1-based column, 0 when unknown."""
    key: str
    """YAML key path, CSV column, JSON key or argument name; may be empty."""


class RobotModel:
    """An immutable robot description (MDH table, joint limits, controller coupling)."""

    name: str
    """The robot's name, e.g. "ABB IRB 120"."""
    manufacturer: str
    """The manufacturer."""
    source: str
    """Where the nominal parameters come from (data sheet)."""
    joint_limits_deg: Array
    """6×2 array of [lower, upper] controller joint limits, deg."""
    is_ortho_parallel: bool
    """True when the closed-form IK applies (otherwise ik() is numeric)."""

    @staticmethod
    def from_file(name_or_path: str) -> "RobotModel":
        """A built-in robot by name or a robot file (YAML) by path."""

    @staticmethod
    def from_dict(d: Dict[str, Any]) -> "RobotModel":
        """A robot from a dict with the robot file's fields (errors name the key)."""

    def to_yaml(self) -> str:
        """The robot file's text."""


class Tool:
    """The tool on the flange: named targets (flange frame, mm; unknown ones are identified) and
    the payload. From a tool file, a dict with the file's fields, or targets as arrays."""

    targets: Dict[str, Array]
    """{name: [x, y, z]} in the flange frame, mm (0 for unknown ones)."""
    unknown_targets: List[str]
    """Names of the targets whose coordinates are identified."""
    mass_kg: float
    """Payload mass, kg."""
    cog_mm: Array
    """Payload centre of gravity in the flange frame, mm."""

    def __init__(self, targets: Dict[str, ArrayLike] = ..., unknown: Sequence[str] = ...,
                 mass_kg: float = 0.0, cog_mm: ArrayLike = ...) -> None:
        """Targets {name: [x, y, z]} (flange frame, mm) known; `unknown` names targets whose
        coordinates calibration identifies; payload mass (kg) and centre of gravity (mm)."""

    @staticmethod
    def from_file(path: str) -> "Tool":
        """Reads a tool file (YAML)."""

    @staticmethod
    def from_dict(d: Dict[str, Any]) -> "Tool":
        """A tool from a dict with the tool file's fields (errors name the key)."""

    def to_yaml(self) -> str:
        """The tool file's text."""


class Measurements:
    """Measured rows of one kind (points, poses or distances) with the tool they refer to."""

    kind: str
    """'points', 'poses' or 'distances'."""
    tool: Tool
    """The tool the targets refer to."""
    warnings: List[str]
    """Ignored columns of the file."""

    @staticmethod
    def from_file(path: str, tool: Tool) -> "Measurements":
        """Reads a measurement CSV (any kind)."""

    @staticmethod
    def points(tool: Tool, joints_deg: ArrayLike, targets: Sequence[str],
               positions_mm: ArrayLike) -> "Measurements":
        """Point rows: joints N×6 (deg), target names (N), positions N×3 (mm)."""

    @staticmethod
    def poses(tool: Tool, joints_deg: ArrayLike, positions_mm: ArrayLike,
              quaternions_wxyz: ArrayLike) -> "Measurements":
        """Pose rows of the TCP: joints N×6 (deg), positions N×3 (mm), quaternions N×4."""

    @staticmethod
    def distances(tool: Tool, joints_deg: ArrayLike, targets: Sequence[str],
                  lengths_mm: ArrayLike) -> "Measurements":
        """Ballbar rows: joints N×6 (deg), target names (N), lengths (N, mm)."""

    @staticmethod
    def from_dict(d: Dict[str, Any], tool: Tool) -> "Measurements":
        """Rows from a dict as to_dict() returns it."""

    def to_dict(self) -> Dict[str, Any]:
        """kind, config, target, joints_deg (N×6), position_mm (N×3) and quaternion_wxyz (poses),
        length_mm (distances), warnings."""

    def to_csv(self) -> str:
        """The measurement file's text (reads back to the same numbers)."""

    def __len__(self) -> int:
        """Number of rows."""


class SolverStatus:
    """How the least-squares solver ended."""

    converged: bool
    """True when the solver converged."""
    iterations: int
    """Solver iterations."""
    message: str
    """The solver's own words."""
    initial_rms_mm: float
    """RMS residual at the start (after the rigid fit), mm."""
    final_rms_mm: float
    """RMS residual at the end, mm."""


class UnknownEstimate:
    """One unknown: value ± std in external units (mm, deg, rad/N·mm)."""

    name: str
    """Dotted name, e.g. "link3.a", "target.T1.x"."""
    unit: str
    """External unit."""
    nominal: float
    """Start value."""
    value: float
    """Estimated value."""
    std: float
    """Standard deviation (0 unless identified)."""
    status: str
    """'identified', 'fixed' or 'dropped'."""
    reason: str
    """Why fixed or dropped."""


class NoiseTest:
    """Are the residuals the instrument's noise? RSS/σ² against χ²(m − n)."""

    tested: bool
    """False without a stated instrument σ."""
    instrument_sigma_mm: float
    """The instrument's stated σ per axis, mm."""
    chi_square: float
    """RSS / σ²."""
    dof: int
    """Degrees of freedom, m − n."""
    p_value: float
    """P(χ²_dof ≥ chi_square)."""
    consistent: bool
    """False when the residuals exceed what the instrument's σ explains (misfit)."""


class PredictedAccuracy:
    """Cramér–Rao predicted position error (mm) over configurations."""

    configurations: int
    """Configurations the prediction averages over."""
    mean_mm: float
    """Predicted mean position error, mm."""
    rms_mm: float
    """Predicted RMS position error, mm."""
    max_mm: float
    """Predicted largest position error, mm."""
    measurement_sigma_mm: float
    """The measurement σ the prediction assumes, mm."""
    mean_vs_measurements_mm: float
    """Predicted mean error against new measurements (model plus instrument), mm."""
    rms_vs_measurements_mm: float
    """Predicted RMS error against new measurements, mm."""


class CalibratedRobot:
    """A robot with identified parameters (or the nominal one)."""

    model: RobotModel
    """The nominal robot it was calibrated from."""
    level: str
    """"nominal", "base", "joints", "kinematic" or "full"."""
    base_fitted: bool
    """True when its world frame was fitted (validation needs it)."""
    parameters: Dict[str, float]
    """{name: value} in mm, deg, rad/N·mm."""
    targets: Dict[str, Array]
    """{target name: [x, y, z]} in the flange frame, mm (identified ones filled in)."""

    @staticmethod
    def from_file(path: str) -> "CalibratedRobot":
        """Loads a calibrated model file written by calibrate."""

    @staticmethod
    def from_dict(d: Dict[str, Any]) -> "CalibratedRobot":
        """A calibrated model from a dict with the calibrated model file's fields (errors name
        the key)."""

    @staticmethod
    def nominal(model: RobotModel, tool: Optional[Tool] = None) -> "CalibratedRobot":
        """The nominal robot as a model with no world frame (validate with fit_base=True)."""

    def position(self, joints_deg: ArrayLike, point_flange_mm: ArrayLike) -> Array:
        """World position (mm) of a flange-frame point at controller joints (deg)."""

    def positions(self, joints_deg: ArrayLike, point_flange_mm: ArrayLike) -> Array:
        """position() over the rows of an N×6 joints array (deg): N×3 world positions (mm)."""

    def to_yaml(self) -> str:
        """The calibrated model file's text."""


class IdentificationResult:
    """A calibration and its statistics."""

    robot: CalibratedRobot
    """The calibrated robot."""
    status: SolverStatus
    """How the solver ended."""
    parameters: List[UnknownEstimate]
    """Every unknown (model parameters, then target coordinates, ballbar centre)."""
    residual_count: int
    """Scalar residuals."""
    identified_count: int
    """Identified unknowns."""
    warnings: List[str]
    """Found before fitting: dropped, near-dependent or unloaded parameters, joints outside
    limits, poses without a tcp."""
    sigma_mm: float
    """A-posteriori residual standard deviation, mm."""
    mean_mm: float
    """Mean over rows of the position residual norm, mm."""
    rms_mm: float
    """RMS over rows of the position residual norm, mm."""
    max_mm: float
    """Largest row residual, mm."""
    start_mean_mm: float
    """Mean row residual of the nominal robot after the rigid fit, mm."""
    start_rms_mm: float
    """RMS row residual of the nominal robot after the rigid fit, mm."""
    start_max_mm: float
    """Largest row residual of the nominal robot after the rigid fit, mm."""
    noise_test: NoiseTest
    """The χ² test of the residuals against the instrument's σ (tested when sigma is given)."""
    residuals: Array
    """Residual of each measurement row at the solution, mm (3D position error; the TCP's for
    poses; |length error| for distances)."""
    condition_number: float
    """Of the column-scaled Jacobian at the solution."""
    predicted: PredictedAccuracy
    """Cramér–Rao predicted accuracy of the calibrated robot."""
    correlations: List[Tuple[str, str, float]]
    """Strongest parameter correlations (first, second, ρ)."""
    outliers: List[Tuple[str, int, float]]
    """[(config, line, residual_mm)] of suspected outliers."""
    by_target: Dict[str, Tuple[int, float, float]]
    """{target: (rows, rms_mm, max_mm)}."""
    parameter_table: Dict[str, Any]
    """Columns name, unit, status (lists) and nominal, value, std (arrays, external units)."""
    identified_names: List[str]
    """Names of the identified unknowns: the rows and columns of covariance."""
    covariance: Array
    """Covariance of the identified unknowns, external units (mm, deg, rad/N·mm)."""

    def _repr_html_(self) -> str:
        """The result as an HTML table (Jupyter shows it)."""


class Calibration:
    """A calibration run (`robcal calibrate`): the identification (`result`, whose attributes
    are also this object's), the warnings, the cross-validation and the problems that keep the
    model from being saved."""

    result: IdentificationResult
    """The identification and its statistics."""
    warnings: List[str]
    """The measurement file's warnings, then the fit's."""
    problems: List[str]
    """Why the model must not be trusted (each says what to check); empty when plausible."""
    cross_validation: Optional[Dict[str, Any]]
    """K-fold held-out errors (kfold/folds, or run because the noise test failed): folds, seed,
    errors_mm, mean_mm, std_mm, mean_plus_3std_mm, max_mm, per_fold (rows, mean_mm, std_mm, max_mm
    of each fold), run_because_of_misfit; None when not run."""

    def save(self, path: str, force: bool = False) -> None:
        """Writes the calibrated model file (YAML), whole or not at all; InputError when the run
        lists problems, unless force=True."""

    def __getattr__(self, name: str) -> Any:
        """The identification result's attributes (rms_mm, parameters, robot, …)."""


class Compensator:
    """Calibrated inverse kinematics and corrected targets for one calibrated robot and tool."""

    @staticmethod
    def from_model(model: str, tool: Optional[str] = None, payload_mass_kg: Optional[float] = None,
                   payload_cog_mm: Optional[ArrayLike] = None, approach: str = "++++++",
                   payload: Optional[str] = None, temperature_c: Optional[float] = None,
                   warmup_time_s: Optional[float] = None, warm: bool = False) -> "Compensator":
        """From a calibrated model file, for targets reached under `robcal compensate`'s
        conditions: approach ('+-++++'), payload (a name of the tool's payloads), temperature_c,
        warmup_time_s (how long the arm has worked) or warm (fully warm)."""

    @staticmethod
    def from_truth(truth: str, tool: Optional[str] = None, payload_mass_kg: Optional[float] = None,
                   payload_cog_mm: Optional[ArrayLike] = None, approach: str = "++++++",
                   payload: Optional[str] = None, temperature_c: Optional[float] = None,
                   warmup_time_s: Optional[float] = None, warm: bool = False) -> "Compensator":
        """From a simulation's truth file, with from_model's conditions."""

    @staticmethod
    def nominal(robot: str, tool: Optional[str] = None) -> "Compensator":
        """The nominal robot at the world origin (compensation changes nothing)."""

    def tcp_pose(self, joints_deg: ArrayLike) -> Dict[str, Array]:
        """TCP pose in the world on the calibrated model."""

    def tcp_poses(self, joints_deg: ArrayLike) -> Dict[str, Array]:
        """tcp_pose over the rows of an N×6 array: position_mm N×3, quaternion_wxyz N×4."""

    def nominal_tcp_pose(self, joints_deg: ArrayLike) -> Dict[str, Array]:
        """TCP pose in the base frame on the nominal model."""

    def config_of(self, joints_deg: ArrayLike) -> str:
        """Arm configuration label of controller joints."""

    def solve(self, position_mm: ArrayLike, quaternion_wxyz: ArrayLike, config: str,
              near_deg: Optional[ArrayLike] = None, method: str = "newton") -> Dict[str, Any]:
        """Joints reaching a world TCP pose on the calibrated model in `config`, and the nominal
        target to send; status says why when it cannot."""

    def solve_batch(self, positions_mm: ArrayLike, quaternions_wxyz: ArrayLike,
                    config: str) -> Dict[str, Any]:
        """solve() over N poses: joints_deg N×6, status, ok, nominal_position_mm (NaN rows where
        ok is False)."""

    def compensate_program(self, in_path: str, out_path: str, joints: bool = False,
                           keep_going: bool = False, frames: Optional[str] = None,
                           confidence_out: Optional[str] = None,
                           pulses_per_degree: Optional[ArrayLike] = None,
                           approach_from_motion: bool = False) -> Dict[str, Any]:
        """Writes a corrected copy of a robot program (only the points change), as `robcal
        compensate-program`; returns its JSON summary: in, out, language, cartesian_points,
        joint_points, uncorrected and assumed ([{where, reason}]). pulses_per_degree: the
        robot's encoder pulses per degree, for Yaskawa pulse positions. approach_from_motion:
        each point under the side each joint reaches it from (`--approach motion`)."""

    def compensate_targets(self, targets: str, method: str = "newton",
                           check_truth: Optional[str] = None,
                           out: Optional[str] = None) -> Dict[str, Any]:
        """Corrected targets for a pose-list file of wanted world poses, as `robcal compensate`,
        each under its row's approach, temperature, warm-up time and payload (the optional
        `approach`, `temperature`, `time_s`, `payload` columns; the compensator's where a row
        gives none): its JSON summary (robot, targets, method, conditions: how many distinct,
        max_residual_mm, closed_loop ...) plus names, joints_deg N×6, nominal_position_mm N×3,
        each row's condition: approach N×6 (+1 from below, -1 from above, 0 unknown),
        temperature_c N (°C), warmup_time_s N (s; inf fully warm, NaN cold), payloads N (the
        tool's payload names, '' for its own or one given by mass), and the CSV text."""


class LaserTracker:
    """Laser tracker: 3D point of one SMR (docs/method/06-instruments.md)."""

    position_mm: Array
    """Tracker position, mm."""
    sigma_mm: Array
    """σ per axis, mm."""
    min_range_mm: float
    """Closest measurable distance, mm."""
    max_range_mm: float
    """Farthest measurable distance, mm."""
    cone_half_angle_deg: float
    """SMR acceptance half-angle, deg."""

    def __init__(self) -> None:
        """The default tracker."""


class Ballbar:
    """Telescoping ballbar: one length near its nominal."""

    centre_mm: Array
    """Fixed ball centre, mm."""
    nominal_length_mm: float
    """Set-up length, mm."""
    range_mm: float
    """Readable range about the set-up length, mm."""
    sigma_mm: float
    """σ of one length, mm."""

    def __init__(self) -> None:
        """The default ballbar."""


class OpticalCmm:
    """Optical CMM: 6D pose of a target cluster."""

    position_mm: Array
    """Camera position, mm."""
    sigma_mm: float
    """Position σ, mm."""
    sigma_orientation_deg: float
    """Orientation σ, deg."""
    facing_limit_deg: float
    """Largest angle between the cluster's normal and the line of sight, deg."""

    def __init__(self) -> None:
        """The default optical CMM."""


def builtin_robots() -> List[str]:
    """Names of the built-in robots."""


def load_robot(name_or_path: str) -> RobotModel:
    """A built-in robot by name or a robot file by path."""


def load_calibrated_robot(path: str) -> CalibratedRobot:
    """Loads a calibrated model file written by calibrate."""


def fk(robot: RobotModel, joints_deg: ArrayLike, check_limits: bool = False) -> Dict[str, Any]:
    """`robcal fk`: flange pose of the nominal robot, {'robot', 'position_mm', 'quaternion_wxyz',
    'euler_deg': {label: value}}; check_limits refuses joints outside the limits."""


def fk_batch(robot: RobotModel, joints_deg: ArrayLike) -> Dict[str, Array]:
    """fk over the rows of an N×6 array: {'position_mm': N×3, 'quaternion_wxyz': N×4}."""


def ik_batch(robot: RobotModel, position_mm: ArrayLike, quaternion_wxyz: ArrayLike,
             seed_joints_deg: Optional[ArrayLike] = None) -> Dict[str, Any]:
    """ik over the rows of N×3 positions (mm) and N×4 quaternions (w, x, y, z), the inverse of
    fk_batch: per pose the solution nearest the previous pose's (the first nearest the seed),
    {'joints_deg': N×6 (NaN rows: unreachable or outside the limits), 'config': labels,
    'status': per pose}."""


def ik(robot: RobotModel, position_mm: ArrayLike, quaternion_wxyz: ArrayLike,
       seed_joints_deg: Optional[ArrayLike] = None,
       require_solution: bool = False) -> Dict[str, Any]:
    """`robcal ik`: every IK solution of the nominal robot, {'robot', 'status', 'method',
    'solutions'}; require_solution raises InputError when there is none inside the limits."""


def robot_catalogue() -> List[Dict[str, Any]]:
    """`robcal robots`: [{'name', 'model', 'manufacturer', 'reach_mm'}]."""


def robot_description(robot: RobotModel) -> Dict[str, Any]:
    """`robcal robot show`: name, manufacturer, source, MDH table, joint limits, link masses."""


def calibrate(robot: Union[None, str, RobotModel], tool: Union[None, str, Measurements],
              *args: Any, **kwargs: Any) -> Calibration:
    """calibrate(robot, tool, measurements, level='full', identify=[], fix=[], loss='none',
    seed=1, model=None, sigma=0, kfold=0, folds=None, units=None, euler=None,
    orientation_weight=100, keep_near_dependent=False, warmup_tau_s=None) from files, as
    `robcal calibrate` (the same library workflow and checks), or calibrate(robot_model,
    measurements, level=..., ..., sigma=0, kfold=0, orientation_weight=100,
    keep_near_dependent=False, warmup_tau_s=None) from objects. warmup_tau_s: the warm-up
    group's time constant (s; `--warmup-tau-s`, default the robot file's). With
    model='calibrated.yaml' (robot=None) only what level ('tool': the new tool's points or TCP
    frame; 'base': a moved base) or identify asks is re-identified, the rest kept; tool=None then
    means the model's tool. save(path) refuses a model with problems unless force=True."""


def calibrate_points(robot: str, tool: str, joints_deg: ArrayLike, targets: Sequence[str],
                     positions_mm: ArrayLike, level: str = "full", identify: Sequence[str] = ...,
                     fix: Sequence[str] = ..., loss: str = "none", seed: int = 1,
                     sigma: float = 0.0, kfold: int = 0, keep_near_dependent: bool = False,
                     warmup_tau_s: Optional[float] = None) -> Calibration:
    """Calibrate from arrays: joints N×6 (deg), target names (N), positions N×3 (mm)."""


def cross_validate(robot: str, tool: str, measurements: str, folds: int, level: str = "full",
                   seed: int = 1) -> Dict[str, Any]:
    """K-fold cross-validation: held-out position error per row and its statistics (mm)."""


def read_measurements(path: str, tool_file: str) -> Dict[str, Any]:
    """Reads a measurement CSV; returns Measurements.to_dict() of it."""


def error_statistics(errors: Sequence[float], unit: str = "mm") -> Dict[str, float]:
    """count, mean, std (population), mean_plus_3std, min and max of absolute errors, keyed
    with their unit as in validate's JSON: mean_mm, ... (or mean_deg, ... for unit="deg")."""


def pairwise_distance_errors(measured_mm: ArrayLike, modelled_mm: ArrayLike, threads: int = 2,
                             bins: int = 128) -> Dict[str, Any]:
    """Distance errors over every pair of rows (N×3 arrays, mm): count (= pairs), mean_mm,
    std_mm, mean_plus_3std_mm, min_mm, max_mm and a histogram."""


def validate(robot: str, tool_file: str, measurements: str, model: str = "",
             fit_base: bool = False, threads: int = 2, orientation_weight: float = 100.0,
             ballbar_centre: Optional[ArrayLike] = None, calibration: str = "",
             units: str = "", euler: str = "", ballbar_length: Optional[float] = None,
             ballbar_range: Optional[float] = None) -> Dict[str, Any]:
    """`robcal validate`: a calibrated model file or the nominal robot against a points, poses or
    distances (ballbar) file (units, euler: as calibrate's; ballbar_length, ballbar_range: mm, as
    --ballbar-length and --ballbar-range); the CLI's --json document plus per-row arrays
    (position_errors_mm, orientation_errors_deg, pose_errors_mm or length_errors_mm), warnings
    and notes."""


def validate_rows(model: CalibratedRobot, measurements: Measurements, fit_base: bool = False,
                  threads: int = 2, orientation_weight: float = 100.0,
                  ballbar_centre: Optional[ArrayLike] = None,
                  calibration: Optional[Measurements] = None,
                  name: str = "<arrays>", ballbar_length: Optional[float] = None,
                  ballbar_range: Optional[float] = None) -> Dict[str, Any]:
    """validate() of a CalibratedRobot against Measurements (files, dicts or arrays);
    `calibration` adds the region classes."""


def observability_indices(jacobian: ArrayLike, configurations: int) -> Dict[str, float]:
    """O1…O5 (docs/method/05-observability.md) of a column-scaled identification Jacobian of n configurations."""


def select_d_optimal(rows: ArrayLike, rows_per_candidate: int, count: int, restarts: int = -1,
                     seed: int = 1) -> List[int]:
    """Indices of `count` candidates chosen by the fast D-optimal greedy + exchange; `restarts`
    more seeded descents (negative: by candidate count, as robcal plan)."""


def select_published_exchange(rows: ArrayLike, rows_per_candidate: int, count: int,
                              seed: int) -> List[int]:
    """Indices chosen by the published exchange on O1 (random start of 11), seeded."""


def d_efficiency(rows: ArrayLike, rows_per_candidate: int, subset: Sequence[int]) -> float:
    """Certified D-efficiency of a subset against the continuous D-optimum."""


def smr_visible(tracker: LaserTracker, smr_mm: ArrayLike, smr_axis: ArrayLike) -> bool:
    """True when the tracker lies within the SMR's acceptance cone and range."""


def read_points(tracker: LaserTracker, smr_mm: ArrayLike, count: int, seed: int) -> Array:
    """`count` noisy readings of one SMR (rows x, y, z in mm), seeded."""


def ballbar_readable(ballbar: Ballbar, length_mm: float) -> bool:
    """True when the length is within the ballbar's ±range of its nominal."""


def simulate(instrument: str = "laser-tracker", truth: str = "published", count: int = 20,
             seed: int = 1, noise_mm: float = 0.0, robot: str = "abb-irb120", cell: str = "",
             tool: str = "", configs: str = "", effects: Sequence[str] = ...,
             approach: str = "below", clock: bool = False, error_length_mm: float = ...,
             error_angle_deg: float = ..., out: str = "") -> Dict[str, Any]:
    """`robcal simulate`: `count` random measurable configurations (or the `configs` file's) of
    a virtual robot measured by a virtual instrument; noise_mm = 0 gives exact readings; with
    thermal drift, clock=True records each row's time instead of its temperature (time_s and
    temperature_c arrays, NaN where a row has none); files written to `out` when given;
    'summary' is the CLI's --json."""


def read_program_points(text: str, language: str, joints: bool = False,
                        pulses_per_degree: Optional[ArrayLike] = None) -> List[Dict[str, Any]]:
    """Every point of a program ('rapid', 'krl', 'ls', 'jbi', 'urscript'), in file order: name, line,
    column, joint_target, position_mm/quaternion_wxyz or joints_deg, config, tool, frame."""


def filter_program(compensator: Compensator, text: str, language: str, joints: bool = False,
                   keep_going: bool = False, frames: Optional[str] = None,
                   file: str = "<text>",
                   pulses_per_degree: Optional[ArrayLike] = None,
                   dat: Optional[str] = None, dat_file: str = "<dat>") -> Dict[str, Any]:
    """Corrects every target of a program text with a Compensator: the `robcal
    compensate-program` summary plus the corrected 'text' and 'confidence_csv'. KRL: with
    `dat`, the .src text and its .dat corrected together as a module ('dat_text')."""


def write_measurement_program(language: str, names: Sequence[str], joints_deg: ArrayLike,
                              name: str = "RCMEAS", hook: str = "wait", signal: int = 1,
                              settle_s: float = 1.0, approach_deg: float = 5.0,
                              speed_percent: float = 10.0, max_configs_per_file: int = 0,
                              tool_number: int = 1,
                              pulses_per_degree: Optional[ArrayLike] = None,
                              robot: Optional[str] = None,
                              date: str = "2000/01/01 00:00",
                              approach: Optional[Sequence[bool]] = None,
                              measure: Optional[Sequence[bool]] = None) -> List[Dict[str, str]]:
    """The measurement program visiting each configuration (N×6 joints, deg) from q -
    approach_deg, as `robcal program`: a list of {'name', 'text'} files. `approach` and
    `measure` (one flag per configuration) turn the approach move and the measurement hook off
    where False (e.g. pre-poses visited but not measured)."""


def write_measurement_program_files(language: str, configs: str, out_dir: str,
                                    robot: Optional[str] = None, tool: Optional[str] = None,
                                    name: str = "RCMEAS", hook: str = "wait",
                                    approach_deg: float = 5.0,
                                    pulses_per_degree: Optional[ArrayLike] = None,
                                    date: str = "2000/01/01 00:00") -> List[str]:
    """`robcal program`: reads the configurations CSV (what `robcal plan` writes), checks them
    against the robot's limits and writes the program's files into out_dir; their paths."""


def read_joint_moves(text: str, language: str,
                     pulses_per_degree: Optional[ArrayLike] = None) -> Dict[str, Any]:
    """Every absolute joint move of a program text: joints_deg N×6 and their lines."""


def experiments(seed: int = 1, out: str = "") -> Dict[str, Any]:
    """The published simulation experiments (docs/method/11-published-results.md, `robcal experiments`): {seed,
    calibration_configurations, validation_configurations, experiments: {a, b, c}}; with `out`
    also 'seconds' and results.json, results.md written there."""


def montecarlo(runs: int = 1000, poses: int = 50, validation: int = 1000, threads: int = 2,
               seed: int = 1, noise_mm: float = 0.022, level: str = "full",
               optimal_plan: bool = True, validation_model: str = "first-order") -> Dict[str, Any]:
    """Repeated simulated calibrations of the published IRB 120 against the Cramér–Rao
    prediction (`robcal montecarlo`): observed and predicted errors (mm), their ratio."""


def model_import(out: str = "", urdf: str = "", tip: str = "", format: str = "urdf",
                 calibration: str = "", robot: str = "") -> Dict[str, Any]:
    """A URDF (format 'urdf') or a UR calibration.conf on its nominal robot (format
    'ur-calibration') as a robot or nominal model file (`robcal model import`): the CLI's JSON as
    a dict plus yaml (the file's text, written to `out` when given)."""


def model_export(out: str = "", robot: str = "", model: str = "", format: str = "urdf",
                 seed: int = 1) -> Dict[str, Any]:
    """A robot (`robot`) or calibrated model file (`model`) as URDF, UR calibration.conf deltas or
    its MDH table with σ (format 'urdf', 'ur-calibration', 'mdh-csv'; `robcal model export`): the
    CLI's JSON as a dict (what the format leaves out and its cost at the TCP) plus text (written
    to `out` when given)."""


def plan(robot: str = "abb-irb120", tool: Optional[str] = None,
         instrument: str = "laser-tracker", level: str = "full", count: int = 40,
         candidates: int = 5000, candidate_joints_deg: Optional[Array] = None,
         seed: int = 1, constraints: str = "auto", floor_mm: float = 50.0,
         noise_mm: float = 0.0, criterion: str = "default", guard: bool = True,
         cell: Optional[str] = None, task_joints_deg: Optional[Array] = None,
         task_box: Optional[str] = None, task_count: int = 1000,
         prior_model: Optional[str] = None, misfit_mm: Optional[float] = None,
         identify: Sequence[str] = ..., approach: str = "auto",
         payloads: str = "auto") -> Dict[str, Any]:
    """Choose calibration configurations and predict their accuracy (`robcal plan`): the CLI's
    JSON as a dict (indices for the chosen and a random choice, predicted_error_mm over the task
    region from instrument noise only, predicted_error_with_misfit_mm when the misfit is known:
    prior_model, a calibrated model file with its cross-validation, or misfit_mm) plus
    joints_deg (count×6), targets, approach_sides ('+-++++' per configuration) and
    payload_names ('' the tool's own) of the chosen configurations; identify adds opt-in groups
    to the design, approach/payloads (auto, below/own, varied) vary the conditions."""


def plan_study(robot: str = "abb-irb120", tool: Optional[str] = None,
               instrument: str = "laser-tracker", level: str = "full",
               counts: Sequence[int] = ..., seeds: int = 4, seed: int = 1,
               candidates: int = 2000, constraints: str = "auto", floor_mm: float = 50.0,
               noise_mm: float = 0.0, task_box: Optional[str] = None,
               task_poses: Optional[str] = None, task_count: int = 200,
               criterion: str = "default", guard: bool = True, effects: Sequence[str] = ...,
               cell: Optional[str] = None, prior_count: int = 60) -> Dict[str, Any]:
    """Planned against random configurations at several counts over random true robots
    (`robcal plan-study`); task_box or task_poses set the task region; criterion default, d or
    i; effects outside the model; cell a cell file; prior_count configurations of each robot's
    prior calibration for the misfit-aware prediction (0: none)."""


def report(model: str, measurements: Sequence[str], calibration: Optional[str] = None,
           before: Optional[str] = None, title: str = "robcal calibration report",
           out: Optional[str] = None, instrument: str = "", seed: Optional[int] = None,
           iso9283_poses: str = "", iso9283_measurements: str = "", iso9283_min_cycles: int = 30,
           ballbar: str = "") -> Dict[str, Any]:
    """A calibrated model validated on measurement files beside the nominal robot (or `before`)
    (`robcal report`): the report's JSON as a dict plus `warnings`; with `out` (.html) also the
    self-contained page and the JSON beside it; provenance, ISO 9283 and ballbar sections."""


def iso9283_plan(robot: CalibratedRobot, region_min_mm: ArrayLike, region_max_mm: ArrayLike,
                 quaternion_wxyz: Optional[ArrayLike] = None, config: str = "front-up-noflip",
                 cycles: int = 30, vap_approach_mm: float = 0.0) -> Dict[str, Any]:
    """The ISO 9283 test cube in a workspace region (world, mm), its poses P1-P5 (tool
    orientation quaternion_wxyz, default 0,0,1,0: pointing down) with joint targets from the
    robot's compensation IK, the cycles and, with vap_approach_mm > 0, the multi-directional
    test's pre-poses and moves (`robcal iso9283 plan`). Keys: cube_centre_mm, cube_edge_mm,
    corners_mm, poses, sequence, approaches, vap_sequence, pose_list_csv, cycles_csv,
    vap_cycles_csv."""


def iso9283_analyse(poses: str, measurements: str, min_cycles: int = 30) -> Dict[str, Any]:
    """AP, RP (position, orientation), vAP, AD, RD of measured cycles (`robcal iso9283
    analyse`): the commanded poses' pose list and the measurements CSV; the CLI's --json."""


def iso9283_plan_files(robot: str, region_min_mm: ArrayLike, region_max_mm: ArrayLike,
                       tool: str = "", model: str = "",
                       quaternion_wxyz: Optional[ArrayLike] = None,
                       config: str = "front-up-noflip", cycles: int = 30,
                       vap_approach_mm: float = 0.0, out_poses: str = "iso9283-poses.csv",
                       out_cycles: str = "iso9283-cycles.csv",
                       out_vap_cycles: str = "iso9283-vap-cycles.csv", program: str = "",
                       program_dir: str = "iso9283-programs") -> Dict[str, Any]:
    """`robcal iso9283 plan` on files: writes the pose list, the cycles (vAP cycles, programs)
    and returns the CLI's --json document."""


def axis_test_plan(joint: int, home_deg: ArrayLike, from_deg: float, to_deg: float,
                   steps: int = 12, approach_deg: float = 5.0, out: str = "") -> Dict[str, Any]:
    """`robcal axis-test plan`: {'csv': the moves file's text, 'moves'}; written to `out`."""


def axis_test_analyse(measurements: str) -> Dict[str, Any]:
    """`robcal axis-test analyse`: circle, backlash and errors of one joint; the CLI's --json."""


def ballbar_path(robot: str, tool: str, target: str, centre_mm: ArrayLike, length_mm: float,
                 out: str, model: str = "", reading_model: str = "", range_mm: float = 1.0,
                 axis: Optional[ArrayLike] = None,
                 elevations_deg: Optional[Sequence[float]] = None, points: int = 12,
                 quaternion_wxyz: Optional[ArrayLike] = None,
                 config: str = "front-up-noflip") -> Dict[str, Any]:
    """`robcal ballbar-path`: the checked path written to `out`; the CLI's --json document plus
    'joints_deg' (N×6) and 'predicted_offsets_mm'."""


def demo(out: str = "", seed: int = 1, count: int = 50, validation: int = 1000) -> Dict[str, Any]:
    """`robcal demo`: the whole method on a virtual IRB 120 with a simulated tracker; the CLI's
    --json summary plus per-row validation errors (errors_mm, errors_vs_truth_mm); writes the
    folder `out` when given."""


def import_measurements(export: str, joints: str, map: str = "", join: str = "order",
                        time_tolerance: float = 0.5, target: str = "", delimiter: str = "",
                        decimal: str = "", columns: str = "", unit: str = "",
                        config_column: str = "", allow_unmeasured: bool = False,
                        world_frame: str = "", configs: str = "") -> Dict[str, Any]:
    """`robcal import`: an instrument export joined with the joint log; {'rows', 'kind',
    'warnings', 'csv', 'measurements': Measurements}; positions in a `frames world` frame;
    configs: the plan's configurations file, each row's approach and payload from it."""


def frames_base(robot: str, joint1: str, joint2: str, target: str = "1", cell: str = "",
                sigma_mm: float = 0.0) -> Dict[str, Any]:
    """`robcal frames base`: {'base': frame ± σ with its 6×6 covariance, 'text': file to write}."""


def frames_tool(robot: str, joint5: str, joint6: str, target: str = "1", tool: str = "",
                sigma_mm: float = 0.0) -> Dict[str, Any]:
    """`robcal frames tool`: the target in the flange frame ± σ, covariance, 'text' (tool file)."""


def frames_point(robot: str, cell: str, measurements: str, target: str = "1", tool: str = "",
                 sigma_mm: float = 0.0) -> Dict[str, Any]:
    """`robcal frames point`: the target from ≥ 4 configurations with the cell's base."""


def frames_world(measured: str, nominal: str, sigma_mm: float = 0.0) -> Dict[str, Any]:
    """`robcal frames world`: the nests' frame ± σ, the instrument in it, 'text' (frame block)."""


def base_from_sweeps(robot: RobotModel, joint1_deg: ArrayLike, points1_mm: ArrayLike,
                     joint2_deg: ArrayLike, points2_mm: ArrayLike,
                     sigma_mm: float = 0.0) -> Dict[str, Any]:
    """frames_base from arrays: each sweep's joints N×6 (deg) and points N×3 (mm)."""


def tool_from_sweeps(robot: RobotModel, joint5_deg: ArrayLike, points5_mm: ArrayLike,
                     joint6_deg: ArrayLike, points6_mm: ArrayLike,
                     sigma_mm: float = 0.0) -> Dict[str, Any]:
    """frames_tool from arrays: the target in the flange frame from joint-5 and joint-6 sweeps."""


def frame_from_nests(measured_mm: ArrayLike, nominal_mm: ArrayLike,
                     sigma_mm: float = 0.0) -> Dict[str, Any]:
    """frames_world from arrays: nests measured (N×3) and their coordinates (N×3), same order."""


class PointSession:
    """The guided tracker/CMM session without its prompt loop: steps, readings, result."""

    def __init__(self, configs: str, tool: Optional[Tool] = None, reference: int = -1,
                 every: int = 0) -> None:
        """From a plan file, the tool, the reference configuration's index and the period."""

    steps: List[Dict[str, Any]]
    """[{'key', 'prompt', 'config', 'drift_check'}] in the order they are asked."""
    answered: int
    """Steps answered so far."""
    next_step: Optional[Dict[str, Any]]
    """The next step to answer, or None when the session is complete."""

    def replay(self, text: str, file: str = "<journal>") -> int:
        """Replaces the readings by a journal's text; returns the length of its complete lines."""

    def load_journal(self, path: str) -> int:
        """Resumes from a journal file: returns the steps answered."""

    def answer(self, line: str, time: str = "") -> str:
        """Answers the next step as typed ('x y z [°C]' or 'skip'); returns the journal line."""

    def add_reading(self, position_mm: Optional[ArrayLike], time: str = "",
                    temperature_c: Optional[float] = None) -> str:
        """Answers the next step with a reading (None: missing); returns the journal line."""

    def journal(self) -> str:
        """The journal's text for the readings so far."""

    def result(self) -> Dict[str, Any]:
        """{'measurements': Measurements, 'read', 'missing', 'drift'} so far."""


def point_session(configs: str, journal: str, out: str,
                  answers: Optional[Sequence[str]] = None, tool: str = "", reference: str = "",
                  every: int = 0, resume: bool = False, follow: str = "", map: str = "",
                  follow_timeout_s: float = 600.0, world_frame: str = "") -> Dict[str, Any]:
    """`robcal session` on files: answers from `answers` (or `follow`, an export as it grows),
    each journalled at once; {'status', 'steps', 'answered', 'resumed', 'configurations',
    'read', 'missing', 'drift', 'measurements', 'csv', 'transcript', 'refused'}."""
