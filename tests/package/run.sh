#!/usr/bin/env bash
# Installs the build tree into a temporary prefix and checks the package: the installed CLI
# finds its robot library with no help, private headers are not installed, pkg-config and the
# man page are there, and tests/package/ builds against find_package(robcal) and gives the same
# numbers with default flags and with -march=native (the public ABI must not depend on them).
# Usage: run.sh BUILD_DIR TESTS_PACKAGE_DIR
set -euo pipefail
build=$1
src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build" --prefix "$tmp/prefix" >"$tmp/install.log" || { cat "$tmp/install.log"; fail "cmake --install"; }
prefix=$tmp/prefix
libdir=$(find "$prefix" -name robcalConfig.cmake -printf '%h\n' | sed 's|/cmake/robcal$||')
[[ -f $libdir/librobcal.a || -f $libdir/librobcal.so ]] || fail "library not installed in $libdir"
[[ -f $prefix/include/robcal/kinematics/inverse_kinematics.hpp ]] || fail "headers not installed"
for private in kinematics/fast_atan2.hpp kinematics/angle_shift.hpp design/leverage_cache.hpp; do
  [[ ! -e $prefix/include/robcal/$private ]] || fail "private header installed: $private"
done
[[ -f $prefix/share/robcal/data/robots/abb-irb120.yaml ]] || fail "robot library not installed"
[[ -f $prefix/share/bash-completion/completions/robcal ]] || fail "bash completion not installed"
if command -v help2man >/dev/null; then
  [[ -s $prefix/share/man/man1/robcal.1 ]] || fail "man page not installed"
fi

# The installed CLI, run from elsewhere with no environment help, finds its robots.
robots=$(cd "$tmp" && env -u ROBCAL_DATA_DIR "$prefix/bin/robcal" robots)
grep -q abb-irb120 <<<"$robots" || fail "installed robcal does not list its robots: $robots"
version=$("$prefix/bin/robcal" --version)
grep -Eq '^robcal [0-9]+\.[0-9]+\.[0-9]+$' <<<"$version" || fail "robcal --version: $version"

if command -v pkg-config >/dev/null; then
  flags=$(PKG_CONFIG_PATH=$libdir/pkgconfig pkg-config --cflags --libs robcal)
  include=$(grep -oE -- '-I[^ ]*/include( |$)' <<<"$flags" | head -1 | sed 's/^-I//; s/ $//')
  [[ -n $include && $(realpath "$include") == $(realpath "$prefix/include") ]] ||
    fail "pkg-config's include folder is not the installed one: $flags"
  grep -q -- "-DEIGEN_MAX_ALIGN_BYTES=16" <<<"$flags" || fail "pkg-config lacks the ABI defines: $flags"
fi

launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=$tmp  # the temporary paths differ from run to run
fi
for variant in default native; do
  flags=""
  [[ $variant == native ]] && flags="-march=native"
  cmake -S "$src" -B "$tmp/build-$variant" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_CXX_FLAGS="$flags" "${launcher[@]}" >"$tmp/configure-$variant.log" 2>&1 ||
    { cat "$tmp/configure-$variant.log"; fail "configure ($variant)"; }
  cmake --build "$tmp/build-$variant" >"$tmp/build-$variant.log" 2>&1 ||
    { cat "$tmp/build-$variant.log"; fail "build ($variant)"; }
  echo "== downstream program, $variant flags ($flags)"
  env -u ROBCAL_DATA_DIR "$tmp/build-$variant/downstream" | tee "$tmp/out-$variant.txt" ||
    fail "downstream checks ($variant)"
done
a=$(grep '^compare:' "$tmp/out-default.txt")
b=$(grep '^compare:' "$tmp/out-native.txt")
[[ $a == "$b" ]] || fail "default and -march=native builds differ: '$a' vs '$b'"
echo "package test passed"
