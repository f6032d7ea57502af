#!/usr/bin/env python3
"""Quality table of issue 3: vdmesh (default size field, sliver pass on)
against `tetgen -pq1.414/10 -aV A` with V chosen for a similar number of
tetrahedra, in the same run, on the shared surfaces and the paper's cases.

  /usr/bin/python3 tests/bench/bench_quality.py BUILD_DIR [--out FILE.md] [--timeout S] [--only TEXT]
      [--all] [--work DIR]

Per input: `vdmesh compare INPUT --runs quality --keep-dir` meshes it with
vdmesh (its report gives the figures before and after the sliver pass) and
finds TetGen's volume bound V for a count near vdmesh's (README, "TetGen
cross-check"); then TetGen runs again on compare's .smesh with the 10-degree
dihedral bound added (-q1.414/10 aV), once more with V rescaled when the count
is off by more than 25 %. Tetrahedra, smallest dihedral angle and the share
under 10 degrees are recomputed here with numpy from both meshers' files.

The issue exempts tetrahedra "next to input facet angles under 20 degrees"
from the 0.1 % target. Here such a tetrahedron has a vertex on an input facet
(within 1e-6 of the bounding diagonal of its plane and inside it) that has a
corner under 20 degrees or meets another facet along an edge at under 20
degrees; the table gives the share under 10 degrees with and without them.

Without --all the slow inputs (bunny, armadillo, cheese, surface-large: 9 of the
10 minutes of a run with them, TetGen up to 148 s on Nefertiti; give --timeout
900) are left out, and so are the CAD files always.
"""
import datetime
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "cli"))
from surface_shapes import icosphere, paper_pyramids, write_off  # noqa: E402
from tet_angles import dihedral_angles  # noqa: E402

DATA = os.environ.get("VDMESH_DATA", os.path.join(HERE, "..", "..", "..", "shared", "data"))
SHARED = ["surface", "surface-multiregion", "plc-sharp", "surface-large"]
SLOW = ("cgal_bunny00", "cgal_armadillo", "cgal_cheese", "surface-large/")
REFUSED = ("cgal_complex_patch", "cgal_horizons.off", "openfoam_buildings")  # open or self-intersecting


def cube(n):
    """Unit cube, each side an n x n grid of squares cut in two, outward."""
    pts, index, tris = [], {}, []

    def vid(p):
        if p not in index:
            index[p] = len(pts)
            pts.append(tuple(x / n for x in p))
        return index[p]
    for axis in range(3):
        for side in (0, n):
            for i in range(n):
                for j in range(n):
                    q = []
                    for di, dj in ((0, 0), (1, 0), (1, 1), (0, 1)):
                        p = [0, 0, 0]
                        p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, i + di, j + dj
                        q.append(vid(tuple(p)))
                    a, b, c, d = q
                    t = [(a, b, c), (a, c, d)]
                    if side == 0:
                        t = [(x, z, y) for x, y, z in t]
                    tris += t
    return pts, tris


def paper_cases(work):
    """The paper's sphere (§9.4), two almost touching pyramids (§9.8), a cube."""
    out = []
    pts, tris = icosphere(3)
    write_off(os.path.join(work, "sphere-1280.off"), pts, tris)
    out.append(("paper: sphere 1280 facets", os.path.join(work, "sphere-1280.off")))
    write_off(os.path.join(work, "pyramids.off"), *paper_pyramids())
    out.append(("paper: two pyramids", os.path.join(work, "pyramids.off")))
    pts, tris = cube(8)
    write_off(os.path.join(work, "cube-8.off"), pts, tris)
    out.append(("cube 8x8 per side", os.path.join(work, "cube-8.off")))
    return out


def shared_inputs(everything):
    for cat in SHARED:
        folder = os.path.join(DATA, cat)
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            rel = cat + "/" + name
            if name.endswith((".md", ".tsv", ".txt")) or any(r in rel for r in REFUSED):
                continue
            if not everything and any(s in rel for s in SLOW):
                continue
            yield rel, os.path.join(folder, name)


