"""robcal: absolute calibration of six-axis industrial robots (mm and degrees outside)."""
from . import hexapod as hexapod
from ._robcal import *  # noqa: F401,F403
from ._robcal import InputError as InputError
from ._robcal import __version__ as __version__
