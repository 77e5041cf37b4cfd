"""The ballbar hexapod of docs/method/07-hexapod.md (mm): fixtures, direct kinematics, the 72 poses, uncertainty,
world frame, planning and its plan file. The functions are the extension's robcal._robcal.hexapod."""
from . import _robcal as _ext

for _name in dir(_ext.hexapod):
    if not _name.startswith("_"):
        globals()[_name] = getattr(_ext.hexapod, _name)
del _name
