#!/usr/bin/env python3
"""`vdmesh compare` over every input of the shared corpus ($VDMESH_DATA,
default ../shared/data): a Markdown table per run (boundary-preserving,
quality) with both meshers' success, time, tetrahedra, smallest dihedral
angle and added boundary vertices, and a summary row (successes, median time
ratio vdmesh / TetGen, median difference of the smallest angle vdmesh - TetGen,
both over the inputs where both succeeded).

  /usr/bin/python3 tests/bench/bench_compare.py BUILD_DIR [--out FILE.md] [--timeout S] [--only TEXT]
      [--runs boundary,quality] [--json-dir DIR]

--timeout is the limit of each mesher run (default 30 s), so that the whole
corpus takes under 30 minutes on the 2-core development machine.

CAD files (.step .stp .iges .igs .brep) go through compare too: it tessellates
them as `vdmesh mesh` does and gives both meshers that surface.
"""
import datetime
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
DATA = os.environ.get("VDMESH_DATA", os.path.join(HERE, "..", "..", "..", "shared", "data"))
CATEGORIES = ["surface", "surface-multiregion", "plc-sharp", "surface-large", "cad-part", "cad-assembly"]


def inputs(only):
    for cat in CATEGORIES:
        folder = os.path.join(DATA, cat)
        if not os.path.isdir(folder):
            continue
        for name in sorted(os.listdir(folder)):
            if name.endswith((".md", ".tsv", ".txt")):
                continue
            rel = os.path.join(cat, name)
            if only and only not in rel:
                continue
            yield rel


def machine():
    cpu = "?"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = "?"
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = "%.0f GiB" % (int(line.split()[1]) / 1024 / 1024)
    except OSError:
        pass
    load = os.getloadavg()[0]
    return "%s, %d CPUs (%s), %s, load %.1f at start" % (platform.platform(terse=True), os.cpu_count(), cpu, mem, load)


def cell(m, key, fmt="%s"):
    if not m or not m.get("meshed") or key not in m:
        return "-"
    return fmt % m[key]


def outcome(m):
    if m is None:
        return "-"
    if not m["meshed"]:
        status = m["status"]
        if "timed out" in status:
            return "timeout"
        if status == "exit 0":  # ran, but left no tetrahedra (e.g. TetGen on an open surface)
            return "fail (%s)" % m["failure"][:40]
        return "fail (%s)" % status.replace("killed by signal", "signal")
    return "ok" if m["passed_checks"] else "checks fail"


def main():
    args = sys.argv[1:]
    if not args or args[0].startswith("-"):
        print(__doc__)
        return 2
    build = args[0]
    opts = dict(zip(args[1::2], args[2::2]))
    binary = os.path.join(build, "bin", "vdmesh")
    timeout = float(opts.get("--timeout", "30"))
    runs = opts.get("--runs", "boundary,quality")
    json_dir = opts.get("--json-dir") or tempfile.mkdtemp(prefix="vdmesh-bench-compare-")
    os.makedirs(json_dir, exist_ok=True)
    started = time.time()
    results = []  # (input, facets, report or None, note)
    for rel in inputs(opts.get("--only")):
        path = os.path.join(DATA, rel)
        js = os.path.join(json_dir, rel.replace("/", "__") + ".json")
        if os.path.exists(js):
            os.remove(js)
        t0 = time.time()
        p = subprocess.run([binary, "compare", path, "--json", js, "--timeout", str(timeout), "--runs", runs,
                            "--quiet"], capture_output=True, text=True)
        seconds = time.time() - t0
        report = json.load(open(js)) if os.path.exists(js) else None
        note = ""
        if report is None:
            err = (p.stderr or p.stdout).strip().splitlines()
            msg = err[-1] if err else "exit %d" % p.returncode
            note = "not compared: exit %d: %s" % (p.returncode, msg[:160])
        print("%-55s exit %d, %.1f s %s" % (rel, p.returncode, seconds, note), file=sys.stderr, flush=True)
        results.append((rel, report, note))

    total = time.time() - started
    lines = ["# vdmesh compare over the shared corpus", "",
             "%s; %s; %d inputs in %.1f min (timeout %g s per mesher run)." % (
                 datetime.date.today().isoformat(), machine(), len(results), total / 60, timeout), ""]
    for run_name, title in (("boundary", "Boundary-preserving: vdmesh --no-interior against tetgen -pYA"),
                            ("quality", "Quality: vdmesh (default size) against tetgen -pq1.414aV A, V for a similar count")):
        if run_name not in runs:
            continue
        lines += ["## " + title, "",
                  "| input | facets | vdmesh | tetgen | s vdmesh / tetgen | tets vdmesh / tetgen | "
                  "min dihedral vdmesh / tetgen | added boundary vertices vdmesh / tetgen |",
                  "|---|---|---|---|---|---|---|---|"]
        ok_v = ok_t = n = 0
        ratios, diffs = [], []
        for rel, report, note in results:
            if report is None:
                lines.append("| %s | - | %s | | | | | |" % (rel, note))
                continue
            r = next((x for x in report["runs"] if x["name"] == run_name), None)
            if r is None:
                continue
            n += 1
            v, t = r["vdmesh"], r["tetgen"]
            ok_v += v["meshed"]
            ok_t += t["meshed"]
            if v["meshed"] and t["meshed"] and t["seconds"] > 0:
                ratios.append(v["seconds"] / t["seconds"])
                diffs.append(v["min_dihedral_deg"] - t["min_dihedral_deg"])
            lines.append("| %s | %d | %s | %s | %s / %s | %s / %s | %s / %s | %s / %s |" % (
                rel, report["input_facets"], outcome(v), outcome(t),
                "%.2f" % v["seconds"], "%.2f" % t["seconds"],
                cell(v, "tetrahedra"), cell(t, "tetrahedra"),
                cell(v, "min_dihedral_deg", "%.2f"), cell(t, "min_dihedral_deg", "%.2f"),
                cell(v, "boundary_vertices_added"), cell(t, "boundary_vertices_added")))
        lines.append("| **summary** | %d inputs | %d meshed | %d meshed | median ratio %s | | median difference %s | |" % (
            n, ok_v, ok_t, "%.2f" % statistics.median(ratios) if ratios else "-",
            "%+.2f deg" % statistics.median(diffs) if diffs else "-"))
        lines.append("")
    lines += ["Time: wall clock of each mesher's own process, reading and writing included. \"checks fail\": "
              "meshed, but an independent check of `vdmesh compare` failed (see the JSON in %s)." % json_dir, ""]
    text = "\n".join(lines)
    print(text)
    if "--out" in opts:
        with open(opts["--out"], "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
