#!/usr/bin/env python3
"""clang-tidy with the project's checks (.clang-tidy) over src/ and apps/robcal/; a finding fails.

Usage: scripts/tidy.py BUILD_DIR [JOBS [FILE ...]]
(with FILEs, only those of them that are checked at all: e.g. the files a change touched,
`scripts/tidy.py build 2 $(git diff --name-only main~5 -- src apps)`)

Each file is checked inside a batch of up to BATCH files of its folder (one translation unit
that #includes them): clang-tidy then parses and walks Eigen, Ceres and CLI11 once per batch
instead of once per file, which makes the run about six times faster and keeps CI within its
time limit (issue 21). The .clang-tidy header filter covers src/ and apps/robcal/, so every
finding in a batched file is reported at its own file:line. A batch that does not compile as
one unit (two files of a folder defining the same internal name) is checked file by file, so
no file is ever left unchecked.
"""
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

BATCH = 10
CHECKED = re.compile(r"/(src/[a-z_0-9]+|apps/robcal)/[^/]+\.cpp$")


def batch_command(entries, unit, directory):
    """The first entry's compiler command, every entry's -D definitions, compiling `unit`."""
    args = shlex.split(entries[0]["command"])
    out = []
    skip = False
    for a in args:
        if skip:
            skip = False
            continue
        if a in ("-o", "-c"):
            skip = a == "-o"
            continue
        if a == entries[0]["file"]:
            continue
        out.append(a)
    defines = []
    for e in entries:
        for a in shlex.split(e["command"]):
            if a.startswith("-D") and a not in out and a not in defines:
                defines.append(a)
    return {"directory": directory, "file": unit,
            "command": shlex.join(out + defines + ["-c", unit])}


def run_tidy(database_dir, source, batched):
    # A batch #includes .cpp files on purpose.
    extra = ["-checks=-bugprone-suspicious-include"] if batched else []
    p = subprocess.run(["clang-tidy", "-p", database_dir, "-quiet", *extra, source],
                       capture_output=True, text=True)
    # "N warnings generated." counts the suppressed ones in Eigen, Ceres...: not findings.
    text = "\n".join(line for line in (p.stdout + p.stderr).splitlines()
                     if not re.fullmatch(r"\d+ warnings? (and \d+ errors? )?generated\.", line)
                     and not line.startswith("Suppressed ")
                     and not line.startswith("Use -header-filter")
                     and line.strip())
    return p.returncode, text


def main():
    build = os.path.abspath(sys.argv[1])
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    jobs = int(sys.argv[2]) if len(sys.argv) > 2 else os.cpu_count()
    only = {os.path.abspath(f) for f in sys.argv[3:]}
    database = json.load(open(os.path.join(build, "compile_commands.json")))
    by_folder = {}
    seen = set()
    for e in database:
        # Each file once: the sanitized copy of the library (robcal_asan) compiles it again.
        if (CHECKED.search(e["file"]) and "-fsanitize" not in e["command"] and e["file"] not in seen
                and (not only or os.path.abspath(e["file"]) in only)):
            seen.add(e["file"])
            by_folder.setdefault((os.path.dirname(e["file"]), e["command"].split()[0]), []).append(e)
    tidy_dir = os.path.join(build, "tidy")
    shutil.rmtree(tidy_dir, ignore_errors=True)
    os.makedirs(tidy_dir)
    # Each batch, and (for a batch that does not compile as one unit) its halves down to pairs:
    # every unit that may be checked has its entry in the batches' compile database.
    units, commands, unit_of = [], [], {}

    def add_unit(name, chunk):
        unit = os.path.join(tidy_dir, name + ".cpp")
        with open(unit, "w") as f:
            f.writelines(f'#include "{e["file"]}"\n' for e in chunk)
        commands.append(batch_command(chunk, unit, build))
        unit_of[tuple(e["file"] for e in chunk)] = unit
        if len(chunk) > 2:
            half = len(chunk) // 2
            add_unit(name + "a", chunk[:half])
            add_unit(name + "b", chunk[half:])
        return unit

    for (folder, _), entries in sorted(by_folder.items()):
        entries.sort(key=lambda e: e["file"])
        name = os.path.relpath(folder, root).replace(os.sep, "_")
        for k in range(0, len(entries), BATCH):
            chunk = entries[k:k + BATCH]
            units.append((add_unit(f"{name}_{k // BATCH}", chunk), chunk))
    commands += [e for _, chunk in units for e in chunk]
    with open(os.path.join(tidy_dir, "compile_commands.json"), "w") as f:
        json.dump(commands, f, indent=1)

    def check_files(chunk):
        if len(chunk) == 1:
            return run_tidy(tidy_dir, chunk[0]["file"], batched=False)
        return check(unit_of[tuple(e["file"] for e in chunk)], chunk)

    def check(unit, chunk):
        code, text = run_tidy(tidy_dir, unit, batched=True)
        if "clang-diagnostic-error" not in text:
            return code, text
        # Not one unit (a name defined twice in the folder): each half alone, down to single
        # files, whose own compile errors are then reported as such.
        print(f"note: {os.path.basename(unit)} does not compile as one unit; checked in halves "
              "(rename the clashing internal names to keep tidy fast)", flush=True)
        half = len(chunk) // 2
        results = [check_files(chunk[:half]), check_files(chunk[half:])]
        return max(c for c, _ in results), "\n".join(t for _, t in results if t)

    files = sum(len(c) for _, c in units)
    print(f"clang-tidy: {files} files of src/ and apps/robcal/ in {len(units)} batches, "
          f"{jobs} at a time", flush=True)
    failed = False
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        for (unit, chunk), (code, text) in zip(units, pool.map(lambda u: check(*u), units)):
            if code != 0 or text:
                failed = True
                print(f"--- {', '.join(os.path.relpath(e['file']) for e in chunk)}\n{text}",
                      flush=True)
    print("clang-tidy: findings above" if failed else "clang-tidy: clean")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
