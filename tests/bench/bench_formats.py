"""Read and write throughput of every volume format, vdmesh against meshio.

Usage: /usr/bin/python3 tests/bench/bench_formats.py BUILD_DIR [--n N] [--seed S]
       [--out table.md] [--keep-dir DIR] [--formats msh41b,vtub,...] [--repeat 3]

The mesh is synthesized here: a unit cube cut into N^3 cells of 6 positive
tetrahedra each (Kuhn split; N = 55 gives 998,250 tetrahedra on 175,616
points), interior points moved by up to 1e-3 of a cell (seeded) so that
coordinates carry all 17 digits as real meshes do, two regions (x < 0.5 and
the rest) and the 36,300 boundary triangles with one face id per cube side.
It is written once as TetGen files; then for each format F:

  vdmesh: build/bin/bench_converters grid.node out.F    (write time and peak)
          build/bin/bench_converters out.F              (read time and peak)
  meshio: a fresh /usr/bin/python3 reads out.F and writes it back as F
          (meshio.read / meshio.write timed in that process; peak RSS of that
          process; Python and numpy alone are its baseline, reported too)

Each step runs --repeat times (3); the table gives the fastest time and the
highest peak.
The file copy column is the floor under any reader: the CPU time for
numpy.fromfile to copy the file's bytes into memory once (the file is in the
page cache by then), parsing nothing.
Times are CPU seconds of the read or write call alone (the machine this ran
on is shared: wall-clock seconds, also in the JSON log, mostly measure the
other processes); peak RSS is VmHWM of that step (vdmesh) or of the whole
process (meshio, with the RSS of Python, numpy and meshio alone as baseline). The mesh's own
size is what vdmesh's arrays hold: points x 24 + tetrahedra x 20 (4 node
indices and a region) + triangles x 24 bytes.
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys
import tempfile

import numpy as np

# name, file, vdmesh write options, meshio file_format and write options
# (meshio reads both Gmsh versions as "gmsh" and writes 2.2 as "gmsh22").
FORMATS = [
    ("msh22", "MSH 2.2 ASCII", "out22a.msh", ["--msh-version", "22"], "gmsh22", {"binary": False}),
    ("msh22b", "MSH 2.2 binary", "out22b.msh", ["--msh-version", "22", "--binary"], "gmsh22", {"binary": True}),
    ("msh41", "MSH 4.1 ASCII", "out41a.msh", [], "gmsh", {"binary": False}),
    ("msh41b", "MSH 4.1 binary", "out41b.msh", ["--binary"], "gmsh", {"binary": True}),
    ("vtk", "VTK legacy ASCII", "outa.vtk", [], "vtk", {"binary": False}),
    ("vtkb", "VTK legacy binary", "outb.vtk", ["--binary"], "vtk", {"binary": True}),
    ("vtu", "VTU ASCII", "outa.vtu", [], "vtu", {"binary": False}),
    # meshio compresses VTU with zlib unless told not to; vdmesh writes plain
    # base64, so meshio is asked for the same.
    ("vtub", "VTU binary (base64)", "outb.vtu", ["--binary"], "vtu", {"binary": True, "compression": None}),
    ("inp", "Abaqus", "out.inp", [], "abaqus", {}),
    ("tetgen", "TetGen .node/.ele", "out.node", [], "tetgen", {}),
    ("mesh", "Medit", "out.mesh", [], "medit", {}),
]

# ru_maxrss survives fork and exec (it would report this script's own peak),
# so the child reads VmHWM, which starts afresh with the new program.
MESHIO_CHILD = r"""
import json, sys, time


def hwm():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024


import meshio
import numpy
baseline = hwm()
src, dst, fmt, opts = sys.argv[1], sys.argv[2], sys.argv[3], json.loads(sys.argv[4])
# The floor of any reader: the file's bytes copied into memory once (what
# numpy.fromfile does for each of meshio's binary blocks), nothing parsed.
import os
parts = [src[:-5] + e for e in (".node", ".ele", ".face")] if src.endswith(".node") else [src]
c0 = time.process_time()
for part in parts:
    if os.path.exists(part):
        raw = numpy.fromfile(part, dtype=numpy.uint8)
        del raw
copy_cpu = time.process_time() - c0
t0, c0 = time.perf_counter(), time.process_time()
m = meshio.read(src, file_format="gmsh" if fmt == "gmsh22" else fmt)
read_s, read_cpu = time.perf_counter() - t0, time.process_time() - c0
read_peak = hwm()
t0, c0 = time.perf_counter(), time.process_time()
meshio.write(dst, m, file_format=fmt, **opts)
write_s, write_cpu = time.perf_counter() - t0, time.process_time() - c0
tets = sum(len(c.data) for c in m.cells if c.type == "tetra")
print(json.dumps({"copy_cpu": copy_cpu, "read_s": read_s, "read_cpu": read_cpu, "write_s": write_s, "write_cpu": write_cpu,
                  "tets": tets, "points": len(m.points), "baseline_rss": baseline,
                  "read_peak_rss": read_peak, "peak_rss": hwm()}))
