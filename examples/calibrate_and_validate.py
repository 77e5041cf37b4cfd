# %% [markdown]
# # Calibrate and validate an ABB IRB 120 from Python
#
# The published IRB 120 data set (laser tracker, three targets on the tool): calibrate the full
# model on 60 rows, validate it on rows it was not fitted to, compare with the nominal robot, and
# plot the error histograms when matplotlib is installed. Run it as a script or cell by cell
# (`# %%` cells, as VS Code and Jupytext read them).
#
# Environment: ROBCAL_EXAMPLE_DATA (the data set's folder), ROBCAL_EXAMPLE_OUT (where files go).

# %%
import os

import numpy as np

import robcal

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.environ.get("ROBCAL_EXAMPLE_DATA",
                      os.path.join(HERE, "..", "tests", "data", "irb120-published"))
OUT = os.environ.get("ROBCAL_EXAMPLE_OUT", "example-out")
os.makedirs(OUT, exist_ok=True)
print("robcal", robcal.__version__)

# %% The robot, the tool and the measurements: objects from files (or from arrays and dicts).
robot = robcal.load_robot("abb-irb120")
tool_path = os.path.join(DATA, "tool.yaml")
tool = robcal.Tool.from_file(tool_path)
rows = robcal.Measurements.from_file(os.path.join(DATA, "calibration.csv"), tool)
print(robot, tool, rows, sep="\n")

# %% Calibrate: every identifiable parameter of the full model (docs/method/03-error-model.md,
# 04-identification.md §3).
result = robcal.calibrate(robot, rows, level="full")
print(result)
table = result.parameter_table
identified = np.array(table["status"]) == "identified"
changed = np.abs(table["value"] - table["nominal"])
is_base = np.array([n.startswith("base.") for n in table["name"]])
for i in np.argsort(-changed * (identified & ~is_base))[:5]:
    print(f"  {table['name'][i]:<20} {table['value'][i]:12.5f} ± {table['std'][i]:.5f} "
          f"{table['unit'][i]}")
print("predicted mean position error:", round(result.predicted.mean_mm, 4), "mm")

# %% Validate on the rows it was not fitted to, beside the nominal robot (placed by a best fit).
model_path = os.path.join(OUT, "model.yaml")
result.save(model_path)
validation = os.path.join(DATA, "validation.csv")
calibrated = robcal.validate("abb-irb120", tool_path, validation, model=model_path)
nominal = robcal.validate("abb-irb120", tool_path, validation, fit_base=True)
for name, report in (("nominal", nominal), ("calibrated", calibrated)):
    e = report["position_error_mm"]
    print(f"{name:>10}: mean {e['mean_mm']:.4f} mm, max {e['max_mm']:.4f} mm over {report['points']} rows")

# %% Plot the two histograms of position errors (only when matplotlib is installed).
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    plt = None
    print("matplotlib is not installed: no plot (apt-get install python3-matplotlib)")
figure_path = None
if plt is not None:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for name, report in (("nominal", nominal), ("calibrated", calibrated)):
        ax.hist(report["position_errors_mm"], bins=20, alpha=0.6, label=name)
    ax.set_xlabel("position error, mm")
    ax.set_ylabel("rows")
    ax.set_xscale("log")
    ax.legend()
    figure_path = os.path.join(OUT, "position_errors.png")
    fig.savefig(figure_path, dpi=100, bbox_inches="tight")
    print("plot written to", figure_path)