def read_tetgen(base):
    """Points and tetrahedra (0-based) of TetGen's BASE.node / BASE.ele."""
    def rows(path):
        with open(path) as f:
            lines = [ln.split("#")[0].split() for ln in f]
        lines = [ln for ln in lines if ln]
        return lines[0], lines[1:]
    head, node = rows(base + ".node")
    n = int(head[0])
    ids = np.array([int(r[0]) for r in node[:n]])
    pts = np.array([[float(x) for x in r[1:4]] for r in node[:n]])
    head, ele = rows(base + ".ele")
    m = int(head[0])
    tets = np.array([[int(x) for x in r[1:5]] for r in ele[:m]], dtype=np.int64)
    tets -= ids.min()
    return pts, tets


def quality(pts, tets):
    """Count, smallest dihedral angle, share of tetrahedra with an angle under 10 degrees, inverted count."""
    a, b, c, d = (pts[tets[:, k]] for k in range(4))
    vol = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)
    angles = dihedral_angles(pts, tets)
    lowest = angles.min(axis=0)
    return {"tets": len(tets), "min": float(lowest.min()), "under10": int((lowest < 10).sum()),
            "under5": int((lowest < 5).sum()),
            "pct10": 100.0 * float((lowest < 10).mean()), "inverted": int((vol <= 0).sum())}


def read_smesh(path):
    """Points and facets (0-based) of a .smesh with its nodes inline, as compare writes it."""
    with open(path) as f:
        lines = [ln.split("#")[0].split() for ln in f]
    lines = [ln for ln in lines if ln]
    n = int(lines[0][0])
    ids = [int(r[0]) for r in lines[1:1 + n]]
    pts = np.array([[float(x) for x in r[1:4]] for r in lines[1:1 + n]])
    m = int(lines[1 + n][0])
    facets = np.array([[int(x) for x in r[1:4]] for r in lines[2 + n:2 + n + m] if r[0] == "3"], dtype=np.int64)
    return pts, facets - min(ids)


def small_angle_facets(pts, facets, limit_deg=20.0):
    """Facets with a corner under the limit, or meeting another facet along an edge at under it."""
    a, b, c = (pts[facets[:, k]] for k in range(3))

    def corner(x, y, z):
        u, v = y - x, z - x
        cos = np.einsum("ij,ij->i", u, v) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))
    small = np.minimum(np.minimum(corner(a, b, c), corner(b, c, a)), corner(c, a, b)) < limit_deg
    around = {}
    for f, t in enumerate(facets):
        for e in range(3):
            around.setdefault(tuple(sorted((t[e], t[(e + 1) % 3]))), []).append(f)
    for (p, q), fs in around.items():
        axis = pts[q] - pts[p]
        axis = axis / np.linalg.norm(axis)
        wings = []
        for f in fs:
            o = [v for v in facets[f] if v != p and v != q][0]
            w = pts[o] - pts[p]
            w = w - np.dot(w, axis) * axis
            wings.append(w / np.linalg.norm(w))
        for i in range(len(fs)):
            for j in range(i + 1, len(fs)):
                if np.degrees(np.arccos(np.clip(np.dot(wings[i], wings[j]), -1, 1))) < limit_deg:
                    small[fs[i]] = small[fs[j]] = True
    return small


def near_small_angles(input_smesh, pts, tets):
    """Per tetrahedron: has it a vertex on an input facet with an angle under 20 degrees?"""
    ipts, ifacets = read_smesh(input_smesh)
    marked = ifacets[small_angle_facets(ipts, ifacets)]
    tol = 1e-6 * np.linalg.norm(ipts.max(axis=0) - ipts.min(axis=0))
    on = np.zeros(len(pts), dtype=bool)
    order = np.argsort(pts[:, 0])
    xs = pts[order, 0]
    for t in marked:
        a, b, c = ipts[t]
        lo, hi = np.minimum(np.minimum(a, b), c) - tol, np.maximum(np.maximum(a, b), c) + tol
        cand = order[np.searchsorted(xs, lo[0]):np.searchsorted(xs, hi[0], side="right")]
        cand = cand[np.all((pts[cand] >= lo) & (pts[cand] <= hi), axis=1)]
        if len(cand) == 0:
            continue
        n = np.cross(b - a, c - a)
        area2 = np.dot(n, n)
        if area2 == 0:
            continue
        x = pts[cand] - a
        close = np.abs(x @ n) <= tol * np.sqrt(area2)
        # Barycentric coordinates in the plane, with a tolerance of tol along the edges.
        u = np.einsum("ij,j->i", np.cross(x, c - a), n) / area2
        v = np.einsum("ij,j->i", np.cross(b - a, x), n) / area2
        slack = tol / np.sqrt(area2) * max(np.linalg.norm(b - a), np.linalg.norm(c - a), np.linalg.norm(c - b))
        inside = (u >= -slack) & (v >= -slack) & (u + v <= 1 + slack)
        on[cand[close & inside]] = True
    return on[tets].any(axis=1)


