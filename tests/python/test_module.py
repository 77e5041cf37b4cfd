"""The extension module loads and describes itself."""
import robcal


def test_module_imports_and_has_doc():
    assert "calibration" in robcal._robcal.__doc__
