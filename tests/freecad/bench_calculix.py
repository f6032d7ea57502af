"""Convergence of the CalculiX cantilever (Mod/VDMesh/vdmeshtest/calculix_case.py) on vdmesh meshes
and on FreeCAD's Gmsh meshes, through FreeCAD's FEM solver machinery. Prints one row per mesh.

    VDMESH_BIN=build/bin/vdmesh BENCH_VDMESH=6,4,3 BENCH_GMSH=3,2,1.5 BENCH_ORDER=2 \
    freecadcmd -c 'exec(open("tests/freecad/bench_calculix.py").read())' -M $PWD/Mod/VDMesh

(freecadcmd takes no options after a script, hence the environment variables; slow: a fine
second-order mesh takes minutes in CalculiX on two cores.)
"""
import os
import sys
import time

import FreeCAD

from vdmeshtest import calculix_case as case
from vdmeshwb import engine, meshobject


def sizes(name):
    return [float(s) for s in os.environ.get(name, "").split(",") if s.strip()]


def row(mesher, size, mesh_seconds, f):
    line = ("| %s | %g | %d | %d | %d | %.6g | %.5g | %.5g | %.0f | %.0f |"
            % (mesher, size, f["nodes_per_tetrahedron"], f["nodes"], f["tetrahedra"], f["max_displacement"],
               f["P_alu"], f["P_steel_over_hole"], mesh_seconds, f["ccx_seconds"]))
    print(line)
    sys.stdout.flush()
    return line


def main():
    order = int(os.environ.get("BENCH_ORDER", "2"))
    doc = FreeCAD.newDocument("BenchCalculix")
    part = case.make_part(doc)
    lines = ["| mesher | size | nodes/tet | nodes | tetrahedra | max displacement (mm) | von Mises P_alu (MPa) "
             "| von Mises P_steel_over_hole (MPa) | mesh s | CalculiX s |", "|---|---|---|---|---|---|---|---|---|---|"]
    print("\n".join(lines))
    for k, h in enumerate(sizes("BENCH_VDMESH")):
        analysis, solver = case.make_analysis(doc, part, "V%d" % k)
        t = time.time()
        obj, info, report, text = meshobject.create_mesh(part, engine.Parameters(size=h, order=order),
                                                         analysis=analysis, name="VDMesh%d" % k)
        lines.append(row("vdmesh", h, time.time() - t, case.run_ccx(analysis, solver, obj)))
    for k, h in enumerate(sizes("BENCH_GMSH")):
        analysis, solver = case.make_analysis(doc, part, "G%d" % k)
        t = time.time()
        obj = case.gmsh_mesh(doc, part, h, order, "%d" % k)
        lines.append(row("Gmsh", h, time.time() - t, case.run_ccx(analysis, solver, obj)))
    print("\n" + "\n".join(lines))


main()
sys.exit(0)
