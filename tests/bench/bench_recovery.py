#!/usr/bin/env python3
"""Benchmark of surface recovery (Delaunayhood + Delaunayzation, no interior
vertices) per oracle, beside `tetgen -pY` on the same surface, measured in
the same run. Prints a Markdown table: seconds and peak memory (MiB).

  /usr/bin/python3 tests/bench/bench_recovery.py BUILD_DIR [--oracles dt,sphere,lp] [--quick]

Inputs: icospheres of about 10k, 100k and 1M facets (written by this script)
and the largest closed surfaces of the shared data ($VDMESH_DATA).
"""
import json
import math
import os
import resource
import subprocess
import sys
import tempfile

DATA = os.environ.get("VDMESH_DATA", os.path.join(os.path.dirname(__file__), "..", "..", "..", "shared", "data"))


def icosphere_off(path, levels):
    t = (1 + math.sqrt(5)) / 2
    pts = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
           (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    pts = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in pts]
    tris = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
            (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11),
            (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(levels):
        mid = {}

        def m(a, b):
            k = (min(a, b), max(a, b))
            if k not in mid:
                p = [(x + y) / 2 for x, y in zip(pts[a], pts[b])]
                n = math.sqrt(sum(x * x for x in p))
                pts.append(tuple(x / n for x in p))
                mid[k] = len(pts) - 1
            return mid[k]
        nxt = []
        for a, b, c in tris:
            ab, bc, ca = m(a, b), m(b, c), m(c, a)
            nxt += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        tris = nxt
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(pts), len(tris)))
        f.writelines("%.17g %.17g %.17g\n" % p for p in pts)
        f.writelines("3 %d %d %d\n" % t for t in tris)
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


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    vdmesh = os.path.join(build, "bin", "vdmesh")
    oracles = ["dt", "sphere", "lp"]
    quick = "--quick" in sys.argv
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
          " | tetgen -pY s / MiB | dt speed-up vs tetgen |")
    print("|---|---|" + "---|" * len(oracles) + "---|---|")
    for name, path in inputs:
        cells = []
        dt_time = None
        facets = "?"
        for o in oracles:
            report = os.path.join(work, "r.json")
            code, sec, mib = peak_of([vdmesh, "mesh", path, "-o", os.path.join(work, "out.vtu"), "--no-interior",
                                      "--oracle", o, "--quiet", "--report", report])
            added = "-"
            if code == 0:
                r = json.load(open(report))
                added = r["counts"]["added_surface_facets"]
                facets = r["counts"]["input_facets"]
                rec = sum(v for k, v in r["seconds"].items() if k in ("tetrahedralize", "delaunayzation"))
                cells.append("%.2f (recovery %.2f) / %.0f / %s" % (sec, rec, mib, added))
                if o == "dt":
                    dt_time = sec
            else:
                cells.append("exit %s after %.1f s" % (code, sec))
        tg_in = path
        if not path.endswith((".off", ".smesh", ".poly", ".stl")):
            tg_in = os.path.join(work, "tg.off")
            subprocess.run([vdmesh, "convert", path, tg_in], check=True)
        code, sec, mib = peak_of(["tetgen", "-pYQ", tg_in])
        tg = "%.2f / %.0f" % (sec, mib) if code == 0 else "failed (%s)" % code
        ratio = "%.1fx" % (sec / dt_time) if code == 0 and dt_time else "-"
        print("| %s | %s | %s | %s | %s |" % (name, facets, " | ".join(cells), tg, ratio), flush=True)


if __name__ == "__main__":
    main()
