#!/usr/bin/env python3
"""Benchmark of surface recovery (Delaunayhood + Delaunayzation, no interior
vertices) per oracle, beside `tetgen -pY` on the same surface, measured in
the same run. Prints a Markdown table: seconds and peak memory (MiB).

  /usr/bin/python3 tests/bench/bench_recovery.py BUILD_DIR [--oracles dt,sphere,lp] [--quick] [--runs N]

Each program runs N times (default 3), the two taking turns, and the table
gives the fastest run's seconds and the largest peak memory: single runs of
the same program moved by 30 % from one run of the benchmark to the next
(TetGen 1.21 -> 2.33 s on the bunny) on the shared 2-core machine.

vdmesh runs with --no-interior --keep-slivers: the Delaunay tetrahedra of
the recovered surface, as tetgen -pY gives its constrained ones (neither
improves quality; vdmesh's sliver pass is measured in bench_quality.py).
Besides whole runs, the same step on both sides: vdmesh's tetrahedralize +
delaunayzation phases (its report) against TetGen's own "Delaunay seconds" +
"Boundary recovery seconds" (a second run with -V, which prints them).

Inputs: icospheres of about 10k, 100k and 1M facets (written by this script)
and the largest closed surfaces of the shared data ($VDMESH_DATA).
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cli"))
from surface_shapes import icosphere, write_off  # noqa: E402

DATA = os.environ.get("VDMESH_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))


def icosphere_off(path, levels):
    pts, tris = icosphere(levels)
    write_off(path, pts, tris)
    return len(tris)


def peak_of(cmd, timeout=3600):
    """Runs cmd in a fresh helper process; returns (exit code, seconds, peak
    RSS in MiB) of cmd alone."""
    wrapper = [sys.executable, "-c",
               "import resource,subprocess,sys,time;t=time.time();"
               "r=subprocess.run(sys.argv[1:],capture_output=True);"
               "print(r.returncode, time.time()-t, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss/1024.0)",
               *cmd]
    try:
        p = subprocess.run(wrapper, capture_output=True, text=True, timeout=timeout)
        code, sec, mib = p.stdout.split()
        return int(code), float(sec), float(mib)
    except subprocess.TimeoutExpired:
        return "timeout", float(timeout), float("nan")


def tetgen_phases(tg_in):
    """TetGen's Delaunay + boundary recovery seconds, as it prints them."""
    out = subprocess.run(["tetgen", "-pYV", tg_in], capture_output=True, text=True).stdout
    sec = {}
    for line in out.splitlines():
        for key in ("Delaunay seconds:", "Boundary recovery seconds:"):
            if line.strip().startswith(key):
                sec[key] = float(line.split(":")[1])
    return sum(sec.values()) if len(sec) == 2 else None


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    vdmesh = os.path.join(build, "bin", "vdmesh")
    oracles = ["dt", "sphere", "lp"]
    quick = "--quick" in sys.argv
    runs = int(sys.argv[sys.argv.index("--runs") + 1]) if "--runs" in sys.argv else 3
    if "--oracles" in sys.argv:
        oracles = sys.argv[sys.argv.index("--oracles") + 1].split(",")
    work = tempfile.mkdtemp(prefix="vdmesh-bench-")
    inputs = []
    # Level 5 is 20k facets, 6 is 82k, 7 is 328k, 8 is 1.3M.
    for levels in ([5, 6] if quick else [5, 6, 8]):
        path = os.path.join(work, "icosphere-%d.off" % levels)
        n = icosphere_off(path, levels)
        inputs.append(("icosphere %dk" % (n // 1000), path))
    for rel in ["surface/cgal_bunny00.off", "surface-large/c3tm_nefertiti.obj", "surface-large/cgal_refined_elephant.off"]:
        p = os.path.join(DATA, rel)
        if os.path.exists(p):
            inputs.append((os.path.basename(rel), p))
    print("| input | facets | " + " | ".join("vdmesh %s s / MiB / added facets" % o for o in oracles) +
          " | tetgen -pY s / MiB | dt speed-up vs tetgen | tetgen Delaunay + boundary recovery s |"
          " dt recovery speed-up vs tetgen's |")
    print("|---|---|" + "---|" * len(oracles) + "---|---|---|---|")
    for name, path in inputs:
        # TetGen writes its output beside its input: a copy in the work
        # directory (run on the shared file, it wrote five files into it).
        if path.endswith((".off", ".smesh", ".poly", ".stl")):
            tg_in = os.path.join(work, "tg" + os.path.splitext(path)[1])
            shutil.copyfile(path, tg_in)
        else:
            tg_in = os.path.join(work, "tg.off")
            subprocess.run([vdmesh, "convert", path, tg_in], check=True)
        best = {}  # oracle or "tetgen" -> (code, fastest seconds, largest MiB, fastest recovery s, added facets)
        facets = "?"
        for _ in range(runs):
            for o in oracles:
                report = os.path.join(work, "r.json")
                code, sec, mib = peak_of([vdmesh, "mesh", path, "-o", os.path.join(work, "out.vtu"), "--no-interior",
                                          "--keep-slivers", "--oracle", o, "--quiet", "--report", report])
                rec, added = None, "-"
                if code == 0:
                    r = json.load(open(report))
                    added = r["counts"]["added_surface_facets"]
                    facets = r["counts"]["input_facets"]
                    rec = sum(v for k, v in r["seconds"].items() if k in ("tetrahedralize", "delaunayzation"))
                best[o] = merge(best.get(o), (code, sec, mib, rec, added))
            code, sec, mib = peak_of(["tetgen", "-pYQ", tg_in])
            rec = tetgen_phases(tg_in) if code == 0 else None
            best["tetgen"] = merge(best.get("tetgen"), (code, sec, mib, rec, None))
        cells = []
        for o in oracles:
            code, sec, mib, rec, added = best[o]
            cells.append("%.2f (recovery %.2f) / %.0f / %s" % (sec, rec, mib, added) if code == 0
                         else "exit %s after %.1f s" % (code, sec))
        dt_time, dt_recovery = (best["dt"][1], best["dt"][3]) if "dt" in best and best["dt"][0] == 0 else (None, None)
        code, sec, mib, tg_rec, _ = best["tetgen"]
        tg = "%.2f / %.0f" % (sec, mib) if code == 0 else "failed (%s)" % code
        ratio = "%.1fx" % (sec / dt_time) if code == 0 and dt_time else "-"
        tg_rec_cell = "%.2f" % tg_rec if tg_rec is not None else "-"
        rec_ratio = "%.1fx" % (tg_rec / dt_recovery) if tg_rec and dt_recovery else "-"
        print("| %s | %s | %s | %s | %s | %s | %s |" % (name, facets, " | ".join(cells), tg, ratio, tg_rec_cell,
                                                       rec_ratio), flush=True)


def merge(kept, run):
    """Of two runs' (code, seconds, MiB, recovery seconds, added): a failed
    run stands; else the fastest seconds and recovery, the largest MiB."""
    if kept is None:
        return run
    if kept[0] != 0:
        return kept
    if run[0] != 0:
        return run
    rec = min(x for x in (kept[3], run[3]) if x is not None) if (kept[3] is not None or run[3] is not None) else None
    return (0, min(kept[1], run[1]), max(kept[2], run[2]), rec, run[4])

if __name__ == "__main__":
    main()
