#!/usr/bin/env bash
# The pytest suite against the installed package: `pip install --no-build-isolation .` into a
# temporary target (reusing the extension of the CMake build tree given), then pytest with only
# that target on the path. Usage: run_installed.sh PYTHON BUILD_DIR ROBCAL_CLI
set -euo pipefail
PYTHON="$1"
BUILD="$(cd "$2" && pwd)"
CLI="$(cd "$(dirname "$3")" && pwd)/$(basename "$3")"
SOURCE="$(cd "$(dirname "$0")/../.." && pwd)"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ROBCAL_CMAKE_BUILD_DIR="$BUILD" ROBCAL_BUILD_JOBS=1 PIP_DISABLE_PIP_VERSION_CHECK=1 \
  "$PYTHON" -m pip install --quiet --no-build-isolation --no-index --no-deps \
  --target "$tmp/site" "$SOURCE" > "$tmp/pip.log" 2>&1 || { cat "$tmp/pip.log"; exit 1; }
cd "$tmp"
env -u ROBCAL_DATA_DIR PYTHONPATH="$tmp/site" ROBCAL_CLI="$CLI" ROBCAL_INSTALLED="$tmp/site" \
  ROBCAL_SOURCE="$SOURCE" "$PYTHON" -m pytest -q -p no:cacheprovider "$SOURCE/tests/python"
