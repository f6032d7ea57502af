"""The engine: vdmesh's Python module (`import vdmesh`) inside FreeCAD, else the vdmesh program.

Meshing and export go through the module when FreeCAD's Python can import it (`cmake --install`
puts it on Debian's python3 path; PYTHONPATH=<build>/python works too): no files or process in
between, and the report comes back as a dict. Without the module, or with VDMESH_ENGINE=program,
they run the program. `compare` always runs the program (it is a command-line tool that times
TetGen and vdmesh in child processes).

The program is found through the environment variable VDMESH_BIN, else `vdmesh` on PATH, else the
path stored in the workbench preferences (User parameter:BaseApp/Preferences/Mod/VDMesh, "Binary").
"""
import json
import os
import shutil
import subprocess
import tempfile
import threading
import time

PREFS = "User parameter:BaseApp/Preferences/Mod/VDMesh"

# vdmesh exit codes (README, "Using it")
EXIT_MEANING = {
    1: "internal error in vdmesh",
    2: "usage error (bad option)",
    3: "bad input geometry",
    4: "some facets could not be made Delaunay within the guards",
    5: "a vdmesh mesh failed one of compare's checks",
}


class VDMeshError(RuntimeError):
    """vdmesh could not mesh the shape; `code` is vdmesh's exit code, `message` its explanation."""

    def __init__(self, message, code=None, output=""):
        super().__init__(message)
        self.code = code
        self.message = message
        self.output = output


class VDMeshCancelled(VDMeshError):
    """The run was stopped through its CancelRequest; nothing was made."""

    def __init__(self):
        super().__init__("vdmesh mesh was cancelled")


class CancelRequest:
    """Stops a running mesh_shape from another thread or a GUI callback (the task panel's Stop
    button): the module's CancelToken, or killing the program."""

    def __init__(self):
        self._event = threading.Event()
        core = core_module()
        self.token = core.CancelToken() if core is not None else None

    def set(self):
        self._event.set()
        if self.token is not None:
            self.token.set()

    def is_set(self):
        return self._event.is_set()


def _in_background(work, idle):
    """work() on a worker thread while the calling thread runs idle() every 20 ms (the GUI's event
    loop, so that it repaints and the Stop button works); without idle, work() here."""
    if idle is None:
        return work()
    outcome = {}

    def run():
        try:
            outcome["value"] = work()
        except BaseException as e:  # handed to the calling thread
            outcome["error"] = e

    worker = threading.Thread(target=run, name="vdmesh")
    worker.start()
    while worker.is_alive():
        idle()
        worker.join(0.02)
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


def core_module():
    """The vdmesh Python module, or None when it cannot be imported or VDMESH_ENGINE=program."""
    if os.environ.get("VDMESH_ENGINE", "") == "program":
        return None
    try:
        import vdmesh
    except ImportError:
        return None
    return vdmesh if hasattr(vdmesh, "mesh_cad") else None


def engine_name():
    core = core_module()
    return "module %s" % core.__file__ if core else "program %s" % find_binary()


def _pref_binary():
    try:
        import FreeCAD
        return FreeCAD.ParamGet(PREFS).GetString("Binary", "")
    except Exception:
        return ""


def set_pref_binary(path):
    import FreeCAD
    FreeCAD.ParamGet(PREFS).SetString("Binary", path)


def find_binary():
    """Path of the vdmesh program, or raises VDMeshError saying where it was looked for."""
    env = os.environ.get("VDMESH_BIN", "")
    if env and os.path.isfile(env) and os.access(env, os.X_OK):
        return env
    on_path = shutil.which("vdmesh")
    if on_path:
        return on_path
    pref = _pref_binary()
    if pref and os.path.isfile(pref) and os.access(pref, os.X_OK):
        return pref
    raise VDMeshError("vdmesh program not found: set VDMESH_BIN, put vdmesh on PATH, or set its path "
                      "in the preferences (" + PREFS + ", Binary)" + (" [VDMESH_BIN=%s is not executable]" % env if env else ""))


