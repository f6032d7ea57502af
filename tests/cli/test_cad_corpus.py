"""Every shared CAD file through surface recovery (`vdmesh mesh --no-interior`), against the outcome
the README's CAD table records: the files that mesh must still mesh (valid: no inverted
tetrahedron, all facets recovered), the broken ones must still be refused with their reason. Recovery
is where CAD changes break things (a guard on tessellation splits once made gmsh_dlr_f6.brep stop in
recovery, and only the benchmark saw it); without interior vertices and sliver pass the whole corpus
takes under a minute.

occt_MODERN_Exhaust_1.brep stopped in recovery on its first tessellation and meshed on the next,
unsmoothed and not remeshed, until the border pieces were cut where CGAL's mesher put its nodes
(2026-11-26: cut evenly, the two sides of its faces' 0 deg corners had nodes at other distances, and
caps of 179.8 deg between them, where recovery ran away): it must now recover at once with every
face remeshed. gmsh_917_fusee.stp did the same (OpenCASCADE's triangles along a tangent seam) until
its B-spline faces were remeshed (2026-11-25): it must recover at once too. gmsh_ellipses.brep
recovers at once since the inner vertices OpenCASCADE put a hair from its ellipsoids' rims are moved
onto them (2026-11-27; it fell back on its unsmoothed surface before).
gmsh_simple_plane.brep stops in recovery at every angle with the automatic chord heights, which
follow its thin solids down; it must recover on the last tessellation, which starts from one chord
height of size / 500 everywhere (2026-11-26), and whose volume rounds then make finer the solids away
from where recovery ran away: every solid within 1 % of its CAD volume (its nose pieces were 5.4 %
off before those rounds, 2026-11-26)."""
import json
import os

from cli_support import check, data, finish, run, tmpdir

out = tmpdir()

MESH = [
    "cad-assembly/caxif_as1-oc-214.stp", "cad-assembly/gmsh_ellipses.brep", "cad-assembly/gmsh_ring.brep",
    "cad-assembly/gmsh_wing_fuselage.step", "cad-assembly/occt_MODERN_Exhaust_1.brep",
    "cad-part/freecad_TSM_104_01_L_DV_A.stp", "cad-part/gmsh_1385_Laufrad_impeller.stp",
    "cad-part/gmsh_918_pump_carter.stp", "cad-part/gmsh_Block.stp", "cad-part/gmsh_Kurbelwelle_crankshaft.stp",
    "cad-part/gmsh_U_Joint_2.stp", "cad-part/gmsh_Zylkopf_cylinder_head.stp", "cad-part/gmsh_dlr_f6.brep",
    "cad-part/gmsh_part.step", "cad-part/gmsh_t20_component8.step", "cad-part/kicad_CP_Radial_D10.0mm.step",
    "cad-part/kicad_SOIC-8.step", "cad-part/pythonocc_Ventilator.stp",
    "cad-part/pythonocc_face_recognition_sample_part.stp", "cad-part/gmsh_917_fusee.stp",
    "cad-assembly/gmsh_simple_plane.brep",
]
# Tessellated from one chord height everywhere: (retries, size / chord height, largest volume error of a
# solid). simple_plane's first recovery runs away, and the unsmoothed surface is skipped (2026-11-27).
UNIFORM_CHORDS = {"cad-assembly/gmsh_simple_plane.brep": (1, 500, 0.01)}
# Faces the general fuse cuts into pieces, and the largest piece's CAD area.
SPLIT_FACES = {"cad-assembly/occt_MODERN_Exhaust_1.brep": {"Face15": 1098.2}}
FIRST_TRY = {"cad-part/gmsh_917_fusee.stp", "cad-assembly/occt_MODERN_Exhaust_1.brep",
             "cad-assembly/gmsh_ellipses.brep"}
# Inner vertices a hair from a border moved onto it (at least this many). The
# ellipsoids' rows, graded by OpenCASCADE towards their rims (the first 4e-4
# from a rim of 0.05 pieces), made needles; with them the ellipses' first
# recovery stalled, and the unsmoothed surface it fell back on gave 0.04 deg
# (measured 2026-11-27: 117 moved, recovered at once).
BORDER_CAPS = {"cad-assembly/gmsh_ellipses.brep": 100, "cad-part/gmsh_U_Joint_2.stp": 40}
# Every face meshed anew. t20's B-spline faces have their smallest corner at
# a sharp corner of the face, which the new mesh keeps as it was: until
# 2026-11-26 a new mesh had to be rounder, and 10 of its 21 faces were left.
# The Exhaust's remeshed faces were dropped after recovery stopped on them.
ALL_REMESHED = {"cad-part/gmsh_t20_component8.step", "cad-assembly/occt_MODERN_Exhaust_1.brep"}
# What the refusal must say.
REFUSED = {
    "cad-part/occt_bearing.iges": ["none closed"],  # its faces sew into an open shell
    # Its tessellation crosses itself at every angular deflection; the message
    # names the CAD faces that cross, and OpenCASCADE's own check finds the
    # shape faulty on the same faces (so the file is to blame, not the mesher).
    "cad-part/pythonocc_11752.stp": ["crosses itself: ", "Face793 with Face1016 near (",
                                     "finds it faulty: 6 crossings of edges or faces (on Face793,",
                                     "edges whose 3D curve leaves their face's surface"],
}