"""


def grid_mesh(n, seed):
    """Points, tetrahedra (0-based), regions, boundary triangles and face ids."""
    rng = np.random.default_rng(seed)
    g = np.linspace(0.0, 1.0, n + 1)
    x, y, z = np.meshgrid(g, g, g, indexing="ij")
    pts = np.stack([x.ravel(), y.ravel(), z.ravel()], axis=1)
    ijk = np.stack(np.meshgrid(*[np.arange(n + 1)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    interior = np.all((ijk > 0) & (ijk < n), axis=1)
    pts[interior] += rng.uniform(-1e-3, 1e-3, (interior.sum(), 3)) / n

    def vid(i, j, k):
        return (i * (n + 1) + j) * (n + 1) + k

    c = np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    corner = lambda b: vid(c[:, 0] + (b & 1), c[:, 1] + ((b >> 1) & 1), c[:, 2] + ((b >> 2) & 1))
    tets = []
    # Kuhn split: 0 -> 7 along each permutation of the axes; (v1, v2) swapped
    # where the permutation is odd so every tetrahedron is positive.
    for a, sign in [((0, 1, 2), 1), ((0, 2, 1), -1), ((1, 0, 2), -1), ((1, 2, 0), 1), ((2, 0, 1), 1), ((2, 1, 0), -1)]:
        b1 = 1 << a[0]
        b2 = b1 | (1 << a[1])
        t = [corner(0), corner(b1), corner(b2), corner(7)]
        if sign < 0:
            t[1], t[2] = t[2], t[1]
        tets.append(np.stack(t, axis=1))
    tets = np.concatenate(tets)
    p = pts[tets]
    det = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    assert (det > 0).all(), "negative tetrahedra in the synthesized grid"
    region = np.where(p.mean(axis=1)[:, 0] < 0.5, 1, 2)

    # Boundary: the faces lying in a side of the cube (all three vertices on
    # it), outward as listed; the face id is the side.
    faces = np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 3, 2]], tets[:, [0, 1, 3]], tets[:, [0, 2, 1]]])
    fijk = ijk[faces]
    face = np.zeros(len(faces), dtype=int)
    for axis in range(3):
        face[(fijk[:, :, axis] == 0).all(axis=1)] = 1 + 2 * axis
        face[(fijk[:, :, axis] == n).all(axis=1)] = 2 + 2 * axis
    tris, face = faces[face > 0], face[face > 0]
    assert len(tris) == 12 * n * n
    assert (face > 0).all()
    return pts, tets, region, tris, face


def write_tetgen(base, pts, tets, region, tris, face):
    with open(base + ".node", "w") as f:
        f.write("%d 3 0 0\n" % len(pts))
        np.savetxt(f, np.column_stack([np.arange(1, len(pts) + 1), pts]), fmt=["%d", "%.17g", "%.17g", "%.17g"])
    with open(base + ".ele", "w") as f:
        f.write("%d 4 1\n" % len(tets))
        np.savetxt(f, np.column_stack([np.arange(1, len(tets) + 1), tets + 1, region]), fmt="%d")
    with open(base + ".face", "w") as f:
        f.write("%d 1\n" % len(tris))
        np.savetxt(f, np.column_stack([np.arange(1, len(tris) + 1), tris + 1, face]), fmt="%d")


def run_json(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        return {"error": "exit %d: %s" % (r.returncode, (r.stderr or r.stdout).strip()[-300:])}
    return json.loads(r.stdout.strip().splitlines()[-1])


def best_of(runs):
    """Times from the fastest of the runs (the others lost time to other
    processes on the shared machine); peaks from the highest."""
    if any("error" in r for r in runs):
        return next(r for r in runs if "error" in r)
    best = dict(runs[0])
    for r in runs[1:]:
        for k, v in r.items():
            if k.endswith("_s") or k.endswith("_cpu"):
                best[k] = min(best[k], v)
            elif "rss" in k and k not in ("rss_start", "baseline_rss"):
                best[k] = max(best[k], v)
    return best


def mib(b):
    return b / 2**20


def file_size(path):
    if path.endswith(".node"):
        base = path[:-5]
        return sum(os.path.getsize(base + e) for e in (".node", ".ele", ".face") if os.path.exists(base + e))
    return os.path.getsize(path)


def machine():
    model = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            model = line.split(":", 1)[1].strip()
            break
    return "%s, %d CPUs (%s), load %.1f at start" % (platform.platform(), os.cpu_count(), model, os.getloadavg()[0])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("build")
    ap.add_argument("--n", type=int, default=55)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out")
    ap.add_argument("--keep-dir")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each step; the fastest counts")
    ap.add_argument("--formats", help="comma-separated names: " + ",".join(f[0] for f in FORMATS))
    args = ap.parse_args()
    tool = os.path.join(os.path.abspath(args.build), "bin", "bench_converters")
    if not os.path.exists(tool):
        sys.exit("bench_formats: %s not found (cmake --build BUILD --target bench_converters)" % tool)
    chosen = FORMATS if not args.formats else [f for f in FORMATS if f[0] in args.formats.split(",")]

    work = args.keep_dir or tempfile.mkdtemp(prefix="vdmesh-bench-formats-")
    os.makedirs(work, exist_ok=True)
    started = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    where = machine()
    pts, tets, region, tris, face = grid_mesh(args.n, args.seed)
    src = os.path.join(work, "grid.node")
    write_tetgen(src[:-5], pts, tets, region, tris, face)
    own = len(pts) * 24 + len(tets) * 20 + len(tris) * 24
    n_points, n_tets, n_tris = len(pts), len(tets), len(tris)
    del pts, tets, region, tris, face  # children fork from a small process
    print("mesh: %d points, %d tetrahedra, %d boundary triangles; own size %.1f MiB" %
          (n_points, n_tets, n_tris, mib(own)), file=sys.stderr)

    rows = []
    for name, label, file, opts, mformat, mopts in chosen:
        out = os.path.join(work, file)
        w = best_of([run_json([tool, src, out] + opts) for _ in range(args.repeat)])
        r = best_of([run_json([tool, out]) for _ in range(args.repeat)]) if "error" not in w else w
        mout = os.path.join(work, "meshio_" + file)
        m = best_of([run_json(["/usr/bin/python3", "-c", MESHIO_CHILD, out, mout, mformat, json.dumps(mopts)])
                     for _ in range(args.repeat)])
        ok = "error" not in r and r["tets"] == n_tets and r["points"] == n_points
        row = {"name": name, "label": label, "bytes": file_size(out) if "error" not in w else 0,
               "vdmesh_write": w, "vdmesh_read": r, "meshio": m, "counts_ok": ok}
        rows.append(row)
        print(json.dumps(row), file=sys.stderr)
        for f in (mout,):
            if not args.keep_dir and os.path.exists(f):
                os.remove(f)

    lines = ["Measured %s; %s. Mesh: unit cube, %d^3 cells x 6 tetrahedra (synthesized, seed %d): "
             "%s points, %s tetrahedra, %s boundary triangles; own size %.1f MiB."
             % (started, where, args.n, args.seed, f"{n_points:,}", f"{n_tets:,}", f"{n_tris:,}", mib(own)),
             "",
             "| format | file MiB | file copy CPU s | vdmesh read CPU s | meshio read CPU s | read speed-up | vdmesh write CPU s "
             "| meshio write CPU s | write speed-up | vdmesh peak MiB read / write (x own size) | meshio peak MiB (baseline) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        w, r, m = row["vdmesh_write"], row["vdmesh_read"], row["meshio"]
        if "error" in w or "error" in r:
            lines.append("| %s | | | fails: %s | | | | | | | |" % (row["label"], (w.get("error") or r.get("error"))[:80]))
            continue
        if "error" in m:
            mr = mw = "fails"
            sr = sw = mp = cp = ""
        else:
            mr, mw = "%.3f" % m["read_cpu"], "%.2f" % m["write_cpu"]
            cp = "%.3f" % m["copy_cpu"]
            sr = "%.1f" % (m["read_cpu"] / r["read_cpu"])
            sw = "%.1f" % (m["write_cpu"] / w["write_cpu"])
            mp = "%.0f (%.0f)" % (mib(m["peak_rss"]), mib(m["baseline_rss"]))
            if m["tets"] != n_tets:
                mr += " (%d tets)" % m["tets"]
        lines.append("| %s | %.1f | %s | %.3f | %s | %s | %.2f | %s | %s | %.0f / %.0f (%.1f / %.1f) | %s |" % (
            row["label"] + ("" if row["counts_ok"] else " (counts differ)"), mib(row["bytes"]), cp,
            r["read_cpu"], mr, sr, w["write_cpu"], mw, sw,
            mib(r["read_peak_rss"]), mib(w["write_peak_rss"]),
            r["read_peak_rss"] / own, w["write_peak_rss"] / own, mp))
    text = "\n".join(lines) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    if any("error" in row["meshio"] for row in rows):
        for row in rows:
            if "error" in row["meshio"]:
                print("meshio %s: %s" % (row["name"], row["meshio"]["error"]), file=sys.stderr)


if __name__ == "__main__":
    main()
