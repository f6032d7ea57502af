"""CAD input (issue 5) from the command line: parts and assemblies made by
Gmsh's OpenCASCADE kernel in the test (so no shared data is needed), checked
against the volumes OpenCASCADE computes and read back by meshio; then real
STEP/BREP files from the shared data; then bad input."""
import os
import shutil
import subprocess

import numpy as np

from cad_support import mesh_as, out, tet_volumes, tets_in_solids
from cli_support import BIN, check, data, finish, read_abaqus_deck, run



def make_brep(name, build):
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add(name)
    build(gmsh.model.occ)
    gmsh.model.occ.synchronize()
    path = os.path.join(out, name + ".brep")
    gmsh.write(path)
    gmsh.finalize()
    return path


def mesh(path, *extra):
    return mesh_as(os.path.splitext(os.path.basename(path))[0], path, *extra)


def check_mesh(path, rep, name):
    """The output read by meshio: positive tetrahedra, region volumes as the
    report says, one region per solid, faces tagged."""
    import meshio
    m = meshio.read(path)
    vol = tet_volumes(m)
    check(len(vol) > 0 and vol.min() > 0, "%s: %d tetrahedra, all positive (meshio)" % (name, len(vol)))
    region = None
    for block, values in zip(m.cells, m.cell_data["region"]):
        if block.type == "tetra":
            region = np.asarray(values)
    solids = rep["cad"]["solids"]
    check(sorted(set(region.tolist())) == list(range(1, solids + 1)),
          "%s: regions %s are the %d solids" % (name, sorted(set(region.tolist())), solids))
    for v in rep["cad"]["volumes"]:
        k = int(v["name"][len("Solid"):])
        mine = vol[region == k].sum()
        err = abs(mine - v["cad"]) / v["cad"]
        check(err < 0.005, "%s: %s volume %.6g vs OpenCASCADE %.6g (%.3f %% < 0.5 %%)" % (name, v["name"], mine, v["cad"], 100 * err))
    return m


def converted_surface(path, name):
    """The surface `vdmesh convert` writes for the CAD file (meshio), or None
    when it fails (a failed check)."""
    import meshio
    surface = os.path.join(out, name + ".vtk")
    code, _, err = run("convert", path, surface)
    check(code == 0, "%s: surface written (exit %d: %s)" % (name, code, err.strip()[:200]))
    return meshio.read(surface) if code == 0 else None