for rel in MESH:
    path = data(rel)
    if not path:
        continue
    stem = os.path.splitext(os.path.basename(rel))[0]
    report_path = os.path.join(out, stem + ".json")
    # --keep-slivers: recovery is what this test is for, and the sliver pass
    # over the ellipses' 287,000 recovered tetrahedra tripled its time.
    code, _, err = run("mesh", path, "-o", os.path.join(out, stem + ".vtu"), "--no-interior", "--keep-slivers",
                       "--quiet", "--report", report_path)
    rep = json.load(open(report_path)) if code == 0 else None
    check(code == 0 and rep["complete"] and rep["quality"]["inverted"] == 0 and rep["counts"]["tetrahedra"] > 0,
          "%s: surface recovered, %s tetrahedra, none inverted (exit %d%s)"
          % (rel, rep["counts"]["tetrahedra"] if rep else "no", code, (": " + err.strip()[-200:]) if code else ""))
    if rep is not None:
        # One row per face number: the fuse may cut a face into pieces that
        # keep its number (the Exhaust's Face15: five), and the facets carry
        # the number, so the pieces' CAD areas add up. Until 2026-11-25 each
        # piece had its own row against the whole face's mesh area (Face15:
        # 9,989,490 % off).
        areas = rep["cad"]["areas"]
        names = [a["name"] for a in areas]
        cad_total = sum(a["cad"] for a in areas)
        mesh_total = sum(a["mesh"] for a in areas)
        check(len(set(names)) == len(names) and abs(mesh_total - cad_total) <= 0.005 * cad_total,
              "%s: one area row per face (%d rows, %d names), surface area %.6g against the CAD's %.6g"
              % (rel, len(names), len(set(names)), mesh_total, cad_total))
        for name, piece_area in SPLIT_FACES.get(rel, {}).items():
            row = [a for a in areas if a["name"] == name]
            check(len(row) == 1 and row[0]["cad"] > piece_area and abs(row[0]["mesh"] - row[0]["cad"]) <= 0.01 * row[0]["cad"],
                  "%s: %s, cut by the fuse, has its pieces' area (%s)" % (rel, name, row))
    if rel in UNIFORM_CHORDS:
        retries, divisor, volume_error = UNIFORM_CHORDS[rel]
        # The report gives the smallest chord height: the rounds' or the start.
        check(rep is not None and rep["cad"]["recovery_retries"] == retries
              and rep["cad"]["deflection"] * divisor / rep["cad"]["size"] < 1 + 1e-9,
              "%s: recovered on the uniform chords (%s)" % (rel, {k: rep["cad"][k] for k in ("recovery_retries", "deflection", "size")} if rep else "?"))
        # Its first tessellation's recovery runs away (7,394 facets missing,
        # then 18,199 two passes later) and is given up as such, not after
        # the patience's 8 passes (111,972 missing, 132k vertices added).
        check(rep is not None and rep["cad"]["recovery_runaways"] >= 1,
              "%s: a recovery given up as running away (%s)" % (rel, rep["cad"].get("recovery_runaways") if rep else "?"))
        # The wing roots ran away on every earlier tessellation: their solids
        # (the wings, 19 to 22) are left alone, the nose pieces (2 and 4) not.
        held = set(rep["cad"]["held_solids"]) if rep else set()
        check({19, 20, 21, 22} <= held and not held & {2, 4},
              "%s: the rounds leave the wings alone, not the nose (held %s)" % (rel, sorted(held)))
        errors = {v["name"]: abs(v["mesh"] / v["cad"] - 1) for v in rep["cad"]["volumes"]} if rep else {}
        check(rep is not None and rep["cad"]["tessellation_rounds"] > 1 and max(errors.values()) <= volume_error,
              "%s: volume rounds on the uniform chords (%s rounds), every solid within %g %% (worst %s)"
              % (rel, rep["cad"]["tessellation_rounds"] if rep else "?", 100 * volume_error,
                 max(errors.items(), key=lambda kv: kv[1]) if errors else "?"))
    if rel in ALL_REMESHED:
        check(rep is not None and rep["cad"]["remeshed_faces"] == rep["cad"]["faces"],
              "%s: every face meshed anew (%s of %s)" % (rel, rep["cad"]["remeshed_faces"] if rep else "?",
                                                         rep["cad"]["faces"] if rep else "?"))
    if rel in BORDER_CAPS:
        check(rep is not None and rep["cad"]["border_caps_snapped"] >= BORDER_CAPS[rel],
              "%s: %s border caps snapped, at least %d" % (rel, rep["cad"]["border_caps_snapped"] if rep else "?",
                                                          BORDER_CAPS[rel]))
    if rel in FIRST_TRY:
        check(rep is not None and rep["cad"]["recovery_retries"] == 0,
              "%s: recovered on its first tessellation (%s retries)" % (rel, rep["cad"]["recovery_retries"] if rep else "?"))

for rel, reasons in REFUSED.items():
    path = data(rel)
    if not path:
        continue
    target = os.path.join(out, "refused.vtu")
    code, _, err = run("mesh", path, "-o", target, "--no-interior", "--quiet")
    check(code == 3 and all(r in err for r in reasons) and not os.path.exists(target),
          "%s: refused, exit 3 saying %s (exit %d: %s)" % (rel, reasons, code, err.strip()[:1000]))

finish()