def run_tetgen(smesh, switches, timeout):
    """TetGen on a copy of compare's .smesh; (quality dict or None, seconds, note)."""
    base = smesh[:-len(".smesh")] + "-" + re.sub(r"[^A-Za-z0-9.]", "_", switches)
    shutil.copy(smesh, base + ".smesh")
    t0 = time.time()
    try:
        p = subprocess.run(["tetgen", "-" + switches, base + ".smesh"], capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, time.time() - t0, "timeout"
    seconds = time.time() - t0
    if p.returncode != 0 or not os.path.exists(base + ".1.ele"):
        return None, seconds, "exit %d" % p.returncode
    pts, tets = read_tetgen(base + ".1")
    return quality(pts, tets), seconds, ""


def machine():
    cpu = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    mem = 0
    for line in open("/proc/meminfo"):
        if line.startswith("MemTotal"):
            mem = int(line.split()[1]) / 1024 / 1024
    return "%s, %d CPUs (%s), %.0f GiB, load %.1f at start" % (
        platform.platform(terse=True), os.cpu_count(), cpu, mem, os.getloadavg()[0])


def bench_one(binary, name, path, work, timeout):
    keep = os.path.join(work, re.sub(r"[^A-Za-z0-9.]", "_", name))
    shutil.rmtree(keep, ignore_errors=True)
    js = keep + ".json"
    t0 = time.time()
    p = subprocess.run([binary, "compare", path, "--runs", "quality", "--json", js, "--keep-dir", keep,
                        "--timeout", str(timeout), "--quiet"], capture_output=True, text=True)
    row = {"input": name, "compare_exit": p.returncode, "compare_seconds": time.time() - t0}
    if not os.path.exists(js):
        row["note"] = "compare exit %d: %s" % (p.returncode, (p.stderr.strip().splitlines() or ["?"])[-1][:120])
        return row
    report = json.load(open(js))
    run = next(r for r in report["runs"] if r["name"] == "quality")
    v, t = run["vdmesh"], run["tetgen"]
    row["facets"] = report.get("input_facets")
    row["vdmesh_status"] = "ok" if v.get("passed_checks") else ("checks fail" if v.get("meshed") else "fail")
    row["vdmesh_seconds"] = v.get("seconds")
    if not v.get("meshed"):
        row["note"] = "vdmesh: " + v.get("status", "?")
        return row
    row["slivers"] = v["report"]["slivers"]
    vpts, vtets = read_tetgen(os.path.join(keep, "quality-vdmesh"))
    row["vdmesh"] = quality(vpts, vtets)
    near = near_small_angles(os.path.join(keep, "quality-tetgen.smesh"), vpts, vtets)
    lowest = dihedral_angles(vpts, vtets).min(axis=0)
    away = lowest[~near]
    row["vdmesh"]["near_small_input_angles"] = int(near.sum())
    row["vdmesh"]["under10_away"] = int((away < 10).sum())
    row["vdmesh"]["pct10_away"] = 100.0 * float((away < 10).sum()) / max(1, len(lowest))
    row["tetgen_q"] = {"label": t.get("label"), "tets": t.get("tetrahedra"), "min": t.get("min_dihedral_deg")}
    # TetGen with the 10-degree bound, at compare's volume bound, rescaled once.
    smesh = os.path.join(keep, "quality-tetgen.smesh")
    m = re.search(r"a([0-9.eE+-]+)A$", t.get("label") or "")
    bound = float(m.group(1)) if m else None
    target = row["vdmesh"]["tets"]
    attempts = []
    switches = "pq1.414/10" + ("a%g" % bound if bound else "") + "A"
    q, secs, note = run_tetgen(smesh, switches, timeout)
    attempts.append((switches, q, secs, note))
    if q and bound and abs(np.log(q["tets"] / target)) > np.log(1.25):
        bound2 = bound * q["tets"] / target
        switches2 = "pq1.414/10a%gA" % bound2
        q2, secs2, note2 = run_tetgen(smesh, switches2, timeout)
        attempts.append((switches2, q2, secs2, note2))
    ok = [a for a in attempts if a[1]]
    best = min(ok, key=lambda a: abs(np.log(a[1]["tets"] / target))) if ok else attempts[-1]
    row["tetgen10"] = {"switches": best[0], "q": best[1], "seconds": best[2], "note": best[3],
                       "attempts": [(a[0], a[1]["tets"] if a[1] else a[3]) for a in attempts]}
    return row


def fmt_row(r):
    if "vdmesh" not in r:
        return "| %s | %s | %s | | | | | | | | | | |" % (r["input"], r.get("facets", "-"), r.get("note", "-"))
    s, v, t = r["slivers"], r["vdmesh"], r["tetgen10"]
    tq = t["q"]
    return "| %s | %d | %d | %.2f / %.2f | %d / %d | %d / %d (%.2f %%) | %d (%.2f %%) | %s | %s | %s | %s | %s | %.1f / %s |" % (
        r["input"], r["facets"], v["tets"], s["min_dihedral_before_deg"], v["min"],
        s["tets_below_5_deg_before"], v["under5"],
        s["tets_below_10_deg_before"], v["under10"], v["pct10"], v["under10_away"], v["pct10_away"],
        r["vdmesh_status"],
        tq["tets"] if tq else t["note"], "%.2f" % tq["min"] if tq else "-", "%.2f %%" % tq["pct10"] if tq else "-",
        "yes" if tq and v["min"] >= tq["min"] and v["pct10_away"] < 0.1 else "no",
        r["vdmesh_seconds"], "%.1f" % t["seconds"] if tq else "-")


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        print(__doc__)
        return 2
    build = os.path.abspath(args[0])
    flags = {a for a in args[1:] if a == "--all"}
    rest = [a for a in args[1:] if a != "--all"]
    opts = dict(zip(rest[0::2], rest[1::2]))
    binary = os.path.join(build, "bin", "vdmesh")
    timeout = float(opts.get("--timeout", "120"))
    work = opts.get("--work") or tempfile.mkdtemp(prefix="vdmesh-bench-quality-")
    os.makedirs(work, exist_ok=True)
    cases = paper_cases(work) + list(shared_inputs("--all" in flags))
    if "--only" in opts:
        cases = [c for c in cases if opts["--only"] in c[0]]
    started, header = time.time(), machine()
    rows = []
    for name, path in cases:
        r = bench_one(binary, name, path, work, timeout)
        rows.append(r)
        print("%-50s %s" % (name, json.dumps({k: r.get(k) for k in ("vdmesh", "tetgen10", "note")})),
              file=sys.stderr, flush=True)
    with open(os.path.join(work, "bench_quality.json"), "w") as f:
        json.dump(rows, f, indent=1)
    lines = ["%s; %s; %d inputs in %.1f min (limit %g s per mesher run); raw figures in %s." % (
        datetime.date.today().isoformat(), header, len(rows), (time.time() - started) / 60, timeout,
        os.path.join(work, "bench_quality.json")), "",
        "| input | facets | vdmesh tets | vdmesh min dihedral before / after sliver pass | vdmesh tets < 5 deg "
        "before / after | vdmesh tets < 10 deg before / after (% after) | of those, away from input angles < 20 deg (% of all) | vdmesh checks | tetgen -q1.414/10 tets | tetgen min dihedral | "
        "tetgen % < 10 deg | issue target met | s vdmesh / tetgen |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    lines += [fmt_row(r) for r in rows]
    text = "\n".join(lines) + "\n"
    print(text)
    if "--out" in opts:
        with open(opts["--out"], "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