def corner_angles(points, triangles):
    """Each triangle's three corners in degrees, one row per triangle."""
    p = points[triangles]
    out = []
    for k in range(3):
        u = p[:, (k + 1) % 3] - p[:, k]
        v = p[:, (k + 2) % 3] - p[:, k]
        cos = (u * v).sum(axis=1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        out.append(np.degrees(np.arccos(np.clip(cos, -1, 1))))
    return np.stack(out, axis=1)


def folded_edges(points, triangles, faces):
    """Edges between two facets of one face whose normals are opposite."""
    p = points[triangles]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.linalg.norm(n, axis=1)[:, None]
    sides = {}
    for i, t in enumerate(triangles.tolist()):
        for k in range(3):
            sides.setdefault(tuple(sorted((t[k], t[(k + 1) % 3]))), []).append(i)
    return sum(1 for f in sides.values()
               if len(f) == 2 and faces[f[0]] == faces[f[1]] and np.dot(n[f[0]], n[f[1]]) < 0)


def meshed_angles(path, name, *extra):
    """Meshes path (--quiet and `extra`), checks the mesh as check_mesh does,
    and gives the report and each tetrahedron's smallest dihedral angle; or
    (None, None) when it did not mesh (a failed check)."""
    from tet_angles import dihedral_angles
    code, rep, target, err = mesh(path, "--quiet", *extra)
    check(code == 0, "%s meshed (exit %d: %s)" % (name, code, err.strip()[:200]))
    if code != 0:
        return None, None
    m = check_mesh(target, rep, name)
    return rep, dihedral_angles(m.points, m.cells_dict["tetra"]).min(axis=0)


# A box with a cylindrical hole: one solid, curved faces.
boxhole = make_brep("boxhole", lambda occ: occ.cut([(3, occ.addBox(-5, -5, 0, 10, 10, 4))],
                                                   [(3, occ.addCylinder(0, 0, -1, 0, 0, 6, 2))]))
code, rep, target, err = mesh(boxhole, "--size", "1")
check(code == 0, "box with a hole meshes (exit %s: %s)" % (code, err.strip()[-300:]))
if code == 0:
    check(rep["cad"]["solids"] == 1 and rep["cad"]["faces"] == 7, "box with a hole: 1 solid, 7 faces (%d, %d)" % (rep["cad"]["solids"], rep["cad"]["faces"]))
    check(not rep["cad"]["size_chosen"] and rep["cad"]["size"] == 1, "the given size is used and reported (%g)" % rep["cad"]["size"])
    check(rep["quality"]["inverted"] == 0, "box with a hole: no inverted tetrahedra")
    check(rep["slivers"]["angle_deg"] == 10, "CAD input: sliver angle 10 deg by default (%g)" % rep["slivers"]["angle_deg"])
    m = check_mesh(target, rep, "box with a hole")
    faces = set()
    for block, values in zip(m.cells, m.cell_data["face"]):
        if block.type == "triangle":
            faces |= set(np.asarray(values).tolist())
    check(faces == set(range(1, 8)), "box with a hole: boundary triangles carry Face1..Face7 (%s)" % sorted(faces))
    # A sliver angle given by hand wins over the CAD default (it was read,
    # then overwritten by the default, until 2026-11-24).
    code, rep20, _, err = mesh(boxhole, "--size", "1", "--sliver-angle", "20", "--quiet")
    check(code == 0 and rep20["slivers"]["angle_deg"] == 20,
          "CAD input: --sliver-angle 20 is used (exit %s, %s)" % (code, rep20["slivers"]["angle_deg"] if rep20 else err.strip()[-200:]))
    if code == 0:
        check(rep20["slivers"]["before"] > rep["slivers"]["before"],
              "CAD input: more tetrahedra count as slivers at 20 deg than at 10 (%d > %d)" % (rep20["slivers"]["before"], rep["slivers"]["before"]))

# The tessellation written where no tags say the sides (STL, OFF, OBJ): the
# hole's faces are turned in as OpenCASCADE orients them (3,275 of 5,812
# facets), and written as they were, no program could read the file as a
# closed solid (vdmesh: "inconsistent orientation"). Now every facet points
# out of the solid: each edge is run once each way, the enclosed volume is
# the part's (meshio), and vdmesh meshes the file.
import meshio
for ext in ("stl", "off", "obj"):
    surface = os.path.join(out, "boxhole_surface." + ext)
    code, _, err = run("convert", boxhole, surface)
    check(code == 0, "box with a hole: convert to .%s (exit %d: %s)" % (ext, code, err.strip()[-200:]))
    if code != 0:
        continue
    s = meshio.read(surface)
    # meshio gives an STL facet its own three points: weld them.
    points, index = np.unique(s.points, axis=0, return_inverse=True)
    tris = index.reshape(-1)[np.concatenate([c.data for c in s.cells if c.type == "triangle"])]
    directed = {}
    for t in tris:
        for k in range(3):
            e = (int(t[k]), int(t[(k + 1) % 3]))
            directed[e] = directed.get(e, 0) + 1
    paired = all(n == 1 and directed.get((b, a)) == 1 for (a, b), n in directed.items())
    p = points[tris]
    volume = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    cad_volume = 10 * 10 * 4 - np.pi * 2 * 2 * 4
    check(paired and abs(volume / cad_volume - 1) < 0.01,
          "box with a hole as .%s: every edge run once each way (%s), enclosed volume %.4g, the part's %.4g"
          % (ext, paired, volume, cad_volume))
    code, _, err = run("mesh", surface, "-o", os.path.join(out, "boxhole_surface_%s.vtu" % ext), "--quiet")
    check(code == 0, "box with a hole as .%s: vdmesh meshes it (exit %d: %s)" % (ext, code, err.strip()[-200:]))

# Convergence on a curved solid: the volume error shrinks with the size.
# OpenCASCADE's 20-degree angular deflection already gives the circles
# 0.51-long chords, so only sizes under that refine them; a short cylinder
# keeps the finest mesh small (64,000 tetrahedra).
cyl = make_brep("cylinder", lambda occ: occ.addCylinder(0, 0, 0, 0, 0, 10, 3))
disc = make_brep("disc", lambda occ: occ.addCylinder(0, 0, 0, 0, 0, 2, 3))
errors = []
for size in (1.0, 0.5, 0.25):
    code, rep, _, err = mesh(disc, "--size", str(size), "--quiet")
    if code != 0:
        check(False, "short cylinder at size %g meshes (exit %s: %s)" % (size, code, err.strip()[-200:]))
        continue
    v = rep["cad"]["volumes"][0]
    errors.append(abs(v["mesh"] - v["cad"]) / v["cad"])
check(len(errors) == 3 and errors[0] > errors[1] > errors[2],
      "short cylinder volume error shrinks with the size: %s" % ", ".join("%.4f %%" % (100 * e) for e in errors))
check(len(errors) == 3 and errors[2] < 0.001, "short cylinder at size 0.25: volume error under 0.1 %")

# A thin rod sunk into a plate (radius 1, its axis 0.5 under the top), at
# the default size (5.7, chord height 0.285): the chord height alone let the
# 120-degree strip above the plate be crossed by single chords, and its
# face kept 95.6 % of its area (gmsh_dlr_f6.brep's Face74, a radius-4
# strip: 86.8 %). Chords across a cylinder or torus now span 60 degrees at
# most.
rod = make_brep("rod_on_plate", lambda occ: occ.fuse([(3, occ.addBox(0, 0, 0, 100, 100, 20))],
                                                     [(3, occ.addCylinder(10, 50, 19.5, 80, 0, 0, 1))]))
code, rep, _, err = mesh(rod, "--quiet")
check(code == 0, "rod on a plate meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    half_rod = np.pi * 1 * 80 * 2 / 3  # the 120 degrees above the plate
    face = min(rep["cad"]["areas"], key=lambda a: abs(a["cad"] - half_rod))
    check(abs(face["cad"] - half_rod) < 1e-6 * half_rod and abs(face["mesh"] / face["cad"] - 1) < 0.02,
          "rod on a plate: the rod's %s has %.3f of its CAD area %.4g (within 2 %%)"
          % (face["name"], face["mesh"] / face["cad"], face["cad"]))

# A boss tangent to a wall: the solid touches itself along the line where
# the cylinder meets the wall's plane. Every recovery with split vertices on
# the CAD geometry ran away there (exit 4; a FreeCAD tester's part,
# 2026-11-30); the chain's last try puts them on the chords, and it meshes.
def boss_on_wall(occ):
    occ.fuse([(3, occ.addBox(0, 0, 0, 60, 60, 5))],
             [(3, occ.addBox(0, 40, 0, 60, 5, 25)), (3, occ.addCylinder(30, 34, 0, 0, 0, 20, 6))])


boss = make_brep("boss_tangent_to_a_wall", boss_on_wall)
code, rep, target, err = mesh(boss, "--quiet")
check(code == 0, "boss tangent to a wall meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    check(rep["cad"]["planar_splits_fallback"], "boss tangent to a wall: meshed with split vertices on the chords")
    check_mesh(target, rep, "boss tangent to a wall")

# A thin part at the size chosen from its diagonal: a disk of radius 25,
# 0.3 thick, got edges 9.4 times its thickness and a smallest dihedral
# angle of 0.010 deg (Gmsh's default 2.95 deg). Its faces now get 4 times
# its mean thickness 2V/A, and its flat faces' vertices slide in their
# planes (the sliver pass); a given --size is kept as it is.
thin = make_brep("thin_disk", lambda occ: occ.addCylinder(0, 0, 0, 0, 0, 0.3, 25))
thickness = 2 * np.pi * 25 ** 2 * 0.3 / (2 * np.pi * 25 ** 2 + 2 * np.pi * 25 * 0.3)  # 2V/A
rep, angles = meshed_angles(thin, "thin disk")
if rep is not None:
    c = rep["cad"]
    check(c["size_chosen"] and c["thin_faces"] == 3 and abs(c["thin_size"] - 4 * thickness) < 1e-6 * thickness,
          "thin disk: %d faces at %.4g (4 x 2V/A = %.4g; size %.4g)" % (c["thin_faces"], c["thin_size"], 4 * thickness, c["size"]))
    check(angles.min() > 10 and (angles < 10).sum() == 0,
          "thin disk: smallest dihedral angle %.2f deg (meshio), %d tetrahedra under 10 deg" % (angles.min(), (angles < 10).sum()))
code, rep, target, err = mesh(thin, "--size", "2.8", "--keep-slivers", "--quiet")
_, table, _ = run("mesh", thin, "-o", target, "--size", "2.8", "--keep-slivers")
check(code == 0 and rep["cad"]["thin_faces"] == 0 and rep["cad"]["size"] == 2.8
      and abs(rep["cad"]["thinnest_solid"] - thickness) < 1e-6 * thickness and "tetrahedra across it are flat" in table,
      "thin disk at --size 2.8: the size is kept, the report says the solid is %.4g thick (exit %s, %s faces bounded)"
      % (rep["cad"]["thinnest_solid"] if rep else 0, code, rep and rep["cad"]["thin_faces"]))

# A line on a box's top face, fragmented in (Gmsh's OpenCASCADE kernel):
# the face keeps it as an INTERNAL edge, which bounds nothing. The closed
# solid was refused as "not closed (1 edges bound only one face)".
def box_with_a_line_on_top(occ):
    line = occ.addLine(occ.addPoint(3, 5, 4), occ.addPoint(7, 5, 4))
    occ.fragment([(3, occ.addBox(0, 0, 0, 10, 10, 4))], [(1, line)])


inner = make_brep("box_with_an_inner_edge", box_with_a_line_on_top)
code, rep, target, err = mesh(inner, "--quiet")
check(code == 0, "box with an INTERNAL edge in its top face meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    check(rep["cad"]["faces"] == 6, "box with an inner edge: 6 faces (%s)" % rep["cad"]["faces"])
    check_mesh(target, rep, "box with an inner edge")

# Surface nodes lie on the CAD surface, not where the random shift took
# them: its tangent plane is the facets', and it left a radius-3
# cylinder's nodes up to 1.1e-6 off, past the tolerance FreeCAD's
# constraints find their nodes with (a pressure on a hole loaded 2.2 % of
# its area, a FreeCAD tester, 2026-11-30). They go back after the volume,
# but those the sliver pass moved or that would turn a tetrahedron over.
code, rep, target, err = mesh(cyl, "--quiet")
check(code == 0, "cylinder at its default size meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    import meshio
    m = meshio.read(target)
    on_surface = np.unique(np.concatenate([c.data.ravel() for c in m.cells if c.type == "triangle"]))
    p = m.points[on_surface]
    off = np.minimum(np.abs(np.hypot(p[:, 0], p[:, 1]) - 3), np.minimum(np.abs(p[:, 2]), np.abs(p[:, 2] - 10)))
    shifted = rep["shift"]["in_plane"] + rep["shift"]["on_edge"]
    check(shifted > 1000 and rep["shift"]["restored"] >= 0.99 * shifted and
          (off > 1e-12).sum() <= shifted - rep["shift"]["restored"],
          "cylinder: %d of %d surface nodes more than 1e-12 off the CAD surface (worst %.3g); %d of %d shifted put back"
          % ((off > 1e-12).sum(), len(p), off.max(), rep["shift"]["restored"], shifted))

# --angular-deflection: at size 2 the disc's circles are OpenCASCADE's
# chords alone; 10 degrees instead of 20 halves them, and the volume lost
# to them drops about fourfold (an inscribed polygon loses about t^2/6).
# One tessellation each (--volume-tolerance 0): the tolerance would make
# both finer.
by_angle = {}
for angle in ("20", "10"):
    # As tessellated: a remeshed cylinder's inside follows the chord height only.
    code, rep, _, err = mesh(disc, "--size", "2", "--angular-deflection", angle, "--volume-tolerance", "0", "--quiet",
                             "--no-face-remesh")
    check(code == 0, "disc at --angular-deflection %s meshes (exit %s: %s)" % (angle, code, err.strip()[-200:]))
    if code == 0:
        v = rep["cad"]["volumes"][0]
        by_angle[angle] = (abs(v["mesh"] - v["cad"]) / v["cad"], rep["cad"]["surface_facets"])
if len(by_angle) == 2:
    (e20, f20), (e10, f10) = by_angle["20"], by_angle["10"]
    check(e10 < e20 / 3 and f10 > f20,
          "disc: --angular-deflection 10 loses %.4f %% of the volume with %d facets, 20 loses %.4f %% with %d"
          % (100 * e10, f10, 100 * e20, f20))
# --volume-tolerance (default 0.4 %): at 0.2 % the same disc is tessellated
# again, finer, until its volume is within the tolerance.
code, rep, _, err = mesh(disc, "--size", "2", "--volume-tolerance", "0.2", "--quiet")
check(code == 0, "disc at the default volume tolerance meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0 and "20" in by_angle:
    c, v = rep["cad"], rep["cad"]["volumes"][0]
    final = abs(v["mesh"] - v["cad"]) / v["cad"]
    check(by_angle["20"][0] > 0.002 and c["tessellation_rounds"] > 1 and c["tessellation_volume_error"] <= 0.002
          and final < 0.0025 and c["angular_deflection_deg"] < 20,
          "disc: one tessellation loses %.3f %%; %d tessellations (last at %.1f deg) lose %.3f %%, the mesh %.3f %%"
          % (100 * by_angle["20"][0], c["tessellation_rounds"], c["angular_deflection_deg"],
             100 * c["tessellation_volume_error"], 100 * final))
# A cone far under the size (radius 1, height 1, at sizes 5 and 60): the
# remesher bounds edges on a cone by the chord height at their distance
# from the axis, down to a tenth of the bound at the face's widest circle.
# Until 2026-11-28 the floor was a tenth of the size, above the whole cone:
# its facets by the apex kept the length the grading from the base circle
# gave them, the volume rounds shrank the chord height 12 times for nothing,
# and the mesh came out 2.7 % (size 5) to 2.9 % (size 60) short.
cone = make_brep("small_cone", lambda occ: occ.addCone(0, 0, 0, 0, 0, 1, 1, 0))
for size in ("5", "60"):
    code, rep, target, err = mesh(cone, "--size", size, "--quiet")
    check(code == 0, "cone of radius 1 at size %s meshes (exit %s: %s)" % (size, code, err.strip()[-200:]))
    if code == 0:
        check_mesh(target, rep, "cone of radius 1 at size %s" % size)

# A pointy cone (radius 10, height 20, semi-angle 26.6 deg) at its default
# size: the new mesh's three triangles round the apex, 103 deg apart on the
# face, were taken for a fold, so the cone kept its refined tessellation
# (needles to a seam split towards the apex) and its smallest dihedral
# angle was 0.81 deg (Gmsh 12.5 deg; a FreeCAD tester's cone, 2026-11-30).
tip = make_brep("pointy_cone", lambda occ: occ.addCone(0, 0, 0, 0, 0, 20, 10, 0))
code, rep, target, err = mesh(tip, "--quiet")
check(code == 0, "pointy cone meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    check(rep["cad"]["remeshed_faces"] == 2 and rep["quality"]["min_dihedral_deg"] > 10,
          "pointy cone: %d of 2 faces remeshed, smallest dihedral angle %.2f deg (over 10)"
          % (rep["cad"]["remeshed_faces"], rep["quality"]["min_dihedral_deg"]))
    check_mesh(target, rep, "pointy cone")

code, _, _, err = mesh(disc, "--volume-tolerance", "-1")
check(code == 2 and "--volume-tolerance" in err, "--volume-tolerance -1 is a usage error (exit %s)" % code)
# A chord height far under the part: 1e-6 on a 100 mm part filled 21.9 of
# 23.5 GB in OpenCASCADE's mesher before a cancel was heard.
code, _, _, err = mesh(boxhole, "--deflection", "1e-6", "--quiet")
check(code == 2 and "is under 1e-07 of the part's diagonal" in err,
      "--deflection 1e-6 on the box with a hole (diagonal 14.7) is a usage error (exit %s: %s)" % (code, err.strip()[-200:]))
code, _, _, err = mesh(disc, "--angular-deflection", "0")
check(code == 2 and "--angular-deflection" in err, "--angular-deflection 0 is a usage error (exit %s)" % code)

# Second order on CAD: the mid-edge nodes of the surface lie on the cylinder
# (radius 3 from the axis, or on the end planes), and the volume of the
# curved elements is far closer to OpenCASCADE's than the straight mesh's.
code, rep, target, err = mesh(cyl, "--size", "2", "--order", "2", "--quiet")
check(code == 0, "cylinder --order 2 meshes (exit %s: %s)" % (code, err.strip()[-200:]))
if code == 0:
    import meshio
    m = meshio.read(target)
    tets = m.cells_dict.get("tetra10")
    tris = m.cells_dict.get("triangle6")
    check(tets is not None and tris is not None and len(tets) > 0,
          "cylinder --order 2: tetra10 and triangle6 cells (meshio: %s)" % sorted(m.cells_dict))
    if tets is not None and tris is not None:
        mids = m.points[np.unique(tris[:, 3:])]
        r = np.hypot(mids[:, 0], mids[:, 1])
        on_side = np.abs(r - 3) < 1e-6
        on_ends = (np.abs(mids[:, 2]) < 1e-9) | (np.abs(mids[:, 2] - 10) < 1e-9)
        # A node goes back onto its chord only where the curved element
        # would fold (the report counts them; a chord on an end plane is on
        # the CAD anyway); all others are on the CAD. At size 2 the side's
        # facets are 0.51 x 2 (OpenCASCADE's 20-degree circles), and about
        # 5 % of the nodes are kept straight.
        off = int((~(on_side | on_ends)).sum())
        straight = rep["second_order"]["kept_straight"]
        check(off <= straight and straight <= 0.08 * len(mids),
              "cylinder --order 2: surface mid-edge nodes on the cylinder or an end plane except the %d kept "
              "straight (at most 8 %% of %d; %d on the side, %d on the ends, %d off)"
              % (straight, len(mids), on_side.sum(), on_ends.sum(), off))
        # Quadratic volume by the degree-3 rule, in the VTK/Abaqus edge order.
        edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
        x = m.points[tets]

        def jac(l):
            d = []
            for i in range(4):
                g = (4 * l[i] - 1) * x[:, i]
                for e, (a, b) in enumerate(edges):
                    if a == i:
                        g = g + 4 * l[b] * x[:, 4 + e]
                    if b == i:
                        g = g + 4 * l[a] * x[:, 4 + e]
                d.append(g)
            return np.einsum("ij,ij->i", np.cross(d[1] - d[0], d[2] - d[0]), d[3] - d[0])

        quad = [(-0.8, (0.25,) * 4)] + [(0.45, tuple(0.5 if j == i else 1 / 6 for j in range(4))) for i in range(4)]
        dets = [jac(l) for _, l in quad]
        volume = sum(w * d for (w, _), d in zip(quad, dets)).sum() / 6
        cad = rep["cad"]["volumes"][0]["cad"]
        err2 = abs(volume - cad) / cad
        check(abs(volume - rep["cad"]["volumes"][0]["mesh"]) < 1e-9 * cad,
              "cylinder --order 2: the report's mesh volume is the curved one (%.9g, meshio %.9g)"
              % (rep["cad"]["volumes"][0]["mesh"], volume))
        check(min(d.min() for d in dets) > 0, "cylinder --order 2: det J positive at the quadrature points")
        check(len(errors) == 3 and err2 < errors[0] / 10,
              "cylinder at size 2: volume error %.5f %% with --order 2, %.4f %% straight" % (100 * err2, 100 * errors[0]))
        check(rep["second_order"]["on_geometry"] > 0 and rep["second_order"]["min_scaled_jacobian"] >= 0.1,
              "cylinder --order 2: report %s" % rep["second_order"])

# OpenCASCADE is the plugin's (lib/vdmesh/libvdmesh_cad.so), not the
# program's: surface input does not load it (21 MiB and 30 ms a run). A
# copy of the program with no plugin beside it still meshes surfaces and
# refuses CAD input with exit 1 and a message naming the missing file.
needed = subprocess.run(["readelf", "-d", BIN], capture_output=True, text=True).stdout
check("libTKernel" not in needed and "Shared library" in needed,
      "the program does not link OpenCASCADE: " + ", ".join(l.split()[-1] for l in needed.splitlines() if "NEEDED" in l))
lonely = os.path.join(out, "alone", "bin")
os.makedirs(lonely)
shutil.copy(BIN, lonely)
alone = os.path.join(lonely, os.path.basename(BIN))
p = subprocess.run([alone, "mesh", boxhole, "-o", os.path.join(out, "alone.vtu")], capture_output=True, text=True)
check(p.returncode == 1 and "libvdmesh_cad.so" in p.stderr and not os.path.exists(os.path.join(out, "alone.vtu")),
      "no plugin: CAD input refused, exit 1, the file named (%d: %s)" % (p.returncode, p.stderr.strip()[:300]))
# A plugin of another build beside the program is refused before its entry
# points are called: an older ABI number, or the same number built against
# other core headers (a stale plugin crashed once Mesh had gained a field).
fake_dir = os.path.join(out, "alone", "lib", "vdmesh")
os.makedirs(fake_dir)
for abi, fingerprint, says in ((3, "", "interface 3"), (4, "0" * 64, "other core headers")):
    src = os.path.join(out, "fake_plugin.c")
    with open(src, "w") as f:
        f.write("struct Entry { int abi; const char* fingerprint; void* mesh; void* tessellate; const char* occ; };\n"
                "static const struct Entry entry = {%d, \"%s\", 0, 0, \"\"};\n"
                "const struct Entry* vdmesh_cad_entry_points(void) { return &entry; }\n" % (abi, fingerprint))
    so = os.path.join(fake_dir, "libvdmesh_cad.so")
    subprocess.run(["gcc", "-shared", "-fPIC", "-o", so, src], check=True)
    p = subprocess.run([alone, "mesh", boxhole, "-o", os.path.join(out, "alone.vtu")], capture_output=True, text=True)
    check(p.returncode == 1 and "another build" in p.stderr and says in p.stderr
          and not os.path.exists(os.path.join(out, "alone.vtu")),
          "plugin of another build (ABI %d): refused, exit 1 (%d: %s)" % (abi, p.returncode, p.stderr.strip()[:300]))
shutil.rmtree(fake_dir)
tet = os.path.join(out, "tet.off")
with open(tet, "w") as f:
    f.write("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
p = subprocess.run([alone, "mesh", tet, "-o", os.path.join(out, "alone_tet.vtu"), "--quiet"], capture_output=True, text=True)
check(p.returncode == 0, "no plugin: surface input meshes (%d: %s)" % (p.returncode, p.stderr.strip()[:300]))

# The paper's planar mid-points stay available.
code, rep, _, err = mesh(boxhole, "--planar-splits", "--quiet")
check(code == 0, "--planar-splits meshes the box with a hole (exit %s)" % code)

# Two boxes that touch, as separate solids: fused into one interface.
two = make_brep("twoboxes", lambda occ: (occ.addBox(0, 0, 0, 1, 1, 1), occ.addBox(1, 0, 0, 1, 1, 1)))
code, rep, target, err = mesh(two, "--size", "0.25")
check(code == 0, "two touching boxes mesh (exit %s: %s)" % (code, err.strip()[-300:]))
if code == 0:
    check(rep["cad"]["solids"] == 2 and rep["cad"]["interface_faces"] == 1,
          "two boxes: 2 solids, 1 interface face (%d, %d)" % (rep["cad"]["solids"], rep["cad"]["interface_faces"]))
    m = check_mesh(target, rep, "two boxes")
    # The interface: triangles with a region on both sides, one face id.
    for block, face, front, back in zip(m.cells, m.cell_data["face"], m.cell_data["front"], m.cell_data["back"]):
        if block.type != "triangle":
            continue
        face, front, back = map(np.asarray, (face, front, back))
        inner = (front > 0) & (back > 0)
        pairs = {tuple(sorted(x)) for x in zip(front[inner].tolist(), back[inner].tolist())}
        check(len(set(face[inner].tolist())) == 1 and pairs == {(1, 2)},
              "two boxes: the interface is one face between regions 1 and 2 (faces %s, sides %s)" % (set(face[inner].tolist()), pairs))
    check(rep["cad"]["fuse"] == "glued" and rep["cad"]["overlaps"] == [],
          "two touching boxes: glued, no overlap (fuse %r, overlaps %s)" % (rep["cad"]["fuse"], rep["cad"]["overlaps"]))

# A block on a bigger one, given as a plain compound: the fuse makes the
# contact one interface that lies on the big block's top and the small
# block's bottom, and its facets belong to both faces' groups. Until
# 2026-11-30 they were the top's only: with the block overhanging, the
# bottom's group had 50 of its 100 mm2; resting fully on the big block, the
# bottom had no group at all. Read back from the Abaqus deck, every group
# of facets in the plane z = 10 (the top, 400 - 100 + 100, and the bottom),
# by its *SURFACE's element sides.
def deck_surface_areas(path):
    """{*SURFACE name: (area, set of facet planes' z when flat in z, else None)} of a C3D4 deck."""
    points, elsets, _, surfaces = read_abaqus_deck(path)
    nodes = {k: np.array(p) for k, p in points.items()}
    tets = {e[0]: list(e[1:5]) for es in elsets.values() for e in es}
    sides = {1: (0, 1, 2), 2: (0, 3, 1), 3: (1, 3, 2), 4: (2, 3, 0)}  # Abaqus C3D4 faces S1..S4
    areas = {}
    for name, entries in surfaces.items():
        area, zs = 0.0, set()
        for e, k in entries:
            p = [nodes[tets[e][i]] for i in sides[k]]
            area += 0.5 * np.linalg.norm(np.cross(p[1] - p[0], p[2] - p[0]))
            zs.add(round(p[0][2], 9) if abs(p[0][2] - p[1][2]) + abs(p[0][2] - p[2][2]) < 1e-9 else None)
        areas[name] = (area, zs)
    return areas


for name, x0, bottom_on_top in (("overhang", 15, 50.0), ("resting", 5, 100.0)):
    stack = make_brep("stack_" + name, lambda occ: (occ.addBox(0, 0, 0, 20, 20, 10), occ.addBox(x0, 5, 10, 10, 10, 5)))
    deck = os.path.join(out, "stack_%s.inp" % name)
    code, _, err = run("mesh", stack, "-o", deck, "--size", "2.5", "--quiet")
    check(code == 0, "%s block on a block: meshes (exit %s: %s)" % (name, code, err.strip()[-300:]))
    if code == 0:
        flat = sorted(round(a, 6) for a, zs in deck_surface_areas(deck).values() if zs == {10.0})
        check(flat == [100.0, 400.0],
              "%s block on a block: the groups in z = 10 are the top (400) and the block's bottom (100), "
              "%.0f of it on the top (%s)" % (name, bottom_on_top, flat))
        # Each face's *SURFACE names its own solid's element sides: the
        # bottom (Solid2's face) named Solid1's elements on the interface,
        # whose pressure or contact then acted on the wrong solid (an FE
        # tester, 2026-11-30).
        _, elsets, _, surfaces = read_abaqus_deck(deck)
        solid_of = {e[0]: set_name for set_name, es in elsets.items() for e in es}
        areas = deck_surface_areas(deck)
        owners = {round(areas[s_name][0]): sorted({solid_of[e] for e, _ in entries})
                  for s_name, entries in surfaces.items() if areas[s_name][1] == {10.0}}
        check(owners == {400: ["Solid1"], 100: ["Solid2"]},
              "%s block on a block: the top's sides are Solid1's elements, the bottom's Solid2's (%s)" % (name, owners))

# Second order on an edge where three faces meet: a cylinder standing on a
# box, partly overhanging it, has its base circle between its side, the
# box's top and their interface over the box. Mid-edge nodes there stayed on
# the chord (r = 3.9924 for 4) until 2026-11-30; elsewhere on the circle
# (two faces) they were on it.
import meshio  # noqa: E402
post = make_brep("post_on_box", lambda occ: (occ.addBox(0, 0, 0, 20, 20, 10), occ.addCylinder(18, 10, 10, 0, 0, 5, 4)))
code, rep, target, err = mesh(post, "--size", "1.5", "--order", "2", "--quiet")
check(code == 0, "cylinder on a box, --order 2: meshes (exit %s: %s)" % (code, err.strip()[-300:]))
if code == 0:
    m6 = meshio.read(target)
    tri6 = m6.cells_dict["triangle6"]
    r = np.hypot(m6.points[:, 0] - 18, m6.points[:, 1] - 10)
    on_circle = (np.abs(r - 4) < 1e-9) & (np.abs(m6.points[:, 2] - 10) < 1e-9)
    mids = {int(t[3 + k]) for t in tri6 for k in range(3) if on_circle[t[k]] and on_circle[t[(k + 1) % 3]]}
    off = [abs(r[v] - 4) for v in mids if abs(r[v] - 4) > 1e-6]
    inside = sum(1 for v in mids if m6.points[v, 0] < 20)
    check(len(mids) > 20 and inside > 5 and not off,
          "cylinder on a box, --order 2: %d mid-edge nodes of the base circle (%d over the box), %d off it (worst %.2g)"
          % (len(mids), inside, len(off), max(off) if off else 0))

# Solids turned inside out (FreeCAD's Shape.reversed(): the root's
# orientation in the BREP text is -): their faces point in, and meshing
# stopped at "region tags contradict the surface: facet 0 says region 1 on
# its back side". Now turned back: the box with a hole alone, and the two
# boxes' compound (each box reversed within it).
def reversed_brep(path, name):
    lines = open(path).read().rstrip("\n").split("\n")
    root = lines[-1].split()
    lines[-1] = " ".join(["-" + root[0][1:] if root[0].startswith("+") else "+" + root[0][1:]] + root[1:])
    target = os.path.join(out, name + ".brep")
    open(target, "w").write("\n".join(lines) + "\n")
    return target


for source, name, solids, volume in ((boxhole, "boxhole_reversed", 1, 400 - np.pi * 16), (two, "twoboxes_reversed", 2, 2.0)):
    code, rep, target, err = mesh(reversed_brep(source, name), "--size", "1", "--quiet")
    check(code == 0, "%s meshes (exit %s: %s)" % (name, code, err.strip()[-200:]))
    if code == 0:
        vol, region = tets_in_solids(target, solids, name)
        check(abs(vol.sum() - volume) < 0.01 * volume, "%s: volume %.4g, the part's %.4g" % (name, vol.sum(), volume))

# Solids that cross: the glued fuse leaves their faces whole, the glued
# surface crosses itself, and the solids are fused again in full. The box
# B pokes out of the unit box A: the common piece keeps A's number (the
# first solid wins the overlap), so region 1 is all of A (volume 1) and
# region 2 what B has outside it (0.125).
crossing = make_brep("crossing_boxes", lambda occ: (occ.addBox(0, 0, 0, 1, 1, 1), occ.addBox(0.5, 0.25, 0.25, 1, 0.5, 0.5)))
# At the default size: the fallback's size comes from the part as read,
# as --full-fuse's does (not from the glued model's triangulations).
code, rep, target, err = mesh(crossing)
check(code == 0, "two crossing boxes mesh (exit %s: %s)" % (code, err.strip()[-300:]))
if code == 0:
    check(rep["cad"]["fuse"] == "in full" and "glued surface refused" in rep["seconds"],
          "crossing boxes: the glued surface refused, fused in full (fuse %r, phases %s)"
          % (rep["cad"]["fuse"], list(rep["seconds"])[:3]))
    ov = rep["cad"]["overlaps"]
    check(rep["cad"]["solids"] == 2 and len(ov) == 1 and ov[0]["solids"] == [1, 2] and abs(ov[0]["volume"] - 0.125) < 1e-9,
          "crossing boxes: 2 solids, their overlap of 0.125 reported (solids %s, overlaps %s)" % (rep["cad"]["solids"], ov))
    check(rep["cad"]["interface_faces"] == 1,
          "crossing boxes: 1 interface face between Solid1 and Solid2, none between Solid1's pieces (%d)"
          % rep["cad"]["interface_faces"])
    wanted = {"Solid1": 1.0, "Solid2": 0.125}
    got = {v["name"]: v["cad"] for v in rep["cad"]["volumes"]}
    check(set(got) == set(wanted) and all(abs(got[k] - wanted[k]) < 1e-9 for k in wanted),
          "crossing boxes: the report's CAD volumes per solid number are A's and B's outside A (%s)" % got)
    import meshio
    m = meshio.read(target)
    vol = tet_volumes(m)
    region = [np.asarray(v) for b, v in zip(m.cells, m.cell_data["region"]) if b.type == "tetra"][0]
    by_region = {int(k): vol[region == k].sum() for k in set(region.tolist())}
    check(vol.min() > 0 and set(by_region) == {1, 2} and abs(by_region[1] - 1.0) < 1e-9
          and abs(by_region[2] - 0.125) < 1e-9,
          "crossing boxes: regions 1 and 2 of volumes 1 and 0.125 (meshio: %s)" % by_region)
    code2, rep2, target2, err2 = mesh_as("crossing_boxes_full", crossing, "--full-fuse")
    check(code2 == 0 and rep2["cad"]["fuse"] == "in full" and "glued surface refused" not in rep2["seconds"]
          and open(target, "rb").read() == open(target2, "rb").read(),
          "crossing boxes: --full-fuse fuses in full at once, into the same mesh (exit %s)" % code2)

# Convergence on an assembly with a curved interface (the issue: each
# region's volume within 0.5 % at the default size, tighter as the size
# shrinks): a pin of radius 3 in a tube of radii 3 and 4, separate solids
# fused into one cylindrical interface. Sizes under the circles' 0.51-long
# chords (OpenCASCADE's 20 deg) refine them. Measured 2026-11-25: pin
# 0.1848 / 0.1808 / 0.0454 %, tube 0.0557 / 0.0147 / 0.0049 % at sizes 1,
# 0.5, 0.25; 0.1684 and 0.0068 % at the default (0.454).
pin_tube = make_brep("pin_tube", lambda occ: (occ.addCylinder(0, 0, 0, 0, 0, 1, 3),
                                              occ.cut([(3, occ.addCylinder(0, 0, 0, 0, 0, 1, 4))],
                                                      [(3, occ.addCylinder(0, 0, 0, 0, 0, 1, 3))])))
by_size = {}
for size in (None, 1.0, 0.5, 0.25):
    code, rep, target, err = mesh(pin_tube, "--quiet", *(("--size", str(size)) if size else ()))
    check(code == 0, "pin in a tube at size %s meshes (exit %s: %s)" % (size or "default", code, err.strip()[-200:]))
    if code != 0:
        continue
    check(rep["cad"]["solids"] == 2 and rep["cad"]["interface_faces"] == 1,
          "pin in a tube: 2 solids, 1 interface face (%d, %d)" % (rep["cad"]["solids"], rep["cad"]["interface_faces"]))
    if size == 0.25:
        check_mesh(target, rep, "pin in a tube at size 0.25")
    by_size[size] = [abs(v["mesh"] - v["cad"]) / v["cad"] for v in rep["cad"]["volumes"]]
if len(by_size) == 4:
    shown = "; ".join("%s: %s" % (k or "default", ", ".join("%.4f %%" % (100 * e) for e in v)) for k, v in by_size.items())
    check(max(by_size[None]) < 0.005, "pin in a tube: each region within 0.5 %% at the default size (%s)" % shown)
    check(all(by_size[1.0][r] > by_size[0.5][r] > by_size[0.25][r] for r in range(2)),
          "pin in a tube: each region's volume error shrinks with the size (%s)" % shown)
    check(max(by_size[0.25]) < 0.001, "pin in a tube: each region within 0.1 %% at size 0.25 (%s)" % shown)

# A cylinder standing on a block, tangent to the block's edge (as the pins of
# caxif_as1-oc-214.stp): the fused top face has a corner of 0 deg where the
# circle meets the edge. The face remesher does not refine triangles whose
# smallest corner is that corner; refined, CGAL's mesher split the circle and
# the edge in shells towards it (chords of 0.007 against 0.06 on the other
# side, caps of 179 deg between them) and the smallest dihedral angle was
# 0.47 deg (26 tetrahedra under 5 deg). Measured 2026-11-26: 2.0 to 2.13 deg
# over seeds 1 to 6, 6 under 5 deg. Since the border pieces are cut where
# CGAL's mesher put its nodes (both sides of the corner at the same
# distances: needles of 1.2 deg at the corner instead of caps), 1.53 to
# 1.54 deg over seeds 1 to 3, 3 under 5 deg.
tangent = make_brep("tangent_cylinder", lambda occ: (occ.addBox(0, 0, 0, 10, 10, 3),
                                                     occ.addCylinder(7, 5, 3, 0, 0, 2, 3)))
rep, lowest = meshed_angles(tangent, "cylinder tangent to the block's edge")
if rep is not None:
    check(lowest.min() > 1.5 and (lowest < 5).sum() < 15,
          "cylinder tangent to the block's edge: smallest dihedral angle %.2f deg > 1.5, %d tetrahedra under 5 deg < 15"
          % (lowest.min(), (lowest < 5).sum()))

# Chord height per face: a thin slab (2V/A = 0.098, chord 0.00196) beside a
# big sphere (2V/A = 6.7, chord 0.13). The sphere is tessellated at its own
# chord height (made finer by the volume tolerance), not the slab's; with
# about the slab's everywhere (--deflection 0.002) it has over five times
# the facets. Both solids keep their volume.
apart = make_brep("slab_sphere", lambda occ: (occ.addBox(0, 0, 0, 10, 10, 0.1), occ.addSphere(25, 5, 0, 10)))


def sphere_facets(target):
    import meshio
    m = meshio.read(target)
    tris = m.cells_dict["triangle"]
    r = np.linalg.norm(m.points[tris].mean(axis=1) - [25, 5, 0], axis=1)
    return int((np.abs(r - 10) < 1).sum())


code, rep, target, err = mesh(apart, "--size", "2", "--quiet")
check(code == 0, "slab and sphere mesh (exit %s: %s)" % (code, err.strip()[-300:]))
if code == 0:
    check_mesh(target, rep, "slab and sphere")
    own = sphere_facets(target)
    code2, _, target2, err2 = mesh(apart, "--size", "2", "--deflection", "0.002", "--quiet")
    check(code2 == 0, "slab and sphere at --deflection 0.002 mesh (exit %s: %s)" % (code2, err2.strip()[-300:]))
    shared = sphere_facets(target2) if code2 == 0 else 0
    slab = 2 * 10.0 / (2 * 100 + 4 * 1) / 50
    check(abs(rep["cad"]["deflection"] - slab) < 1e-9 and own * 5 < shared,
          "slab and sphere: finest chord height %g; the sphere has %d facets at its own, %d at the slab's"
          % (rep["cad"]["deflection"], own, shared))

# Real files from the shared data.
for rel, solids, interfaces in (("cad-assembly/gmsh_wing_fuselage.step", 2, 1),
                                # its pins lost 0.85 % before recovery flips were bounded
                                # by the chord height
                                ("cad-assembly/caxif_as1-oc-214.stp", 18, 88),
                                ("cad-assembly/occt_MODERN_Exhaust_1.brep", 3, 2),
                                ("cad-part/gmsh_part.step", 1, 0),
                                ("cad-part/kicad_CP_Radial_D10.0mm.step", 1, 0),
                                # recovery stopped at 8 tessellation nodes no facet used
                                # (gmsh_Block and pythonocc_Ventilator, 170,000 and 240,000
                                # tetrahedra, go through recovery in test_cad_corpus)
                                ("cad-part/gmsh_U_Joint_2.stp", 1, 0)):
    path = data(rel)
    if not path:
        continue
    code, rep, target, err = mesh(path, "--quiet")
    check(code == 0, "%s meshes (exit %s: %s)" % (rel, code, err.strip()[-300:]))
    if code == 0:
        check(rep["cad"]["solids"] == solids and rep["cad"]["interface_faces"] == interfaces,
              "%s: %d solids, %d interfaces (%d, %d)" % (rel, solids, interfaces, rep["cad"]["solids"], rep["cad"]["interface_faces"]))
        check_mesh(target, rep, rel)

# The faces' new meshes are planned and made on several threads, each
# against the surface as it was, and put in in the faces' order: one thread
# and two give the same file (caxif: 192 faces, most of them remeshed).
path = data("cad-assembly/caxif_as1-oc-214.stp")
if path:
    files = {}
    for threads in ("1", "2"):
        code, rep, target, err = mesh_as("caxif_threads%s" % threads, path, "--quiet", "--threads", threads)
        check(code == 0, "caxif on %s threads meshes (exit %s: %s)" % (threads, code, err.strip()[-300:]))
        if code == 0:
            files[threads] = (open(target, "rb").read(), rep["cad"]["remeshed_faces"])
    if len(files) == 2:
        check(files["1"] == files["2"] and files["1"][1] > 100,
              "caxif: the same mesh file on 1 and 2 threads (%d faces remeshed)" % files["1"][1])

# The Block's grooves are 0.8 high where its size is 2: the two rows of
# vertices at their floor and ceiling corners make flat rectangles, and a
# tetrahedron of four surface vertices lay flat in one (0.0004 deg). Its
# centroid is the point that opens it, but a point in so thin a groove takes
# a facet, so it was refused; now the longest surface edge of such a
# tetrahedron is split as a fold's is, and the rows no longer meet in one
# plane (measured 2026-11-26: 0.00 -> 0.19 deg, 16 -> 2 tetrahedra under
# 5 deg). The 0.19 deg was a cap over the seam between the two halves of a
# cylinder, beside the corner with the top face, still there after the three
# rounds of fold splits; the rounds for caps over smooth borders between two
# faces split it once more (2026-11-27: 3.82 deg on seed 1, 4.66 on seeds 2
# and 3).
block = data("cad-part/gmsh_Block.stp")
if block:
    rep, lowest = meshed_angles(block, "the Block")
    if rep is not None:
        check(lowest.min() > 3 and (lowest < 5).sum() < 4 and rep["interior"]["cap_folds_split"] > 100,
              "the Block: smallest dihedral angle %.3f deg > 3, %d tetrahedra under 5 deg < 4, %d edges split for caps"
              % (lowest.min(), (lowest < 5).sum(), rep["interior"]["cap_folds_split"]))
    # At twice its size (6.74), the recovery of the first tessellation has
    # 6 facets missing at its 8th pass, 10 at its 16th and none at its 18th.
    # The patience of 8 passes gave it up at the 16th for the unsmoothed,
    # unremeshed tessellation, whose needle strips (4 deg corners along a
    # chamfer 0.5 wide) came out at 0.01 deg with 3,176 tetrahedra under 10;
    # with under 100 facets missing the patience is now twice as long
    # (2026-11-27: 7.19 deg, 13 under 10, no retry).
    rep, lowest = meshed_angles(block, "the Block at size 6.74", "--size", "6.7369")
    if rep is not None:
        check(rep["cad"]["recovery_retries"] == 0 and lowest.min() > 5 and (lowest < 10).sum() < 30,
              "the Block at size 6.74: %d retries (0), smallest dihedral angle %.3f deg > 5, %d tetrahedra under 10 < 30"
              % (rep["cad"]["recovery_retries"], lowest.min(), (lowest < 10).sum()))

# t20's chamfer cone meets the sides of a hexagon in faces with 3 to 5 deg
# corners. The remesher's planning put the first nodes on the two borders
# of such a corner 1.50 and 2.49 away: the triangle there was a cap of
# 168 deg (10 facets over 160 deg), and a tetrahedron on it 1.81 deg. With
# the far node at the near one's distance (2026-11-27), 3.14 deg: the two
# first nodes sat across a 3 deg gap, and so did the tetrahedron's faces.
# Now the node added on the far border (which has no planned node) goes 1.3
# times as far as the near one: 9.45 deg (9.40 and 9.45 with seeds 2 and
# 3), with 5 facets over 160 deg, none over 164.
t20 = data("cad-part/gmsh_t20_component8.step")
if t20:
    rep, lowest = meshed_angles(t20, "t20")
    surface = converted_surface(t20, "t20_surface")
    if rep is not None and surface is not None:
        largest = corner_angles(surface.points, surface.cells_dict["triangle"]).max(axis=1)
        check(lowest.min() > 8 and largest.max() < 170,
              "t20: smallest dihedral angle %.2f deg > 8, largest facet corner %.1f deg < 170"
              % (lowest.min(), largest.max()))

# At 0.45 times its size (1.1783) t20's first recovery runs away and the
# uniform chord heights (0.0023567) mesh it. There CGAL's mesher made a
# 0.013 mm triangle of the plane Face3, at the corner where Face2 meets it
# at 0.26 deg, that lay folded over its three neighbours (their normals
# opposite): the border node's place in the face's chart and on the face
# differ by more than its width. The tetrahedron in the fold had 0.003 deg.
# A face whose new mesh folds on the face keeps its facets (2026-11-29:
# 0.84 deg, 66 tetrahedra under 5 deg where there were 71).
if t20:
    import meshio
    surface = os.path.join(out, "t20_uniform_chords.vtk")
    code, _, err = run("convert", t20, surface, "--size", "1.1783", "--deflection", "0.0023567")
    check(code == 0, "t20 at size 1.1783, chord 0.0023567: surface written (exit %d: %s)" % (code, err.strip()[:200]))
    if code == 0:
        s = meshio.read(surface)
        tri = s.cells_dict["triangle"]
        faces = [np.asarray(v) for b, v in zip(s.cells, s.cell_data["face"]) if b.type == "triangle"][0]
        folded = folded_edges(s.points, tri, faces)
        check(folded == 0, "t20 at size 1.1783, chord 0.0023567: %d edges with a facet folded over the other (0)" % folded)
    rep, lowest = meshed_angles(t20, "t20 at size 1.1783", "--size", "1.1783")
    if rep is not None:
        check(lowest.min() > 0.5, "t20 at size 1.1783: smallest dihedral angle %.3f deg > 0.5 (0.003 in a fold)" % lowest.min())

# The Exhaust's flange face has 0 deg corners where the pipe's round corners
# leave its straight sides. With the border pieces cut evenly into as many
# pieces as CGAL's mesher wanted, the two sides of such a corner had nodes at
# other distances from it: 114 facets over 170 deg, caps of up to 179.8 deg,
# and recovery ran away there (the mesh dropped the remeshing). Cut where the
# mesher put its nodes: 4 over 170 deg (measured 2026-11-26).
exhaust = data("cad-assembly/occt_MODERN_Exhaust_1.brep")
if exhaust:
    s = converted_surface(exhaust, "exhaust")
    if s is not None:
        largest = corner_angles(s.points, s.cells_dict["triangle"]).max(axis=1)
        check((largest > 170).sum() < 10, "exhaust: %d facets with a corner over 170 deg (114 before), largest %.2f deg"
              % ((largest > 170).sum(), largest.max()))
    # Where a seam leaves the flange face tangentially (a corner of 0.7 deg
    # between two border edges), splitting the caps' folds made the corner
    # smaller and the border nodes across it closer at each round: 0.00027
    # apart beside tetrahedra 0.2 long, 0.036 deg (299 under 10 deg). The
    # folds at such corners stay: 0.244 deg, 199 under 10 (2026-11-27).
    # Since the piece of Face15 that lies on Face42 is a face of its own
    # (face groups, 2026-11-30), its outline is a face border, and the worst
    # tetrahedra lie along it: 0.142 deg, 300 under 10 (253 of the 300 touch
    # that piece).
    rep, lowest = meshed_angles(exhaust, "exhaust")
    if rep is not None:
        check(rep["interior"]["cap_folds_at_sharp_corners"] > 0 and lowest.min() > 0.1 and (lowest < 10).sum() < 330,
              "exhaust: %d cap folds left at sharp corners, smallest dihedral angle %.3f deg > 0.1, %d under 10 deg < 330"
              % (rep["interior"]["cap_folds_at_sharp_corners"], lowest.min(), (lowest < 10).sum()))

# caxif's pins stand on its block tangent to the block's edges: the block's
# top face has corners of 3.2 deg there, and the caps over the block's edge
# under them could be opened neither by a point under the fold's middle (it
# takes the thin corner facet) nor, since the fold is a side of that corner,
# by a split. A point under the middle of the cap's other surface edges can:
# 4.14 -> 8.79 deg, 8 -> 6 tetrahedra under 10 deg (2026-11-27; Gmsh at a
# similar count 11.76 deg, 7.67 deg made conformal).
caxif = data("cad-assembly/caxif_as1-oc-214.stp")
if caxif:
    rep, lowest = meshed_angles(caxif, "caxif")
    if rep is not None:
        check(rep["interior"]["cap_points_fallback"] > 0 and lowest.min() > 8 and (lowest < 10).sum() < 8,
              "caxif: %d cap points under another edge than the fold, smallest dihedral angle %.2f deg > 8, "
              "%d under 10 deg < 8" % (rep["interior"]["cap_points_fallback"], lowest.min(), (lowest < 10).sum()))

# OpenCASCADE puts 31 inner nodes of the capacitor's fillets 4e-6 to 2.5e-5
# from border nodes (median edge 0.5); recovery failed at them (exit 4) until
# edges under a tenth of the chord height were collapsed. The surface it
# starts from has no such edge left.
cap = data("cad-part/kicad_CP_Radial_D10.0mm.step")
if cap:
    s = converted_surface(cap, "capacitor")
    if s is not None:
        tri = s.cells_dict["triangle"]
        edges = np.unique(np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1), axis=0)
        length = np.linalg.norm(s.points[edges[:, 0]] - s.points[edges[:, 1]], axis=1)
        check(length.min() > 1e-3 * np.median(length),
              "capacitor: shortest surface edge %.3g, median %.3g (was 3.6e-6 before the collapse)"
              % (length.min(), np.median(length)))
    code, rep, _, err = mesh(cap, "--quiet", "--no-interior")
    check(code == 0 and rep["cad"]["collapsed_edges"] >= 31,
          "capacitor: %s short edges collapsed (exit %d)" % (rep["cad"]["collapsed_edges"] if rep else "?", code))

# At 1.5 and 2 times its size (0.858) the capacitor had a flat cap over a
# fold inside one face, its lead's cylinder: the cap point made tetrahedra
# flatter still (0.006 deg), and the sliver pass brought the cap back (0.020
# deg at 1.287, 0.12 deg at 1.716). Such a point is now refused and the fold
# split on the face (cap_vertices.cpp, kFairCapPointDeg): 7.52 and 7.44 deg
# on 2026-11-28.
if cap:
    for size in ("1.287", "1.716"):
        rep, lowest = meshed_angles(cap, "capacitor at size " + size, "--size", size)
        if rep is not None:
            check(lowest.min() > 5 and rep["interior"]["cap_folds_split"] > 0,
                  "capacitor at size %s: smallest dihedral angle %.3f deg > 5 (meshio), %d cap folds split"
                  % (size, lowest.min(), rep["interior"]["cap_folds_split"]))

# Flat caps over shallow folds whose circumsphere's centre lies outside the
# solid: no point inward of the fold is in the circumsphere, so the cap's own
# centroid opens it. The cylinder head's smallest angle was 0.12 deg (Gmsh at
# a similar count: 0.13 deg); 0.76 deg with the centroid.
head = data("cad-part/gmsh_Zylkopf_cylinder_head.stp")
if head:
    code, rep, target, err = mesh(head, "--quiet")
    check(code == 0, "cylinder head meshed (exit %d: %s)" % (code, err.strip()[:200]))
    if code == 0:
        import meshio
        m = meshio.read(target)
        from tet_angles import dihedral_angles
        smallest = float(dihedral_angles(m.points, m.cells_dict["tetra"]).min())
        check(smallest > 0.5 and rep["interior"]["cap_points"] > 0,
              "cylinder head: smallest dihedral %.3f deg (meshio, numpy), %d cap points"
              % (smallest, rep["interior"]["cap_points"]))

# Caps no cap point opens without taking a facet get their folds split, on
# CAD input with the mid-point on the face (three rounds). gmsh_ring.brep's
# smallest angle was 2.05 deg (a cap over a 89.9 + 85.7 deg facet pair) before,
# 4.57 deg after (2026-11-25); with its quarter tori remeshed too (6 of its
# 7 faces: its sphere is whole, which no chart covers), 10.01 deg, and 961 ->
# 0 tetrahedra under 10 deg. With the whole sphere remeshed in two halves
# (2026-11-26), its poles lose OpenCASCADE's fans of 30 facets with 10.6 deg
# corners: 11.21 -> 13.12 deg (the smallest now inside, near the torus).
ring = data("cad-assembly/gmsh_ring.brep")
if ring:
    rep, smallest = meshed_angles(ring, "gmsh_ring.brep")
    if rep:
        worst = max(abs(v["mesh"] - v["cad"]) / v["cad"] for v in rep["cad"]["volumes"])
        check(rep["interior"]["cap_folds_split"] > 0 and rep["cad"]["remeshed_faces"] == 7 and smallest.min() > 12.5
              and (smallest < 10).sum() == 0 and worst < 0.005,
              "gmsh_ring.brep: %d cap folds split, %d faces remeshed, smallest dihedral %.2f deg (meshio, numpy; "
              "2.05 before), %d tetrahedra under 10 deg, volume error %.3f %%"
              % (rep["interior"]["cap_folds_split"], rep["cad"]["remeshed_faces"], smallest.min(),
                 (smallest < 10).sum(), 100 * worst))
    # Its torus and sphere touch, and do not cross: glued, they fuse into
    # the shape the full fuse makes (the same mesh, byte for byte).
    code, full, target, err = mesh_as("gmsh_ring_full", ring, "--quiet", "--full-fuse")
    check(rep is not None and rep["cad"]["fuse"] == "glued" and code == 0 and full["cad"]["fuse"] == "in full"
          and open(target, "rb").read() == open(os.path.join(out, "gmsh_ring.vtu"), "rb").read(),
          "gmsh_ring.brep: glued and fused in full, the same mesh (exit %s)" % code)

# Smoothing of the tessellation on the CAD faces: gmsh_part.step's flat
# tetrahedra sat on caps along CAD edges (corners of 172-174 deg at a face's
# inner vertex); moved towards their neighbours' middle, on the face.
# Measured 2026-11-24: 167 -> 72 tetrahedra under 10 deg, 2.80 -> 2.85 deg.
# 2026-11-25, with the caps' folds split on CAD input too (which open some of
# the same caps, 30 folds split unsmoothed, 12 smoothed): 152 -> 79, 3.04 deg
# both (3.044508 against 3.044508: the same tetrahedron, 1.5e-7 deg apart);
# so smoothing now takes away at least 40 % of them, not half.
# 2026-11-25, with flat inner vertices removed after the smoothing (one
# vertex here, which renumbers the rest and so moves every random shift):
# seed 1 152 -> 149 unsmoothed, 79 -> 92 smoothed, and the smallest angle
# 3.06 unsmoothed against 2.31 smoothed. Over seeds 1 to 4 the smallest
# angles were 3.06 / 3.02 / 2.47 / 3.09 unsmoothed and 2.31 / 3.00 / 3.09 /
# 3.39 smoothed: either may be lower on one seed, so the test counts over
# three seeds (149 + 162 + 164 against 92 + 87 + 88) and compares no angle.
# 2026-12-01, with vertices of curved faces sliding in the sliver pass,
# which mends most of what smoothing did: 30 + 48 + 21 against 21 + 18 + 21
# (39 % fewer; before the pass, 624 + 608 + 633 against 495 + 482 + 489).
# 2026-12-02, with the sliver pass's moves free of the facets' Delaunayhood:
# 2 against 4 after the pass, which now mends nearly all of them either way,
# so the test counts before the pass (the report's tets_below_10_deg_before),
# where smoothing must take away 15 % (it takes 21 %).
part = data("cad-part/gmsh_part.step")
if part:
    runs = {}
    for flag in ("--no-smoothing", None):
        for seed in ("1", "2", "3"):
            # The faces as refined: gmsh_part's faces are all planes and cylinders, remeshed by default.
            code, rep, target, err = mesh(part, "--quiet", "--no-face-remesh", "--seed", seed, *([flag] if flag else []))
            name = "gmsh_part.step %s seed %s" % (flag or "smoothed", seed)
            check(code == 0, "%s meshed (exit %d: %s)" % (name, code, err.strip()[:200]))
            if code == 0:
                from tet_angles import dihedral_angles
                m = check_mesh(target, rep, name)
                smallest = dihedral_angles(m.points, m.cells_dict["tetra"]).min(axis=0)
                under, moves, after = runs.get(flag, (0, 0, 0))
                runs[flag] = (under + rep["slivers"]["tets_below_10_deg_before"], moves + rep["cad"]["smoothing_moves"],
                              after + int((smallest < 10).sum()))
    if len(runs) == 2:
        off, on = runs["--no-smoothing"], runs[None]
        check(off[1] == 0 and on[1] > 0 and on[0] < 0.85 * off[0],
              "gmsh_part.step smoothed, seeds 1 to 3: %d moves, %d -> %d tetrahedra under 10 deg before the sliver pass"
              " (%d -> %d after it)" % (on[1], off[0], on[0], off[2], on[2]))

# --surface-grading on CAD input: the graded splits are made on the CAD
# faces. The SOIC package's narrow faces come out of OpenCASCADE as needles,
# and every tetrahedron on a needle is flat; graded, they are split to about
# their faces' width. Measured 2026-11-24 (smoothed): 3.68 -> 9.07 deg, 909 -> 34
# tetrahedra under 10 deg (off by default on CAD input: see cad_mesher.h).
soic = data("cad-part/kicad_SOIC-8.step")
if soic:
    runs = {}
    for grading in ("0", "2"):
        code, rep, target, err = mesh(soic, "--quiet", "--no-face-remesh", "--surface-grading", grading)
        check(code == 0, "SOIC-8 at --surface-grading %s meshed (exit %d: %s)" % (grading, code, err.strip()[:200]))
        if code == 0:
            import meshio
            from tet_angles import dihedral_angles
            m = check_mesh(target, rep, "SOIC-8 graded %s" % grading)
            angles = dihedral_angles(m.points, m.cells_dict["tetra"])
            runs[grading] = (float(angles.min()), int((angles.min(axis=0) < 10).sum()), rep["cad"]["surface_facets"])
    if len(runs) == 2:
        check(runs["2"][0] > runs["0"][0] + 2 and runs["2"][1] < runs["0"][1] / 4 and runs["2"][2] > runs["0"][2],
              "SOIC-8: graded on the CAD faces, smallest dihedral %.2f -> %.2f deg, %d -> %d under 10 deg, "
              "surface %d -> %d facets" % (runs["0"][0], runs["2"][0], runs["0"][1], runs["2"][1], runs["0"][2], runs["2"][2]))

# Plane and cylinder faces meshed anew inside their borders (cad_remesh.cpp):
# Delaunay refinement in the unrolled (u, v), so the surface triangles are
# round, and the tetrahedra on them. All 23 faces of the face recognition
# sample are planes or cylinders. Measured 2026-11-25: surface triangles
# with a corner under 20 deg 403 -> 8 (of 5664 / 6134), smallest dihedral
# 4.28 -> 10.04 deg (16.13 with the raised sliver aim), 63 -> 0 tetrahedra
# under 10 deg.
sample = data("cad-part/pythonocc_face_recognition_sample_part.stp")
if sample:
    runs = {}
    for flag in ("--no-face-remesh", None):
        code, rep, target, err = mesh(sample, "--quiet", *([flag] if flag else []))
        name = "face recognition sample %s" % (flag or "remeshed")
        check(code == 0, "%s meshed (exit %d: %s)" % (name, code, err.strip()[:200]))
        if code == 0:
            from tet_angles import dihedral_angles
            m = check_mesh(target, rep, name)
            smallest = dihedral_angles(m.points, m.cells_dict["tetra"]).min(axis=0)
            thin = int((corner_angles(m.points, m.cells_dict["triangle"]).min(axis=1) < 20).sum())
            error = max(abs(v["mesh"] / v["cad"] - 1) for v in rep["cad"]["volumes"])
            runs[flag] = (float(smallest.min()), int((smallest < 10).sum()), thin, rep["cad"]["remeshed_faces"], error,
                          rep["slivers"]["raised_to_deg"])
    if len(runs) == 2:
        off, on = runs["--no-face-remesh"], runs[None]
        # The smallest angle unremeshed was 8.64 deg (45 tetrahedra under 10)
        # until the sliver pass's vertex insertions (case D, 2026-12-02): 9.94
        # (1 under 10) since; remeshed 19.47 either way.
        check(off[3] == 0 and on[3] == 23 and on[2] < off[2] / 10 and on[0] > off[0] + 5 and on[1] <= off[1] / 4
              and on[4] < 0.005,
              "face recognition sample: %d faces remeshed, surface triangles under 20 deg %d -> %d, smallest "
              "dihedral %.2f -> %.2f deg, %d -> %d tetrahedra under 10 deg, volume error %.3f %%"
              % (on[3], off[2], on[2], off[0], on[0], off[1], on[1], 100 * on[4]))
        # Nothing left under 10 deg remeshed: the sliver pass goes on to
        # 20 deg (16.13 deg reached, 2026-11-25; 10.04 before); unremeshed,
        # tetrahedra stay under 10 and it does not.
        check(on[5] == 20 and on[0] > 15 and off[5] == 0,
              "face recognition sample: sliver aim raised to %g deg (unremeshed: %g), smallest dihedral %.2f deg"
              % (on[5], off[5], on[0]))

# Cones, spheres and tori are meshed anew too, in charts of their (u, v)
# that keep angles: a cone unrolled into a sector of a disc, Mercator on a
# sphere, the conformal height on a torus (lengths scaled by a factor the
# size bound is divided by). Other faces (a B-spline here) get an affine
# chart, isometric at the face's middle, and keep the new mesh only when its
# smallest corner is larger and it lies as close to the face. Parts made
# here: a sphere cut to a band (no pole), a torus, a cone frustum, a loft
# from a circle to an ellipse. Measured 2026-11-25: surface triangles with a
# corner under 20 deg 18 / 180 / 50 / 21 -> 0 / 0 / 0 / 10, volume errors
# 0.249 / 0.427 / 0.218 / 0.243 % -> 0.223 / 0.322 / 0.187 / 0.191 %.
def curved_part(name, build, exact_chart=True):
    path = make_brep(name, build)
    runs = {}
    for flag in ("--no-face-remesh", None):
        # The tessellations compared, without the sliver pass: since
        # 2026-11-30 it slides the vertices of flat faces on the convex hull
        # too, which reshapes their triangles (the loft's flat ends: 21 -> 19
        # under 20 deg unremeshed, none of them on the face remeshed).
        code, rep, target, err = mesh(path, "--quiet", "--keep-slivers", *([flag] if flag else []))
        check(code == 0, "%s %s meshed (exit %d: %s)" % (name, flag or "remeshed", code, err.strip()[:200]))
        if code != 0:
            return
        import meshio
        m = meshio.read(target)
        corners = corner_angles(m.points, m.cells_dict["triangle"]).min(axis=1)
        error = max(abs(v["mesh"] / v["cad"] - 1) for v in rep["cad"]["volumes"])
        runs[flag] = (rep["cad"]["remeshed_faces"], rep["cad"]["faces"], int((corners < 20).sum()), error,
                      float(corners.min()))
        check_mesh(target, rep, "%s %s" % (name, flag or "remeshed"))
    off, on = runs["--no-face-remesh"], runs[None]
    thin_after = on[2] == 0 if exact_chart else on[2] <= off[2] / 2 and on[4] > 2 * off[4]
    check(off[0] == 0 and on[0] == on[1] and off[2] > 0 and thin_after and on[3] < 0.005,
          "%s: %d of %d faces remeshed, surface triangles under 20 deg %d -> %d, smallest corner %.1f -> %.1f deg, "
          "volume error %.3f -> %.3f %%" % (name, on[0], on[1], off[2], on[2], off[4], on[4], 100 * off[3], 100 * on[3]))


def sphere_band(occ):
    occ.intersect([(3, occ.addSphere(0, 0, 0, 2))], [(3, occ.addBox(-3, -3, -1, 6, 6, 2))])


def loft(occ):
    circle = occ.addCurveLoop([occ.addCircle(0, 0, 0, 2)])
    ellipse = occ.addCurveLoop([occ.addEllipse(0.5, 0, 3, 1.5, 0.8)])
    occ.addThruSections([circle, ellipse], makeSolid=True, makeRuled=False)


curved_part("sphere_band", sphere_band)
curved_part("torus", lambda occ: occ.addTorus(0, 0, 0, 3, 1))
curved_part("cone_frustum", lambda occ: occ.addCone(0, 0, 0, 0, 0, 3, 2, 1))
# A sphere's poles (a stereographic chart from the point opposite the face:
# the other pole of a dome, the middle of a ball's cut) and a cone's apex
# (the apex is the sector's centre): 42 / 103 / 271 -> 0 thin surface
# triangles (2026-11-25).
curved_part("dome", lambda occ: occ.intersect([(3, occ.addSphere(0, 0, 0, 2))], [(3, occ.addBox(-3, -3, -1, 6, 6, 4))]))
curved_part("cut_ball", lambda occ: occ.intersect([(3, occ.addSphere(0, 0, 0, 2))], [(3, occ.addBox(-3, -3, -3, 4.5, 6, 6))]))
curved_part("cone_tip", lambda occ: occ.addCone(0, 0, 0, 0, 0, 3, 2, 0))
# A half ball: its plane's border holds the sphere's poles, singular
# vertices of the sphere only; the plane was left for them until
# 2026-11-25 (28 thin triangles, smallest dihedral 9.18 deg; now none, 20.01).
curved_part("half_ball", lambda occ: occ.intersect([(3, occ.addSphere(0, 0, 0, 2))], [(3, occ.addBox(-3, 0, -3, 6, 3, 6))]))
curved_part("loft", loft, exact_chart=False)

# A pin of radius 5 and length 200 at size 10.55 (caxif's pins at its
# chosen size): the chord height asks for edges of 1.1 around, 7 times the
# strips' facets. Remeshed (a face may grow 50 times while the surface stays
# within 4 times), its tetrahedra are fine; left to its strips (when a face
# could grow 3 times), 5,345 of 7,406 tetrahedra were under 10 deg and the
# smallest 4.31 deg (2026-11-25).
pin = make_brep("pin", lambda occ: occ.addCylinder(0, 0, 0, 200, 0, 0, 5))
rep, smallest = meshed_angles(pin, "pin at size 10.55", "--size", "10.55")
if rep:
    check(rep["cad"]["remeshed_faces"] == 3 and smallest.min() > 15 and (smallest < 10).sum() == 0,
          "pin at size 10.55: %d of 3 faces remeshed, %d facets, smallest dihedral %.2f deg, %d of %d tetrahedra "
          "under 10 deg" % (rep["cad"]["remeshed_faces"], rep["cad"]["surface_facets"], smallest.min(),
                            (smallest < 10).sum(), len(smallest)))

# Faces at knife edges (two faces meeting under 60 deg) are remeshed too:
# the crankshaft's smallest dihedral was 4.08 deg (48 tetrahedra under 10)
# while they were left to the refinement, 15.61 deg after (2026-11-25).
crank = data("cad-part/gmsh_Kurbelwelle_crankshaft.stp")
if crank:
    rep, smallest = meshed_angles(crank, "crankshaft")
    if rep:
        check(rep["cad"]["remeshed_faces"] >= 54 and smallest.min() > 12 and (smallest < 10).sum() == 0,
              "crankshaft: %d of %d faces remeshed, smallest dihedral %.2f deg, %d tetrahedra under 10 deg"
              % (rep["cad"]["remeshed_faces"], rep["cad"]["faces"], smallest.min(), (smallest < 10).sum()))

# Inner vertices of three facets lying on their neighbours' edge (a corner
# over 170 deg) are removed, the three facets made one: the U-joint's
# B-spline faces left as tessellated had 29 (a node 0.019 from a 3.53-long
# border edge: a 178.4 deg facet). Measured 2026-11-25: smallest dihedral
# 0.0007 -> 0.11 deg, tetrahedra under 10 deg 878 -> 382. Since then, inner
# vertices a hair from a border (a cap of over 170 deg on a border piece)
# are moved onto it, on a node split under them, before: measured
# 2026-11-27, the U-joint 0.13 -> 0.34 deg, 329 -> 267 tetrahedra under 10
# deg, 42 moved, and 13 flat inner vertices are left for the removal. The
# needle edges collapsed at poles after them (12 here) made that 297 at the
# same angle; sliver case A across ridges within the chord height, 273.
# At twice its size (11.094), a snap refused in every pass held a CAD vertex
# that the cap beside it wanted: not proposed again, 315 -> 287 under 10 deg.
# These figures are those of the sliver pass with the facets kept Delaunay
# (--delaunay-surface), the default until 2026-12-02. Free of that (the
# default since), the pass takes the U-joint to 72 tetrahedra under 10 deg
# instead of 170, but it ends on another path, on a flat tetrahedron of two
# facets of faces nearly tangent (a fold of 0.21 deg) that the held pass
# had flipped away: 0.211 deg against 0.344.
ujoint = data("cad-part/gmsh_U_Joint_2.stp")
if ujoint:
    rep, smallest = meshed_angles(ujoint, "U-joint, facets kept Delaunay", "--delaunay-surface")
    if rep:
        check(rep["cad"]["border_caps_snapped"] >= 40 and smallest.min() > 0.25 and (smallest < 10).sum() < 300,
              "U-joint, facets kept Delaunay: %d border caps snapped, smallest dihedral %.4f deg, %d tetrahedra under 10 deg"
              % (rep["cad"]["border_caps_snapped"], smallest.min(), (smallest < 10).sum()))
        held_under = (smallest < 10).sum()
        rep, smallest = meshed_angles(ujoint, "U-joint")
        if rep:
            check((smallest < 10).sum() < 0.6 * held_under and smallest.min() > 0.2,
                  "U-joint: %d tetrahedra under 10 deg (%d with the facets kept Delaunay), smallest dihedral %.4f deg"
                  % ((smallest < 10).sum(), held_under, smallest.min()))
    rep, smallest = meshed_angles(ujoint, "U-joint at twice its size", "--size", "11.094")
    if rep:
        check((smallest < 10).sum() < 300,
              "U-joint at twice its size: %d tetrahedra under 10 deg" % (smallest < 10).sum())

# The same on a shape of our own, which runs without the shared data: an
# ellipsoid (semi-axes 1.5, 0.4, 0.2) fragmented with a box that holds its
# half y < 0 (three solids). Measured 2026-11-27: without the snaps the first
# recovery stopped (one retry), 0.33 deg, 4,145 tetrahedra under 10 deg; with
# them 20 moved, no retry, 1.74 deg, 535 under 10 deg; with the needle edges
# of OpenCASCADE's rows at the poles collapsed too (446), 2.49 deg and 94.
def ellipsoid_in_box(occ):
    ellipsoid = occ.addSphere(0, 0, 0, 1)
    occ.dilate([(3, ellipsoid)], 0, 0, 0, 1.5, 0.4, 0.2)
    occ.fragment([(3, ellipsoid)], [(3, occ.addBox(-2, -2, -2, 4, 2, 4))])
halves = make_brep("ellipsoid_halves", ellipsoid_in_box)
rep, smallest = meshed_angles(halves, "ellipsoid halves")
if rep:
    check(rep["cad"]["solids"] == 3 and rep["cad"]["border_caps_snapped"] >= 10 and rep["cad"]["recovery_retries"] == 0
          and rep["cad"]["needle_edges_collapsed"] >= 100 and smallest.min() > 2.0 and (smallest < 10).sum() < 200,
          "ellipsoid halves: %d solids, %d border caps snapped, %d needle edges collapsed, %d retries, smallest "
          "dihedral %.3f deg > 2, %d tetrahedra under 10 deg"
          % (rep["cad"]["solids"], rep["cad"]["border_caps_snapped"], rep["cad"]["needle_edges_collapsed"],
             rep["cad"]["recovery_retries"], smallest.min(), (smallest < 10).sum()))

# Case A on CAD input takes a pair of facets across a ridge under the flip
# angle when the surface moves by at most the face's chord height, as a flip
# of Delaunayzation may. A lone ellipsoid (semi-axes 3, 1, 0.3): flat
# tetrahedra between four surface vertices near its poles, their facets
# 0.1 deg apart, over case A's 0.1 deg ridge limit. Measured 2026-11-27:
# smallest dihedral 0.04 -> 5.75 deg, 12 such pairs; 31 -> 32 tetrahedra
# under 10 deg, the same volume error (0.296 %).
lone = make_brep("lone_ellipsoid", lambda occ: occ.dilate([(3, occ.addSphere(0, 0, 0, 1))], 0, 0, 0, 3, 1, 0.3))
rep, smallest = meshed_angles(lone, "lone ellipsoid")
if rep:
    check(rep["slivers"]["removed_across_ridges"] >= 5 and smallest.min() > 3.0,
          "lone ellipsoid: %d case-A pairs across ridges, smallest dihedral %.3f deg > 3"
          % (rep["slivers"]["removed_across_ridges"], smallest.min()))

# The ellipses' ellipsoids come from OpenCASCADE with rows of nodes graded
# towards their rims (4e-4 to 1.3e-3 from a rim of 0.05 to 0.08 pieces):
# needles whose tetrahedra were flat, and the first recovery stalled on
# them. Moved onto the rims, the ellipses mesh on their first tessellation
# (measured 2026-11-27: smallest dihedral 0.04 -> 0.31 deg, Gmsh 0.26 at a
# similar count; 16,907 -> 5,617 tetrahedra under 10 deg; 20.4 -> 7.6 s).
# The needle edges at their poles collapsed too (2,380): 2.19 deg, 742.
ellipses = data("cad-assembly/gmsh_ellipses.brep")
if ellipses:
    rep, smallest = meshed_angles(ellipses, "ellipses")
    if rep:
        check(rep["cad"]["recovery_retries"] == 0 and rep["cad"]["border_caps_snapped"] >= 100
              and rep["cad"]["needle_edges_collapsed"] >= 1000 and smallest.min() > 1.5 and (smallest < 10).sum() < 1500,
              "ellipses: %d retries, %d border caps snapped, %d needle edges collapsed, smallest dihedral %.4f deg > 1.5, "
              "%d tetrahedra under 10 deg" % (rep["cad"]["recovery_retries"], rep["cad"]["border_caps_snapped"],
                                              rep["cad"]["needle_edges_collapsed"], smallest.min(), (smallest < 10).sum()))

# A face of zero area (the nose of gmsh_simple_plane.brep) comes back from
# OpenCASCADE as pairs of triangles on the same collinear nodes, facing away
# from each other. They are dropped, so the surface is valid: one recovery
# pass then ends in exit 4 (not recovered within the guard), where it was
# refused as degenerate facets (exit 3) before.
plane = data("cad-assembly/gmsh_simple_plane.brep")
if plane:
    code, _, err = run("mesh", plane, "-o", os.path.join(out, "plane.vtu"), "--no-interior", "--max-passes", "1",
                       "--quiet")
    check(code == 4 and "degenerate" not in err,
          "gmsh_simple_plane.brep: folded face dropped, the surface validates (exit %d: %s)" % (code, err.strip()[:200]))

# A slender pin (6 x 200) at the default size: OpenCASCADE's strips along
# its length are halved down to the size, and four times their count was
# the budget that refused the cylinder its remesh (20,650 facets asked,
# 17,776 allowed): 4,282 of 10,003 tetrahedra under 5 deg, exit 0, until
# 2026-11-30. Every face is remeshed now.
pin = make_brep("pin", lambda occ: occ.addCylinder(0, 0, 0, 0, 0, 200, 3))
code, rep, _, err = mesh(pin, "--quiet")
if code == 0:
    q, c = rep["quality"], rep["cad"]
    check(c["remeshed_faces"] == 3 and q["min_dihedral_deg"] > 15 and q["tets_below_10_deg"] == 0,
          "6 x 200 pin at the default size: %d of 3 faces remeshed, smallest angle %.2f deg, %d tetrahedra under 10 deg"
          % (c["remeshed_faces"], q["min_dihedral_deg"], q["tets_below_10_deg"]))
else:
    check(False, "6 x 200 pin meshes (exit %d: %s)" % (code, err.strip()[:300]))

# Bad input: exit 3, a message naming the problem, no output.
def bad(name, content, needle):
    path = os.path.join(out, name)
    if content is not None:
        with open(path, "wb" if isinstance(content, bytes) else "w") as f:
            f.write(content)
    target = os.path.join(out, name + ".vtu")
    code, _, err = run("mesh", path, "-o", target)
    check(code == 3 and needle in err and not os.path.exists(target),
          "%s: exit 3 naming '%s' (exit %d: %s)" % (name, needle, code, err.strip()[:300]))

bad("missing.step", None, "no such file")
bad("empty.step", "", "empty file")
bad("text.step", "this is not a STEP file\n", "not a readable STEP file")
bad("text.brep", "hello\n", "not a BREP file")
os.makedirs(os.path.join(out, "folder.step"))
bad("folder.step", None, "a folder, not a CAD file")
# A BREP text without its version line made OpenCASCADE print "File was not
# written with this version of the topology" on standard output, under
# --quiet and from Python too, until 2026-11-30.
for name, text in (("text.brep", None), ("v9.brep", "DBRep_DrawableShape\n\nCASCADE Topology V9, (c) Open Cascade\n")):
    if text is not None:
        with open(os.path.join(out, name), "w") as f:
            f.write(text)
    code, stdout, err = run("mesh", os.path.join(out, name), "-o", os.path.join(out, "text2.vtu"), "--quiet")
    check(code == 3 and stdout == "" and "not a BREP file" in err and "CASCADE Topology" in err,
          "%s --quiet: nothing on standard output, the missing line named (%r, %s)" % (name, stdout[:200], err.strip()[:300]))
# OpenCASCADE's syntax error goes into the message, not to standard output
# (printed there in colour, under --quiet too, until 2026-11-30).
text_step = os.path.join(out, "text.step")
code, stdout, err = run("mesh", text_step, "-o", os.path.join(out, "text2.vtu"), "--quiet")
check(code == 3 and stdout == "" and "OpenCASCADE says:" in err and "Incorrect syntax" in err,
      "text.step --quiet: OpenCASCADE's syntax error in the message, nothing on standard output (%r, %s)" %
      (stdout[:200], err.strip()[:300]))
# Files that made OpenCASCADE's readers dereference null (a segmentation
# fault, exit 139, before its fault handlers were set while reading,
# cad_read.cpp): one byte changed in a real file, found by mutating them.
# The STEP transfer then has no shape; the IGES reader drops the entity that
# faulted (a B-spline surface whose degree is garbage) and reads the rest,
# which is no solid (the bearing is an open shell).
def one_line_broken(name, relative, line, broken, needle):
    """A shared file with one line changed, refused with exit 3 naming needle."""
    path = data(relative)
    if not path:
        return None
    raw = open(path, "rb").read()
    check(line in raw, "%s holds the line the broken copy changes" % relative)
    bad(name, raw.replace(line, broken), needle)
    return path


face_bound = b"#149 = FACE_OUTER_BOUND( '', #236, .T. );"
one_line_broken("dangling.step", "cad-part/gmsh_part.step", face_bound, face_bound.replace(b"#236", b"#99999"),
                "no shape OpenCASCADE could transfer")
surface = b"128,3,1,3,1,0,0,1,0,0,0.E+000,0.E+000,0.E+000,0.E+000,1.,1.,1.,  0004031P0006364"
bearing = one_line_broken("garbled.iges", "cad-part/occt_bearing.iges", surface,
                          surface.replace(b"128,3,1,", b"128,3,\x9f,"), "no solid")
if bearing:
    # --quiet is quiet: OpenCASCADE's IGES reader printed "Total number of
    # loaded entities 2932." to standard output.
    code, stdout, _ = run("mesh", bearing, "-o", os.path.join(out, "bearing.vtu"), "--quiet")
    check(code == 3 and stdout == "", "occt_bearing.iges --quiet: nothing on standard output (%r)" % stdout[:200])
sheet = make_brep("sheet", lambda occ: occ.addRectangle(0, 0, 0, 1, 1))
bad(os.path.basename(sheet), None, "no solid")
def box_without_lid(occ):
    box = occ.addBox(0, 0, 0, 1, 1, 1)
    occ.remove([(3, box)])          # the volume only: its six faces stay
    occ.remove([(2, 6)], recursive=True)  # one face gone: an open shell


open_box = make_brep("openbox", box_without_lid)
bad(os.path.basename(open_box), None, "none closed")

# A size far below the part's (a unit mix-up) is refused before the
# refinement runs out of memory: exit 3 naming the size, at once.
import time
unit_box = make_brep("unitbox", lambda occ: occ.addBox(0, 0, 0, 1, 1, 1))
started = time.time()
code, _, err = run("mesh", unit_box, "-o", os.path.join(out, "unitbox_tiny.vtu"), "--size", "1e-7", timeout=120)
check(code == 3 and "size 1e-07 asks for about" in err and "GiB of memory" in err
      and not os.path.exists(os.path.join(out, "unitbox_tiny.vtu")) and time.time() - started < 60,
      "CAD --size 1e-7 on a unit box: exit 3 naming the size and the memory (exit %d after %.1f s: %s)"
      % (code, time.time() - started, err.strip()[:300]))

# A chord height far over the part: OpenCASCADE's mesher left gaps between
# gmsh_part.step's faces at --deflection 1000 (the part is 213 mm across),
# and the mesh was refused as an open surface. Over the size it bounds
# nothing the splits to the size do not, and it is taken as the size.
path = data("cad-part/gmsh_part.step")
if path:
    code, rep, target, err = mesh_as("part_huge_deflection", path, "--deflection", "1000", "--quiet")
    check(code == 0 and abs(rep["cad"]["deflection"] - rep["cad"]["size"]) < 1e-12,
          "gmsh_part.step --deflection 1000 meshes at a chord height of its size (exit %d: %s)"
          % (code, {k: rep["cad"][k] for k in ("deflection", "size")} if rep else err.strip()[-300:]))

# The cautious run, which a run falls back to when its recovery with interior
# vertices stops, asked for with --cautious: interior candidates that would
# take a surface facet out of the tetrahedralization are refused
# (volume/facet_takers.h), and no cap fold is split. gmsh_part.step refuses
# 898 of them (2026-11-27).
path = data("cad-part/gmsh_part.step")
if path:
    code, rep, target, err = mesh_as("part_cautious", path, "--cautious", "--quiet")
    check(code == 0 and rep["complete"] and rep["interior"]["rejected_taking_a_facet"] > 0
          and rep["interior"]["cap_folds_split"] == 0 and not rep["interior"]["cap_fold_round_undone"],
          "gmsh_part.step --cautious: candidates taking a facet refused, no fold splits (exit %d, %s)"
          % (code, rep["interior"] if rep else err.strip()[-300:]))
    if code == 0:
        import meshio
        m = meshio.read(target)
        vol = tet_volumes(m)
        check(vol.min() > 0 and len(vol) == rep["counts"]["tetrahedra"],
              "gmsh_part.step --cautious: %d tetrahedra, all positive (meshio)" % len(vol))

finish()
