"""Type stubs and docstrings: every public name of the installed package (functions, classes and
their members, the hexapod module) has a stub with a docstring, the stubs' argument names are the
extension's, and every runtime function and class has its own docstring."""
import ast
import inspect
import os

import robcal
import robcal.hexapod

STUB_DIR = os.path.dirname(robcal.__file__)


def stub_entries(path):
    """{name: (node, docstring)} of a stub's top level, and of each class body as 'Class.name'."""
    tree = ast.parse(open(path).read())
    out = {}

    def walk(body, prefix):
        for i, node in enumerate(body):
            following = body[i + 1] if i + 1 < len(body) else None
            trailing = (following.value.value if isinstance(following, ast.Expr)
                        and isinstance(following.value, ast.Constant) else None)
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
                out[prefix + node.name] = (node, ast.get_docstring(node))
                if isinstance(node, ast.ClassDef):
                    walk(node.body, prefix + node.name + ".")
            elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
                out[prefix + node.target.id] = (node, trailing)

    walk(tree.body, "")
    return out


def runtime_names(module, skip=()):
    names = []
    for name, obj in vars(module).items():
        if name.startswith("_") or name in skip or inspect.ismodule(obj):
            continue
        names.append(name)
        if isinstance(obj, type) and obj.__module__.startswith("robcal"):
            names += [f"{name}.{a}" for a in vars(obj) if not a.startswith("_")]
    return names


def signature_args(func):
    """Argument names of a pybind11 function with one signature, else None."""
    first = (func.__doc__ or "").split("\n")[0]
    if "(*args, **kwargs)" in first or "(" not in first:
        return None
    inner, depth, args, current = first[first.index("(") + 1:], 0, [], ""
    for ch in inner:
        if ch in "([" and not (depth == 0 and ch == "("):
            depth += 1
        elif ch in ")]":
            if depth == 0:
                break
            depth -= 1
        if ch == "," and depth == 0:
            args.append(current)
            current = ""
        else:
            current += ch
    args.append(current)
    return [a.split(":")[0].strip() for a in args if a.strip() and a.split(":")[0].strip() != "self"]


def check(module, stub, skip=()):
    entries = stub_entries(os.path.join(STUB_DIR, stub))
    missing = [n for n in runtime_names(module, skip) if n not in entries]
    undocumented = [n for n in runtime_names(module, skip) if n in entries and not entries[n][1]]
    assert not missing, f"not in {stub}: {missing}"
    assert not undocumented, f"no docstring in {stub}: {undocumented}"
    for name in runtime_names(module, skip):
        obj = module
        for part in name.split("."):
            obj = getattr(obj, part)
        if callable(obj) and not isinstance(obj, type):
            assert (obj.__doc__ or "").strip(), f"{name} has no runtime docstring"
            args = signature_args(obj)
            node = entries[name][0]
            if args is not None and isinstance(node, ast.FunctionDef):
                stub_args = [a.arg for a in node.args.args if a.arg != "self"]
                assert stub_args == args, f"{name}: stub {stub_args}, extension {args}"
        if isinstance(obj, type):
            assert (obj.__doc__ or "").strip(), f"{name} has no runtime docstring"


def test_extension_stub_covers_every_public_name():
    check(robcal._robcal, "_robcal.pyi", skip=("hexapod",))


def test_hexapod_stub_covers_every_public_name():
    check(robcal._robcal.hexapod, "hexapod.pyi")
    assert set(n for n in dir(robcal.hexapod) if not n.startswith("_")) >= set(
        n for n in dir(robcal._robcal.hexapod) if not n.startswith("_"))


def test_package_stub_exports():
    entries = open(os.path.join(STUB_DIR, "__init__.pyi")).read()
    for name in ("__version__", "InputError", "hexapod", "from ._robcal import *"):
        assert name in entries
    assert os.path.exists(os.path.join(STUB_DIR, "py.typed"))
