"""robcal: absolute calibration of six-axis industrial robots.

Millimetres and degrees in every argument and result; the C++ library underneath works in
millimetres and radians.
"""
from ._robcal import *  # noqa: F401,F403