class Parameters:
    """Meshing parameters; the names are the mesh object's properties."""

    def __init__(self, size=0.0, interior=True, flips=True, ridge_angle=20.0, oracle="dt", lp_limit=0,
                 sliver_angle=10.0, seed=1, order=1):
        self.size = size            # 0: vdmesh chooses (bounding-box diagonal / 25)
        self.interior = interior
        self.flips = flips
        self.ridge_angle = ridge_angle  # --flip-angle: largest ridge angle a flip may create
        self.oracle = oracle
        self.lp_limit = lp_limit    # 0: no limit
        self.sliver_angle = sliver_angle
        self.seed = seed
        self.order = order          # 2: 10-node tetrahedra (C3D10 in the deck)

    def keywords(self):
        """The options as the module's keyword arguments (the same as options() on the command line)."""
        k = {"interior": bool(self.interior), "flips": bool(self.flips), "oracle": self.oracle or "dt",
             "sliver_angle": float(self.sliver_angle), "seed": int(self.seed), "order": int(self.order)}
        if self.size and self.size > 0:
            k["size"] = float(self.size)
        if self.flips:
            k["flip_angle"] = float(self.ridge_angle)
        if self.lp_limit and self.lp_limit > 0:
            k["lp_limit"] = int(self.lp_limit)
        return k

    def options(self):
        o = []
        if self.size and self.size > 0:
            o += ["--size", repr(float(self.size))]
        if not self.interior:
            o.append("--no-interior")
        if not self.flips:
            o.append("--no-flips")
        else:
            o += ["--flip-angle", repr(float(self.ridge_angle))]
        if self.oracle and self.oracle != "dt":
            o += ["--oracle", self.oracle]
        if self.lp_limit and self.lp_limit > 0:
            o += ["--lp-limit", str(int(self.lp_limit))]
        o += ["--sliver-angle", repr(float(self.sliver_angle))]
        o += ["--seed", str(int(self.seed))]
        if int(self.order) == 2:  # only then: a vdmesh without --order still meshes first order
            o += ["--order", "2"]
        return o


def _run(args, timeout=None, cancel=None):
    """Runs the program; a set `cancel` kills it (VDMeshCancelled)."""
    try:
        proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    except OSError as e:
        raise VDMeshError("could not run %s: %s" % (args[0], e))
    start = time.monotonic()
    while True:
        try:
            out, err = proc.communicate(timeout=0.1)
            return subprocess.CompletedProcess(args, proc.returncode, out, err)
        except subprocess.TimeoutExpired:
            stop = cancel is not None and cancel.is_set()
            late = timeout is not None and time.monotonic() - start > timeout
            if stop or late:
                proc.kill()
                proc.communicate()
                if stop:
                    raise VDMeshCancelled()
                raise VDMeshError("vdmesh did not finish within %s s" % timeout)


def _failure(proc, what):
    code = proc.returncode
    lines = [l for l in proc.stderr.splitlines() if l.strip() and not l.startswith("vdmesh: ") or "error" in l.lower()]
    detail = "\n".join(lines[-8:]) if lines else proc.stderr.strip()[-2000:]
    meaning = EXIT_MEANING.get(code, "exit code %s" % code)
    return VDMeshError("%s failed: %s (exit %s)\n%s" % (what, meaning, code, detail), code, proc.stdout + proc.stderr)


def export_shape(shape, path):
    """Writes a Part shape as BREP (vdmesh numbers its solids and faces as FreeCAD does)."""
    shape.exportBrep(path)
    return path


def mesh_file(input_path, output_path, params, report_path=None, timeout=None, cancel=None):
    """Runs `vdmesh mesh`; returns (report dict or None, stdout). Raises VDMeshError on failure."""
    args = [find_binary(), "mesh", input_path, "-o", output_path] + params.options()
    if report_path:
        args += ["--report", report_path]
    proc = _run(args, timeout, cancel)
    if proc.returncode != 0:
        raise _failure(proc, "vdmesh mesh")
    report = None
    if report_path and os.path.isfile(report_path):
        with open(report_path) as f:
            report = json.load(f)
    return report, proc.stdout


def _mesh_with_module(core, brep, params, inp, cancel):
    """mesh_shape through the module; the same errors and exit codes as the program."""
    keywords = params.keywords()
    if cancel is not None and cancel.token is not None:
        keywords["cancel"] = cancel.token
    try:
        mesh, report = core.mesh_cad(brep=brep, **keywords)
    except core.Cancelled:
        raise VDMeshCancelled()
    except core.InputError as e:
        raise VDMeshError("vdmesh mesh failed: %s (exit 3)\n%s" % (EXIT_MEANING[3], e), 3)
    except core.RecoveryError as e:
        raise VDMeshError("vdmesh mesh failed: %s (exit 4)\n%s" % (EXIT_MEANING[4], e), 4)
    except KeyboardInterrupt:
        raise VDMeshError("vdmesh mesh was interrupted")
    except (core.Error, ValueError, TypeError, RuntimeError) as e:
        raise VDMeshError("vdmesh mesh failed: %s" % e, 1)
    core.write(mesh, inp)
    return report, "vdmesh %s: %d tetrahedra\n" % (getattr(core, "__file__", "module"), len(mesh.tets))


