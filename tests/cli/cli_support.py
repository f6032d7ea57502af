"""Shared by the command-line tests: where vdmesh and the data are, running it."""
import os
import subprocess
import sys
import tempfile

BIN = os.environ.get("VDMESH_BIN", "vdmesh")
DATA = os.environ.get("VDMESH_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))
SOURCE = os.environ.get("VDMESH_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", ".."))

failures = []


def run(*args, timeout=600, env=None):
    """Runs vdmesh (env: the whole environment, default ours); returns (exit
    code, stdout, stderr)."""
    p = subprocess.run([BIN, *map(str, args)], capture_output=True, text=True, timeout=timeout, env=env)
    return p.returncode, p.stdout, p.stderr


def check(condition, what):
    print(("ok   " if condition else "FAIL ") + what, flush=True)
    if not condition:
        failures.append(what)


def tmpdir():
    return tempfile.mkdtemp(prefix="vdmesh-cli-")


def data(relative):
    path = os.path.join(DATA, relative)
    if not os.path.exists(path):
        print("not run (shared data missing): " + path)
        return None
    return path


def finish():
    print("%d checks failed" % len(failures) if failures else "all checks passed")
    sys.exit(1 if failures else 0)


def read_abaqus_deck(path):
    """A vdmesh Abaqus deck as (nodes, elsets, nsets, surfaces): {id: (x, y, z)},
    {ELSET: [(id, node, ...)]} of its *ELEMENT blocks, {NSET: set of ids}, and
    {*SURFACE name: [(element, side 1..4)]}."""
    import re
    nodes, elsets, nsets, surfaces, mode, current = {}, {}, {}, {}, None, None
    for line in open(path):
        s = line.strip()
        if not s or s.startswith("**"):
            continue
        if s.startswith("*"):
            key = s.upper()
            mode = next((k for k in ("*NODE", "*ELEMENT", "*NSET", "*SURFACE") if key.startswith(k)), None)
            named = {"*ELEMENT": ("ELSET", elsets), "*NSET": ("NSET", nsets), "*SURFACE": ("NAME", surfaces)}
            if mode in named:
                option, into = named[mode]
                current = re.search(option + r"=([A-Za-z0-9_]+)", s, re.I).group(1)
                into.setdefault(current, set() if mode == "*NSET" else [])
            continue
        f = [x.strip() for x in s.split(",") if x.strip()]
        if mode == "*NODE":
            nodes[int(f[0])] = tuple(float(x) for x in f[1:4])
        elif mode == "*ELEMENT":
            elsets[current].append(tuple(int(x) for x in f))
        elif mode == "*NSET":
            nsets[current].update(int(x) for x in f)
        elif mode == "*SURFACE":
            surfaces[current].append((int(f[0]), int(f[1][1:])))
    return nodes, elsets, nsets, surfaces

