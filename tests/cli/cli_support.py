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