def mesh_shape(shape, params, workdir=None, cancel=None, idle=None, name=None):
    """Meshes a Part shape; returns (inp path, report dict, report text). The files stay in workdir:
    the Abaqus deck is what Export converts and what the FemMesh is read from.

    cancel: a CancelRequest; once set, the run stops and VDMeshCancelled is raised. idle: called
    every 20 ms on this thread while the mesher works on another (a GUI passes its event loop).
    name: what an error calls the shape (the part's label)."""
    if shape is None or shape.isNull():
        raise VDMeshError("the selected object has no shape")
    if not shape.Solids:
        raise VDMeshError("the selected shape has no solid (%d faces, %d shells): vdmesh meshes solids"
                          % (len(shape.Faces), len(shape.Shells)))
    own = workdir is None
    workdir = workdir or tempfile.mkdtemp(prefix="vdmesh-")
    try:
        return _mesh_in(workdir, shape, params, cancel, idle)
    except BaseException as e:
        # A failed or stopped run's folder is nobody's: each Stop and each refused part left one
        # in the temporary folder.
        if own:
            shutil.rmtree(workdir, ignore_errors=True)
        if isinstance(e, VDMeshError):
            raise _named(e, workdir, name)
        raise


def _named(error, workdir, name):
    """error with the shape called by name: the program names its input file, which is gone by the
    time a user reads the message (/tmp/vdmesh-.../part.brep), the module calls it <brep>."""
    if name:
        for said in (os.path.join(workdir, "part.brep"), "<brep>"):
            error.message = error.message.replace(said, name)
        error.args = (error.message,)
    return error


def _mesh_in(workdir, shape, params, cancel, idle):
    """mesh_shape's run, its files in workdir."""
    inp = os.path.join(workdir, "mesh.inp")
    core = core_module()
    if core is not None:
        brep = shape.exportBrepToString()  # FreeCAD's shape on this thread only
        report, text = _in_background(lambda: _mesh_with_module(core, brep, params, inp, cancel), idle)
        return inp, report, text
    brep = export_shape(shape, os.path.join(workdir, "part.brep"))
    report, text = _in_background(
        lambda: mesh_file(brep, inp, params, os.path.join(workdir, "report.json"), cancel=cancel), idle)
    return inp, report, text


def convert(input_path, output_path, extra=()):
    """`vdmesh convert`; through the module when there is one (extra: the command line's --binary
    and --msh-version)."""
    core = core_module()
    if core is not None:
        extra = list(extra)
        binary = "--binary" in extra
        version = int(extra[extra.index("--msh-version") + 1]) if "--msh-version" in extra else 41
        try:
            core.write(core.read(input_path), output_path, binary=binary, msh_version=version)
        except (ValueError, RuntimeError, OSError) as e:
            raise VDMeshError("vdmesh convert failed: %s" % e, 3)
        return output_path
    proc = _run([find_binary(), "convert", input_path, output_path] + list(extra))
    if proc.returncode != 0:
        raise _failure(proc, "vdmesh convert")
    return output_path


def compare_shape(shape, size=0.0, timeout=120):
    """`vdmesh compare part.brep --json`: returns (table text, result dict or None, exit code)."""
    workdir = tempfile.mkdtemp(prefix="vdmesh-compare-")
    try:
        brep = export_shape(shape, os.path.join(workdir, "part.brep"))
        out_json = os.path.join(workdir, "compare.json")
        args = [find_binary(), "compare", brep, "--json", out_json, "--timeout", str(timeout)]
        if size and size > 0:
            args += ["--size", repr(float(size))]
        proc = _run(args)
        result = None
        if os.path.isfile(out_json):
            with open(out_json) as f:
                result = json.load(f)
    finally:
        # the table and the result are returned: nothing in the folder is wanted after
        shutil.rmtree(workdir, ignore_errors=True)
    if proc.returncode not in (0, 5) and result is None:
        raise _failure(proc, "vdmesh compare")
    return proc.stdout, result, proc.returncode
