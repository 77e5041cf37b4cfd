"""robcal: absolute calibration of six-axis industrial robots.

Millimetres and degrees in every argument and result; the C++ library underneath works in
millimetres and radians. Bad input raises robcal.InputError (a ValueError) whose message names
the file, line and column or key.
"""
import os as _os

# An installed package carries the robot library next to the extension (setup.py puts it there).
_DATA = _os.path.join(_os.path.dirname(__file__), "data")
if _os.path.isdir(_DATA):
    _os.environ.setdefault("ROBCAL_DATA_DIR", _DATA)

from ._robcal import *  # noqa: E402,F401,F403
from ._robcal import __version__, InputError  # noqa: E402,F401
from . import hexapod  # noqa: E402,F401
