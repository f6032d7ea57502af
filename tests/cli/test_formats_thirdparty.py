"""Third-party readers accept what `vdmesh convert` writes.

A 3x3x3 block of cubes, each split into 6 positive tetrahedra (162 in all),
two regions (x < 1.5 is region 1), the 6 block sides as faces 1..6 and the
region interface as face 7, is written as a Medit .mesh, converted by the
CLI to every volume format, and read back with meshio (counts, volume, tag
sets), Gmsh (the .msh and the legacy .vtk) and VTK (the .vtk and .vtu);
and the other way: files VTK's writers make of it, and files Gmsh and
meshio write, read by vdmesh; and surfaces VTK writes as POLYDATA, and
PLY both ways.
Exits non-zero on the first failed check; prints every check it made.
Needs VDMESH_BIN (the CLI); without it the test says so and passes.
"""
import itertools
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

N = 3
FAILED = []


def check(ok, what):
    print(("ok    " if ok else "FAIL  ") + what)
    if not ok:
        FAILED.append(what)


def block_mesh():
    idx = {}
    pts = []
    for k, j, i in itertools.product(range(N + 1), repeat=3):
        idx[(i, j, k)] = len(pts)
        pts.append((float(i), float(j), float(k)))
    pts = np.array(pts)
    tets, regions = [], []
    for i, j, k in itertools.product(range(N), repeat=3):
        corner = [idx[(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))] for c in range(8)]
        for a in itertools.permutations(range(3)):
            v1 = 1 << a[0]
            v2 = v1 | (1 << a[1])
            t = [corner[0], corner[v1], corner[v2], corner[7]]
            p = pts[t]
            if np.linalg.det(np.array([p[1] - p[0], p[2] - p[0], p[3] - p[0]])) < 0:
                t[1], t[2] = t[2], t[1]
            tets.append(t)
            regions.append(1 if i + 0.5 < 1.5 else 2)
    faces = {}
    for t, r in zip(tets, regions):
        for f in ((1, 3, 2), (0, 2, 3), (0, 3, 1), (0, 1, 2)):
            tri = (t[f[0]], t[f[2]], t[f[1]])  # outward
            faces.setdefault(tuple(sorted(tri)), []).append((tri, r))
    tris, face_ids = [], []
    for sides in faces.values():
        if len(sides) == 1:
            tri = sides[0][0]
            p = pts[list(tri)]
            n = np.cross(p[1] - p[0], p[2] - p[0])
            axis = int(np.argmax(np.abs(n)))
            tris.append(tri)
            face_ids.append(1 + 2 * axis + (1 if n[axis] > 0 else 0))
        elif sides[0][1] != sides[1][1]:
            tris.append(sides[0][0] if sides[0][1] == 1 else sides[1][0])
            face_ids.append(7)
    return pts, np.array(tets), np.array(regions), np.array(tris), np.array(face_ids)


def write_medit(path, pts, tets, regions, tris, face_ids):
    with open(path, "w") as f:
        f.write("MeshVersionFormatted 2\nDimension 3\nVertices\n%d\n" % len(pts))
        for p in pts:
            f.write("%.17g %.17g %.17g 0\n" % tuple(p))
        f.write("Triangles\n%d\n" % len(tris))
        for t, r in zip(tris, face_ids):
            f.write("%d %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1, r))
        f.write("Tetrahedra\n%d\n" % len(tets))
        for t, r in zip(tets, regions):
            f.write("%d %d %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1, t[3] + 1, r))
        f.write("End\n")


def signed_volumes(points, tets):
    p = points[tets]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def check_meshio(path, fmt, n_tets, n_tris, volume):
    import meshio

    m = meshio.read(path)
    tets = np.concatenate([c.data for c in m.cells if c.type == "tetra"] or [np.zeros((0, 4), int)])
    tris = np.concatenate([c.data for c in m.cells if c.type == "triangle"] or [np.zeros((0, 3), int)])
    vols = signed_volumes(m.points, tets)
    check(len(tets) == n_tets, "meshio %s: %d tetrahedra (expected %d)" % (fmt, len(tets), n_tets))
    check(bool(np.all(vols > 0)), "meshio %s: every tetrahedron positive" % fmt)
    check(abs(vols.sum() - volume) < 1e-9, "meshio %s: volume %.12g (expected %g)" % (fmt, vols.sum(), volume))

    def tags(name, cell_type):
        if name not in m.cell_data:
            return None
        out = set()
        for block, data in zip(m.cells, m.cell_data[name]):
            if block.type == cell_type:
                out |= set(int(x) for x in np.asarray(data).ravel())
        return out

    if fmt == "msh":
        check(len(tris) == n_tris, "meshio msh: %d triangles (expected %d)" % (len(tris), n_tris))
        check(tags("gmsh:physical", "tetra") == {1, 2}, "meshio msh: physical volumes {1, 2}")
        check(tags("gmsh:physical", "triangle") == set(range(1, 8)), "meshio msh: physical surfaces 1..7")
    elif fmt in ("vtu", "vtk"):
        check(len(tris) == n_tris, "meshio %s: %d triangles (expected %d)" % (fmt, len(tris), n_tris))
        check(tags("region", "tetra") == {1, 2}, "meshio %s: region array {1, 2} on tetrahedra" % fmt)
        check(tags("face", "triangle") == set(range(1, 8)), "meshio %s: face array 1..7 on triangles" % fmt)
    elif fmt == "mesh":
        check(len(tris) == n_tris, "meshio mesh: %d triangles (expected %d)" % (len(tris), n_tris))
        check(tags("medit:ref", "tetra") == {1, 2}, "meshio mesh: tetrahedron refs {1, 2}")
        check(tags("medit:ref", "triangle") == set(range(1, 8)), "meshio mesh: triangle refs 1..7")
    elif fmt == "inp":
        sets = {k.upper() for k in m.cell_sets}
        check({"REGION1", "REGION2"} <= sets, "meshio inp: element sets Region1, Region2 (%s)" % sorted(sets))
        check({"FACE%d_NODES" % k for k in range(1, 8)} <= {k.upper() for k in m.point_sets},
              "meshio inp: node sets Face1_Nodes..Face7_Nodes")


def check_gmsh(path, n_tets, volume, physical):
    import gmsh

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        types, tags, nodes = gmsh.model.mesh.getElements(3)
        count = sum(len(t) for t in tags)
        check(count == n_tets, "gmsh %s: %d volume elements (expected %d)" % (os.path.basename(path), count, n_tets))
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        xyz = dict(zip(node_tags, coords.reshape(-1, 3)))
        total = 0.0
        positive = True
        for t, n in zip(types, nodes):
            if t != 4:
                continue
            quad = n.reshape(-1, 4)
            pts = np.array([[xyz[v] for v in q] for q in quad])
            vols = signed_volumes(pts.reshape(-1, 3), np.arange(len(pts) * 4).reshape(-1, 4))
            positive &= bool(np.all(vols > 0))
            total += vols.sum()
        check(positive, "gmsh %s: every tetrahedron positive" % os.path.basename(path))
        check(abs(total - volume) < 1e-9, "gmsh %s: volume %.12g" % (os.path.basename(path), total))
        if physical:
            groups = gmsh.model.getPhysicalGroups()
            check(set(g for d, g in groups if d == 3) == {1, 2}, "gmsh msh: physical volumes {1, 2}")
            check(set(g for d, g in groups if d == 2) == set(range(1, 8)), "gmsh msh: physical surfaces 1..7")
            names = {gmsh.model.getPhysicalName(3, 1), gmsh.model.getPhysicalName(3, 2)}
            check(names == {"Region1", "Region2"}, "gmsh msh: physical names Region1, Region2")
    finally:
        gmsh.finalize()


def check_vtk(path, n_tets, volume):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    reader = vtk.vtkXMLUnstructuredGridReader() if path.endswith(".vtu") else vtk.vtkUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    types = vtk_to_numpy(grid.GetCellTypesArray())
    check(int((types == 10).sum()) == n_tets, "vtk %s: %d tetrahedra" % (os.path.basename(path), (types == 10).sum()))
    region = grid.GetCellData().GetArray("region")
    check(region is not None, "vtk %s: cell array 'region'" % os.path.basename(path))
    if region is not None:
        r = vtk_to_numpy(region)
        check(set(r[types == 10].tolist()) == {1, 2}, "vtk %s: regions {1, 2}" % os.path.basename(path))
    quality = vtk.vtkMeshQuality()
    quality.SetInputData(grid)
    quality.SetTetQualityMeasureToVolume()
    quality.Update()
    q = vtk_to_numpy(quality.GetOutput().GetCellData().GetArray("Quality"))[types == 10]
    check(bool(np.all(q > 0)) and abs(q.sum() - volume) < 1e-9,
          "vtk %s: signed volumes positive, total %.12g" % (os.path.basename(path), q.sum()))


def check_calculix(inp, tmp):
    """The .inp plus material, sections and a step is a valid CalculiX deck:
    block clamped at z = 0 (Face5), pressure on z = N (Face6) pushes it down."""
    import shutil

    if not shutil.which("ccx"):
        print("skip  CalculiX: ccx not installed")
        return
    deck = os.path.join(tmp, "job.inp")
    with open(deck, "w") as f:
        f.write("*HEADING\nvdmesh converter check\n*INCLUDE, INPUT=%s\n"
                "*MATERIAL, NAME=STEEL\n*ELASTIC\n210000, 0.3\n"
                "*SOLID SECTION, ELSET=Region1, MATERIAL=STEEL\n*SOLID SECTION, ELSET=Region2, MATERIAL=STEEL\n"
                "*STEP\n*STATIC\n*BOUNDARY\nFace5_Nodes, 1, 3, 0.\n*DLOAD\nFace6, P, 10.\n"
                "*NODE PRINT, NSET=NALL\nU\n*END STEP\n" % os.path.basename(inp))
    run = subprocess.run(["ccx", "job"], cwd=tmp, capture_output=True, text=True, timeout=300)
    check(run.returncode == 0 and "error" not in run.stdout.lower(), "ccx runs the deck (exit %d)" % run.returncode)
    uz = []
    dat = os.path.join(tmp, "job.dat")
    if os.path.exists(dat):
        for line in open(dat):
            parts = line.split()
            if len(parts) == 4 and parts[0].isdigit():
                uz.append(float(parts[3]))
    check(len(uz) > 0 and min(uz) < 0 and max(uz) <= 1e-12, "ccx: pressure on Face6 moves the block down (min uz %s)"
          % (min(uz) if uz else None))


def vdmesh_info(binary, path):
    """(exit code, tetrahedra, {region: volume}, message) of `vdmesh info`."""
    run = subprocess.run([binary, "info", path], capture_output=True, text=True)
    tets, volumes = None, {}
    for line in run.stdout.splitlines():
        words = line.replace(",", " ").split()
        if "tetrahedra" in words:
            tets = int(words[words.index("tetrahedra") + 1])
        if len(words) == 4 and words[0] == "region" and words[2] == "volume":
            volumes[int(words[1].rstrip(":"))] = float(words[3])
    return run.returncode, tets, volumes, run.stderr.strip()[:200]


def check_reads_vtk_writers(binary, vtu, tmp, n_tets, expected):
    """What VTK's own writers make of our file, read back by vdmesh: the
    XML writer's default (appended, zlib, 32768-byte blocks declared for
    arrays far smaller), inline binary, ASCII (an <InformationKey> inside
    the points' array), and the legacy writer (METADATA after each FIELD
    array), ASCII and binary; each with a number and a string array of the
    whole data set (<FieldData>, FIELD)."""
    import vtk

    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    grid = reader.GetOutput()
    # Arrays of the whole data set, as VTK and ParaView write them (a time,
    # a name): refused in every mode until 2026-11-30.
    time = vtk.vtkDoubleArray()
    time.SetName("TimeValue")
    time.InsertNextValue(1.5)
    grid.GetFieldData().AddArray(time)
    author = vtk.vtkStringArray()
    author.SetName("author")
    author.InsertNextValue("me and you")
    grid.GetFieldData().AddArray(author)
    # vdmesh's region names (vtk_common.h), which every writer must carry
    # through: a .pvtu's pieces and legacy .vtk files lost them (2026-11-30).
    names = vtk.vtkUnsignedCharArray()
    names.SetName("vdmesh_names")
    named = {r: "Part_%d" % r for r in expected}
    for byte in "".join("region %d %s\n" % (r, n) for r, n in named.items()).encode():
        names.InsertNextValue(byte)
    grid.GetFieldData().RemoveArray("vdmesh_names")
    grid.GetFieldData().AddArray(names)
    variants = []
    # Since 2026-11-30 also VTK's other compressors (LZ4, LZMA), big-endian
    # files and several pieces, each refused before ("unsupported compressor
    # vtkLZ4DataCompressor", "big-endian VTU is not supported", "only one
    # <Piece> is supported"), and the .pvtu of the parallel writer.
    for mode in ("default", "binary", "ascii", "raw", "lz4", "lzma", "lzma_binary", "bigendian",
                 "bigendian_zlib", "bigendian_raw", "pieces", "pieces_lz4", "pieces_ghosts", "pieces_whole"):
        w = vtk.vtkXMLUnstructuredGridWriter()
        w.SetInputData(grid)
        path = os.path.join(tmp, "vtkw_%s.vtu" % mode)
        w.SetFileName(path)
        if mode in ("binary", "lzma_binary"):
            w.SetDataModeToBinary()
        elif mode == "ascii":
            w.SetDataModeToAscii()
        if mode in ("raw", "bigendian_raw"):
            w.SetCompressorTypeToNone()
        elif mode in ("lz4", "pieces_lz4"):
            w.SetCompressorTypeToLZ4()
        elif mode in ("lzma", "lzma_binary"):
            w.SetCompressorTypeToLZMA()
        if mode.startswith("bigendian"):
            w.SetByteOrderToBigEndian()
            if mode == "bigendian":
                w.SetDataModeToBinary()
                w.SetCompressorTypeToNone()
        if mode.startswith("pieces"):
            # Pieces of the grid (a writer given the grid itself writes it
            # whole into each piece; read so too, the repeats dropped).
            split = vtk.vtkExtractUnstructuredGridPiece()
            split.SetInputData(grid)
            if mode == "pieces_ghosts":
                split.CreateGhostCellsOn()
                w.SetGhostLevel(1)
            w.SetInputConnection(split.GetOutputPort())
            w.SetNumberOfPieces(3)
        if mode == "pieces_whole":
            w.SetNumberOfPieces(3)
        w.Write()
        variants.append(path)
    pw = vtk.vtkXMLPUnstructuredGridWriter()
    split = vtk.vtkExtractUnstructuredGridPiece()
    split.SetInputData(grid)
    pw.SetInputConnection(split.GetOutputPort())
    pw.SetNumberOfPieces(3)
    pw.SetStartPiece(0)
    pw.SetEndPiece(2)
    pvtu = os.path.join(tmp, "vtkw_parallel.pvtu")
    pw.SetFileName(pvtu)
    pw.Write()
    variants.append(pvtu)
    for legacy_binary in (False, True):
        w = vtk.vtkUnstructuredGridWriter()
        w.SetInputData(grid)
        path = os.path.join(tmp, "vtkw_legacy_%s.vtk" % ("binary" if legacy_binary else "ascii"))
        w.SetFileName(path)
        if legacy_binary:
            w.SetFileTypeToBinary()
        w.Write()
        variants.append(path)
    import meshio

    def sides(path):
        """{triangle (its corners' coordinates): (front, back)} of vdmesh's .vtu of a file."""
        out = path + ".sides.vtu"
        subprocess.run([binary, "convert", path, out], capture_output=True, check=True)
        got = meshio.read(out)
        found = {}
        for k, cells in enumerate(got.cells):
            if cells.type != "triangle":
                continue
            front, back = got.cell_data["front"][k], got.cell_data["back"][k]
            for tri, f, b in zip(cells.data, front, back):
                key = tuple(sorted(tuple(got.points[v]) for v in tri))
                found[key] = (int(f), int(b))
        return found

    one_piece = sides(variants[0])
    points = None
    for path in variants:
        code, tets, volumes, err = vdmesh_info(binary, path)
        ok = code == 0 and tets == n_tets and set(volumes) == set(expected) and all(
            abs(volumes[r] - v) < 1e-9 for r, v in expected.items())
        check(ok, "vdmesh info %s (written by VTK): exit %d, %s tetrahedra, volumes %s %s" %
              (os.path.basename(path), code, tets, volumes, err))
        deck = path + ".inp"
        subprocess.run([binary, "convert", path, deck], capture_output=True)
        elsets = set(re.findall(r"ELSET=(\w+)", open(deck).read())) if os.path.exists(deck) else set()
        check(set(named.values()) <= elsets, "%s: the region names %s in the deck's element sets" %
              (os.path.basename(path), sorted(named.values())))
        # The pieces repeat the points where they meet: welded, the mesh has
        # the points of the one-piece file, and a deck of it holds together.
        info = subprocess.run([binary, "info", path], capture_output=True, text=True).stdout
        count = re.search(r"points (\d+)", info)
        if points is None:
            points = count and int(count.group(1))
        check(count and int(count.group(1)) == points,
              "vdmesh info %s: %s points, as the one-piece file (%s)" % (os.path.basename(path),
                                                                          count and count.group(1), points))
        if "pieces" in path or path.endswith(".pvtu"):
            # A triangle between two pieces was taken for exterior on one
            # side (.pvtu, a build of the same day).
            check(sides(path) == one_piece, "vdmesh reads %s's triangles with the one-piece file's sides" %
                  os.path.basename(path))


def check_reads_gmsh_and_meshio_files(binary, tmp):
    """Files Gmsh and meshio write, read by vdmesh.
    - Gmsh 4.1 of a box with a sphere in it whose physical group is on the
      sphere only: the box shell (entity 3) was numbered as the sphere's
      group 3, one region (2.2 with Mesh.SaveAll writes no groups at all).
    - meshio's MSH 2.2 without cell data: every tag 0, read as region 0 (the
      exterior), and `vdmesh mesh` said "open surface".
    - Gmsh's surface meshes, whose sides $Entities gives wrong (its
      OpenCASCADE kernel writes every sign as +) and whose triangles turn
      like each surface's parametrization (its built-in kernel): two boxes
      sharing a wall, a sphere in a box, a built-in box; refused before."""
    import gmsh
    import meshio

    def box_sphere(model, physical):
        gmsh.model.add(model)
        box = gmsh.model.occ.addBox(-1, -1, -1, 2, 2, 2)
        ball = gmsh.model.occ.addSphere(0, 0, 0, 0.5)
        gmsh.model.occ.fragment([(3, box)], [(3, ball)])
        gmsh.model.occ.synchronize()
        vols = sorted(t for _, t in gmsh.model.getEntities(3))
        masses = {t: gmsh.model.occ.getMass(3, t) for t in vols}
        if physical:
            sphere = min(vols, key=lambda t: masses[t])
            gmsh.model.addPhysicalGroup(3, [sphere], 3)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        return masses

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("Mesh.SaveAll", 1)
        box_sphere("partial", True)
        gmsh.model.mesh.generate(3)
        for version in (4.1, 2.2):
            path = os.path.join(tmp, "partial_%s.msh" % version)
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.write(path)
            code, tets, volumes, err = vdmesh_info(binary, path)
            small = [v for v in volumes.values() if v < 1]
            # info prints 9 digits
            check(code == 0 and len(volumes) == 2 and 3 in volumes and len(small) == 1 and
                  abs(sum(volumes.values()) - 8) < 1e-7,
                  "vdmesh info %s (Gmsh, physical group on the sphere only): 2 regions, %s %s" %
                  (os.path.basename(path), volumes, err))
        gmsh.option.setNumber("Mesh.SaveAll", 0)
        # Two boxes in a group "all" and one group each: Gmsh lists the
        # left box's groups as "11 100" and the right one's as "100 22", and
        # the first listed was the region until 2026-11-30 (regions 11 and
        # 100: "right" gone, "all" the right box alone). A tetrahedron takes
        # the group of fewest tetrahedra.
        gmsh.model.add("overlapping_groups")
        gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1, 1)
        gmsh.model.occ.addBox(1, 0, 0, 1, 1, 1, 2)
        gmsh.model.occ.fragment([(3, 1)], [(3, 2)])
        gmsh.model.occ.synchronize()
        left = [t for _, t in gmsh.model.getEntities(3) if gmsh.model.occ.getCenterOfMass(3, t)[0] < 1]
        right = [t for _, t in gmsh.model.getEntities(3) if gmsh.model.occ.getCenterOfMass(3, t)[0] > 1]
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, left + right, 100), "all")
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, left, 11), "left")
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, right, 22), "right")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(3)
        for version in (4.1, 2.2):
            for binary_file in (0, 1):
                path = os.path.join(tmp, "overlapping_%s_%d.msh" % (version, binary_file))
                gmsh.option.setNumber("Mesh.MshFileVersion", version)
                gmsh.option.setNumber("Mesh.Binary", binary_file)
                gmsh.write(path)
                code, tets, volumes, err = vdmesh_info(binary, path)
                check(code == 0 and sorted(volumes) == [11, 22] and
                      all(abs(v - 1) < 1e-9 for v in volumes.values()),
                      "vdmesh info %s (boxes in 'all' and in 'left' / 'right'): regions 11 and 22 of volume 1, "
                      "got %s %s" % (os.path.basename(path), volumes, err))
                deck = os.path.join(tmp, "overlapping.inp")
                run = subprocess.run([binary, "convert", path, deck], capture_output=True, text=True)
                with open(deck) as f:
                    blocks = re.findall(r"^\*ELEMENT, TYPE=C3D4, ELSET=(\w+)", f.read(), re.M)
                check(run.returncode == 0 and sorted(blocks) == ["left", "right"],
                      "vdmesh convert %s overlapping.inp: element sets left and right, got %s" %
                      (os.path.basename(path), blocks))
        gmsh.option.setNumber("Mesh.Binary", 0)
        # Groups whose ranking by volumes and by tetrahedra differ: A holds
        # V1 and a big V2, B holds V1 and two tiny volumes. MSH 4.1 ranked by
        # volumes (V1 in A) and 2.2 by tetrahedra (V1 in B) in a build of the
        # same day; both by tetrahedra now.
        gmsh.model.add("ranked_groups")
        for k, (x, edge) in enumerate(((0, 1), (3, 1), (6, 0.2), (8, 0.2))):
            gmsh.model.occ.addBox(x, 0, 0, edge, edge, edge, k + 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [1, 2], 5)
        gmsh.model.addPhysicalGroup(3, [1, 3, 4], 7)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.2)
        gmsh.model.mesh.generate(3)
        seen = []
        for version in (4.1, 2.2):
            path = os.path.join(tmp, "ranked_%s.msh" % version)
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.write(path)
            seen.append(vdmesh_info(binary, path)[2])
        check(seen[0] == seen[1] and set(seen[0]) == {5, 7} and abs(seen[0][5] - 1) < 1e-9,
              "groups ranked alike in MSH 4.1 and 2.2 (V1 in 7, the group of fewer tetrahedra): %s" % seen)
        # Partitioned (gmsh -part 2), with and without ghost cells, ASCII and
        # binary: each partition's piece of a volume was a region of its
        # own and the cuts between partitions faces (4 regions, 33 triangles
        # too many) until 2026-11-30; 2.2 writes the parents' groups.
        gmsh.model.add("parts")
        a = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        b = gmsh.model.occ.addBox(1, 0, 0, 2, 1, 1)
        gmsh.model.occ.fragment([(3, a)], [(3, b)])
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [a], 11)
        gmsh.model.addPhysicalGroup(3, [b], 22)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(3)
        whole = len(gmsh.model.mesh.getElementsByType(4)[0])
        faces = len(gmsh.model.mesh.getElementsByType(2)[0])
        gmsh.option.setNumber("Mesh.SaveAll", 1)  # the cuts' triangles too, which are in no group
        for ghosts in (0, 1):
            gmsh.option.setNumber("Mesh.PartitionCreateGhostCells", ghosts)
            gmsh.model.mesh.partition(2)
            for version, binary_file in ((4.1, 0), (4.1, 1), (2.2, 0)):
                gmsh.option.setNumber("Mesh.MshFileVersion", version)
                gmsh.option.setNumber("Mesh.Binary", binary_file)
                path = os.path.join(tmp, "parts_%d_%s_%d.msh" % (ghosts, version, binary_file))
                gmsh.write(path)
                code, tets, volumes, err = vdmesh_info(binary, path)
                info = subprocess.run([binary, "info", path], capture_output=True, text=True).stdout.split()
                triangles = int(info[info.index("triangles") + 1].rstrip(",")) if "triangles" in info else None
                # 2.2 with Mesh.SaveAll writes no groups: the volumes' entities 1 and 2 number them.
                first, second = (11, 22) if version == 4.1 else (a, b)
                check(code == 0 and tets == whole and triangles == faces and set(volumes) == {first, second} and
                      abs(volumes[first] - 1) < 1e-9 and abs(volumes[second] - 2) < 1e-9,
                      "vdmesh info %s (Gmsh, 2 partitions): %s tetrahedra of %d, %s triangles of %d, volumes %s %s" %
                      (os.path.basename(path), tets, whole, triangles, faces, volumes, err))
            gmsh.model.mesh.unpartition()
        gmsh.option.setNumber("Mesh.SaveAll", 0)
        # 2.2 with parametric nodes ($ParametricNodes in place of $Nodes):
        # every element "refers to node 15, which does not exist" before.
        gmsh.option.setNumber("Mesh.SaveParametric", 1)
        for binary_file in (0, 1):
            gmsh.option.setNumber("Mesh.MshFileVersion", 2.2)
            gmsh.option.setNumber("Mesh.Binary", binary_file)
            path = os.path.join(tmp, "parametric_%d.msh" % binary_file)
            gmsh.write(path)
            code, tets, volumes, err = vdmesh_info(binary, path)
            check(code == 0 and tets == whole and set(volumes) == {11, 22} and abs(volumes[22] - 2) < 1e-9,
                  "vdmesh info %s (Gmsh 2.2, parametric nodes): %s tetrahedra of %d, volumes %s %s" %
                  (os.path.basename(path), tets, whole, volumes, err))
        gmsh.option.setNumber("Mesh.SaveParametric", 0)
        gmsh.option.setNumber("Mesh.Binary", 0)
        # MSH 1.0 ($NOD/$ELM, no $MeshFormat): refused as "does not start
        # with $MeshFormat" until 2026-11-30.
        gmsh.option.setNumber("Mesh.MshFileVersion", 1.0)
        path = os.path.join(tmp, "parts_1.0.msh")
        gmsh.write(path)
        code, tets, volumes, err = vdmesh_info(binary, path)
        check(code == 0 and tets == whole and set(volumes) == {11, 22} and abs(volumes[11] - 1) < 1e-9 and
              abs(volumes[22] - 2) < 1e-9, "vdmesh info %s (Gmsh 1.0): %s tetrahedra of %d, volumes %s %s" %
              (os.path.basename(path), tets, whole, volumes, err))
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        surfaces = []
        gmsh.model.add("two")
        a = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        b = gmsh.model.occ.addBox(1, 0, 0, 1, 1, 1)
        gmsh.model.occ.fragment([(3, a)], [(3, b)])
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        surfaces.append(("two_boxes", [1.0, 1.0]))
        for version in (4.1, 2.2):
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.write(os.path.join(tmp, "two_boxes_%s.msh" % version))
        masses = box_sphere("box_sphere", False)
        gmsh.model.mesh.generate(2)
        surfaces.append(("box_sphere", None))
        for version in (4.1, 2.2):
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.write(os.path.join(tmp, "box_sphere_%s.msh" % version))
        gmsh.model.add("geo")
        gmsh.model.geo.addPoint(0, 0, 0, 0.3, 1)
        e1 = gmsh.model.geo.extrude([(0, 1)], 1, 0, 0)
        e2 = gmsh.model.geo.extrude([(1, e1[1][1])], 0, 1, 0)
        gmsh.model.geo.extrude([(2, e2[1][1])], 0, 0, 1)
        gmsh.model.geo.synchronize()
        gmsh.model.mesh.generate(2)
        surfaces.append(("builtin_box", [1.0]))
        for version in (4.1, 2.2):
            gmsh.option.setNumber("Mesh.MshFileVersion", version)
            gmsh.write(os.path.join(tmp, "builtin_box_%s.msh" % version))
        # With physical volumes, surface only (4.1): the volumes' numbers and
        # names, from the triangles each volume lists, turned out of it (the
        # sphere's are a cavity of the box's volume). They came out as
        # regions 1 and 2, beside names for 11 and 22 (a surface tester,
        # 2026-11-30).
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.model.add("named")
        a = gmsh.model.occ.addBox(0, 0, 0, 1, 1, 1)
        b = gmsh.model.occ.addBox(1, 0, 0, 1, 1, 1)
        gmsh.model.occ.fragment([(3, a)], [(3, b)])
        gmsh.model.occ.synchronize()
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [a], 11), "Left")
        gmsh.model.setPhysicalName(3, gmsh.model.addPhysicalGroup(3, [b], 22), "Right")
        gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 101)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        gmsh.write(os.path.join(tmp, "named_boxes.msh"))
        gmsh.model.add("named_sphere")
        gmsh.model.occ.addBox(-1, -1, -1, 2, 2, 2)
        gmsh.model.occ.addSphere(0, 0, 0, 0.5)
        gmsh.model.occ.fragment([(3, 1)], [(3, 2)])
        gmsh.model.occ.synchronize()
        vols = sorted(t for _, t in gmsh.model.getEntities(3))
        ball = min(vols, key=lambda t: gmsh.model.occ.getMass(3, t))
        gmsh.model.addPhysicalGroup(3, [ball], 503)
        gmsh.model.addPhysicalGroup(3, [t for t in vols if t != ball], 502)
        gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 101)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.3)
        gmsh.model.mesh.generate(2)
        gmsh.write(os.path.join(tmp, "named_sphere.msh"))
    finally:
        gmsh.finalize()
    for name, regions in (("named_boxes", {11: "Left", 22: "Right"}), ("named_sphere", {502: None, 503: None})):
        path = os.path.join(tmp, name + ".msh")
        deck = os.path.join(tmp, name + ".inp")
        run = subprocess.run([binary, "mesh", path, "-o", deck, "--quiet"], capture_output=True, text=True)
        code, tets, volumes, err = vdmesh_info(binary, deck) if run.returncode == 0 else (
            run.returncode, None, {}, run.stderr.strip()[:200])
        names = [l.split("ELSET=")[1].strip() for l in open(deck) if "TYPE=C3D4" in l] if run.returncode == 0 else []
        if name == "named_boxes":
            ok = set(volumes) == {11, 22} and all(abs(v - 1) < 1e-9 for v in volumes.values()) and \
                sorted(names) == ["Left", "Right"]
        else:  # the sphere's chords cut into it
            ok = set(volumes) == {502, 503} and volumes[503] < 4 / 3 * 3.14159266 * 0.125 and \
                abs(volumes[502] + volumes[503] - 8) < 1e-7
        check(code == 0 and ok, "vdmesh mesh %s (Gmsh surface mesh, physical volumes): regions %s, element sets %s %s"
              % (os.path.basename(path), volumes, names, err))
    for name, expected in surfaces:
        for version in (4.1, 2.2):
            path = os.path.join(tmp, "%s_%s.msh" % (name, version))
            out = os.path.join(tmp, "%s_%s.vtu" % (name, version))
            run = subprocess.run([binary, "mesh", path, "-o", out, "--quiet", "--no-interior"],
                                 capture_output=True, text=True)
            code, tets, volumes, err = vdmesh_info(binary, out) if run.returncode == 0 else (
                run.returncode, None, {}, run.stderr.strip()[:200])
            got = sorted(volumes.values())
            if expected is None:  # the sphere's chords cut into it: sum 8, one region under its CAD volume
                ok = len(got) == 2 and abs(sum(got) - 8) < 1e-7 and got[0] < min(masses.values())
            else:
                ok = len(got) == len(expected) and all(abs(g - e) < 1e-7 for g, e in zip(got, expected))
            check(code == 0 and ok, "vdmesh mesh %s (Gmsh surface mesh): exit %d, volumes %s %s" %
                  (os.path.basename(path), code, got, err))
    # meshio without cell data: every tag 0.
    mesh = meshio.read(os.path.join(tmp, "partial_2.2.msh"))
    plain = meshio.Mesh(mesh.points, [("triangle", mesh.cells_dict["triangle"]), ("tetra", mesh.cells_dict["tetra"])])
    path = os.path.join(tmp, "plain.msh")
    meshio.write(path, plain, file_format="gmsh22", binary=False)
    code, tets, volumes, err = vdmesh_info(binary, path)
    check(code == 0 and 0 not in volumes and tets == len(mesh.cells_dict["tetra"]),
          "vdmesh info plain.msh (meshio, no cell data): no region 0: %s %s" % (volumes, err))
    run = subprocess.run([binary, "mesh", path, "-o", os.path.join(tmp, "plain.vtu"), "--quiet", "--no-interior"],
                         capture_output=True, text=True)
    check(run.returncode == 0, "vdmesh mesh plain.msh (meshio, no cell data): exit %d %s" %
          (run.returncode, run.stderr.strip()[:200]))


def check_plc_hole_point_in_a_thin_slot(binary, tmp):
    """A 10 x 10 x 1 box of region 7 around a 6 x 6 x 0.0005 slot, coarse:
    the slot's hole point went a hundredth of a facet's inradius off it,
    past the slot's far wall into the solid, and TetGen carved the solid
    away (66 tetrahedra, 0.018 of volume kept; a build of 2026-11-30). It
    lies in the slot now, and the box keeps 100 - 0.018."""
    import gmsh
    src = os.path.join(tmp, "slot.msh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("slot")
        gmsh.model.occ.addBox(0, 0, 0, 10, 10, 1, 1)
        gmsh.model.occ.addBox(2, 2, 0.5, 6, 6, 0.0005, 2)
        gmsh.model.occ.cut([(3, 1)], [(3, 2)])
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [t for _, t in gmsh.model.getEntities(3)], 7)
        gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 1)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 3)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 6)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.model.mesh.generate(3)
        gmsh.write(src)
    finally:
        gmsh.finalize()
    poly = os.path.join(tmp, "slot.poly")
    conv = subprocess.run([binary, "convert", src, poly], capture_output=True, text=True)
    tet = subprocess.run(["tetgen", "-pAQ", poly], capture_output=True, text=True, cwd=tmp)
    code, _, volumes, err = vdmesh_info(binary, os.path.join(tmp, "slot.1.ele"))
    check(conv.returncode == 0 and tet.returncode == 0 and list(volumes) == [7] and
          abs(volumes[7] - (100 - 6 * 6 * 0.0005)) < 1e-9,
          "tetgen -pA of a box with a thin slot written as .poly: region 7 of 99.982, got %s %s" % (volumes, err))


def check_meshb_with_meshio(binary, tmp):
    """Binary Medit (.meshb): meshio's files (version 4: 64-bit words) read
    by vdmesh, and vdmesh's (version 2) read by meshio, with the references
    (regions, face ids); refused as an unknown extension until 2026-11-30."""
    import meshio
    pts, tets, regions, tris, face_ids = block_mesh()
    volume = float(N ** 3)
    src = os.path.join(tmp, "meshio.meshb")
    meshio.write(src, meshio.Mesh(np.array(pts, float), [("tetra", np.array(tets)), ("triangle", np.array(tris))],
                                  cell_data={"medit:ref": [np.array(regions), np.array(face_ids)]}))
    code, n, volumes, err = vdmesh_info(binary, src)
    vols = signed_volumes(pts, tets)
    expected = {r: float(vols[np.array(regions) == r].sum()) for r in (1, 2)}
    check(code == 0 and n == len(tets) and set(volumes) == set(expected) and
          all(abs(volumes[r] - v) < 1e-9 for r, v in expected.items()),
          "vdmesh info meshio.meshb: %s tetrahedra, volumes %s (%s) %s" % (n, volumes, expected, err))
    out = os.path.join(tmp, "vdmesh.meshb")
    run = subprocess.run([binary, "convert", src, out], capture_output=True, text=True)
    try:
        back = meshio.read(out)
        cells = {c.type: c.data for c in back.cells}
        refs = back.cell_data.get("medit:ref")
        ok = (run.returncode == 0 and len(cells.get("tetra", [])) == len(tets) and
              len(cells.get("triangle", [])) == len(tris) and refs is not None)
        if ok:
            tet_refs = [r for c, r in zip(back.cells, refs) if c.type == "tetra"][0]
            tri_refs = [r for c, r in zip(back.cells, refs) if c.type == "triangle"][0]
            ok = sorted(set(tet_refs.tolist())) == [1, 2] and sorted(set(tri_refs.tolist())) == sorted(set(face_ids))
        what = "%d tetrahedra, %d triangles" % (len(cells.get("tetra", [])), len(cells.get("triangle", [])))
    except Exception as e:  # meshio refused the file
        ok, what = False, repr(e)
    check(ok, "meshio reads vdmesh's .meshb: %s %s" % (what, run.stderr.strip()[:200]))


def check_plc_keeps_regions_and_cavities(binary, tmp):
    """A volume mesh written as a PLC (.poly/.smesh) names its regions and
    cavities: a box of region 7 with a cubic cavity, meshed, converted to
    .poly and meshed again by TetGen (-pA) and by vdmesh, keeps region 7 and
    the volume 26. Until 2026-11-30 the lists were empty: the cavity came
    back as a region of its own (volume 27 in all) and the regions numbered
    1, 2 (a CAD ring's two solids swapped)."""
    def box(lo, hi, first):
        corners = [(x, y, z) for z in (lo, hi) for y in (lo, hi) for x in (lo, hi)]
        quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
        return corners, [[first + i for i in q] for q in quads]
    outer, outer_quads = box(0, 3, 1)
    inner, inner_quads = box(1, 2, 9)
    src = os.path.join(tmp, "cavity.poly")
    with open(src, "w") as f:
        f.write("16 3 0 0\n")
        for i, p in enumerate(outer + inner):
            f.write("%d %g %g %g\n" % (i + 1, *p))
        f.write("12 1\n")
        for k, q in enumerate(outer_quads + inner_quads):
            f.write("1 0 %d\n4 %s\n" % (k + 1, " ".join(map(str, q))))
        f.write("1\n1 1.5 1.5 1.5\n1\n1 0.5 0.5 0.5 7\n")
    meshed = os.path.join(tmp, "cavity.vtu")
    run = subprocess.run([binary, "mesh", src, "-o", meshed, "--size", "0.5", "--quiet"], capture_output=True,
                         text=True)
    code, _, volumes, err = vdmesh_info(binary, meshed)
    check(run.returncode == 0 and volumes == {7: 26.0}, "vdmesh mesh cavity.poly: region 7 of 26, got %s %s" %
          (volumes, run.stderr[:200]))
    for ext in ("poly", "smesh"):
        back = os.path.join(tmp, "back." + ext)
        run = subprocess.run([binary, "convert", meshed, back], capture_output=True, text=True)
        check(run.returncode == 0, "vdmesh convert cavity.vtu back.%s (%s)" % (ext, run.stderr[:200]))
        tet = subprocess.run(["tetgen", "-pAQ", back], capture_output=True, text=True, cwd=tmp)
        code, _, volumes, err = vdmesh_info(binary, os.path.join(tmp, "back.1.ele"))
        check(tet.returncode == 0 and code == 0 and list(volumes) == [7] and abs(volumes[7] - 26) < 1e-9,
              "tetgen -pA back.%s: region 7 of volume 26 (the cavity kept), got %s" % (ext, volumes))
        # `tetgen -f` lists the inner faces too, with marker 0: they were
        # read as a face "Face0" (and the MSH 4.1 written from them did not
        # open in meshio) until 2026-11-30.
        if ext == "poly":
            tet = subprocess.run(["tetgen", "-pAfQ", back], capture_output=True, text=True, cwd=tmp)
            every = os.path.join(tmp, "back.1.face")
            with open(every) as f:
                listed = int(f.readline().split()[0])
            info = subprocess.run([binary, "info", every], capture_output=True, text=True)
            faces = re.search(r"triangles (\d+)", info.stdout)
            tagged = re.search(r"faces (\d+)", info.stdout)
            msh = os.path.join(tmp, "every_face.msh")
            conv = subprocess.run([binary, "convert", every, msh], capture_output=True, text=True)
            import meshio
            try:
                read_back = sum(len(c.data) for c in meshio.read(msh).cells if c.type == "triangle")
            except Exception as e:  # meshio refused the file
                read_back = repr(e)
            check(tet.returncode == 0 and conv.returncode == 0 and faces and tagged and
                  int(tagged.group(1)) == 12 and 0 < int(faces.group(1)) < listed and read_back == int(faces.group(1)),
                  "tetgen -pAf: of its %d faces vdmesh keeps the boundary's (%s triangles, %s face ids, 12 wanted), "
                  "meshio reads them from MSH 4.1: %s" % (listed, faces and faces.group(1),
                                                          tagged and tagged.group(1), read_back))
        if ext == "poly":
            # Tetrahedra without regions (no -A): the cavity keeps its point
            # (facets beside them were passed over in a build of the same
            # day: volume 27), and -f's inner faces are dropped too.
            tet = subprocess.run(["tetgen", "-pfQ", back], capture_output=True, text=True, cwd=tmp)
            plain = os.path.join(tmp, "plain.poly")
            conv = subprocess.run([binary, "convert", os.path.join(tmp, "back.1.ele"), plain], capture_output=True,
                                  text=True)
            info = subprocess.run([binary, "info", os.path.join(tmp, "back.1.face")], capture_output=True,
                                  text=True).stdout
            tet2 = subprocess.run(["tetgen", "-pQ", plain], capture_output=True, text=True, cwd=tmp)
            code, _, _, _ = vdmesh_info(binary, os.path.join(tmp, "plain.1.ele"))
            unknown = re.search(r"no region: volume ([0-9.e+-]+)", subprocess.run(
                [binary, "info", os.path.join(tmp, "plain.1.ele")], capture_output=True, text=True).stdout)
            check(tet.returncode == 0 and conv.returncode == 0 and tet2.returncode == 0 and "faces 12" in info and
                  unknown and abs(float(unknown.group(1)) - 26) < 1e-9,
                  "tetgen -pf without regions: 12 face ids (%s), the cavity kept through .poly and tetgen -p: "
                  "volume %s" % (info.split("\n")[2:3], unknown and unknown.group(1)))
        again = os.path.join(tmp, "again.vtu")
        run = subprocess.run([binary, "mesh", back, "-o", again, "--quiet"], capture_output=True, text=True)
        code, _, volumes, err = vdmesh_info(binary, again)
        check(run.returncode == 0 and list(volumes) == [7] and abs(volumes[7] - 26) < 1e-9,
              "vdmesh mesh back.%s: region 7 of volume 26, got %s %s" % (ext, volumes, run.stderr[:200]))


def check_convert_reorients_inverted_tetrahedra(binary, tmp):
    """FreeCAD's FemMesh.write(".vtu") writes every tetrahedron inverted;
    `vdmesh convert` passed them on silently (a deck of negative volume).
    Now it warns, and --reorient turns them, mid-edge nodes with their
    edges: a second-order Gmsh mesh of a box, inverted through meshio, comes
    back with no inverted tetrahedron, the box's volume and every mid node on
    the edge it was on."""
    import gmsh
    import meshio
    src = os.path.join(tmp, "box_o2.msh")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box_o2")
        gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [1], 5)
        gmsh.model.addPhysicalGroup(2, [t for _, t in gmsh.model.getEntities(2)], 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.4)
        # Asked before meshing: Gmsh's Medit writer heads 10-node
        # tetrahedra "TetrahedraP2" only then ("Tetrahedra" after setOrder).
        gmsh.option.setNumber("Mesh.ElementOrder", 2)
        gmsh.model.mesh.generate(3)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(src)
        medit_p2 = os.path.join(tmp, "box_o2.mesh")
        gmsh.write(medit_p2)
    finally:
        gmsh.finalize()
    # Gmsh's Medit second order (TetrahedraP2, TrianglesP2), refused as an
    # "unknown section 'tetrahedrap2'" until 2026-11-30: on the box's
    # straight edges every mid node lies at its edge's mid-point.
    as_vtu = os.path.join(tmp, "box_o2_from_medit.vtu")
    run = subprocess.run([binary, "convert", medit_p2, as_vtu], capture_output=True, text=True)
    ok, worst = run.returncode == 0, None
    if ok:
        p2 = meshio.read(as_vtu)
        cells = {c.type: c.data for c in p2.cells}
        pts = p2.points
        worst = 0.0
        for kind, edges in (("tetra10", ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))),
                            ("triangle6", ((0, 1), (1, 2), (2, 0)))):
            corners = len(edges) == 6 and 4 or 3
            for k, (a, b) in enumerate(edges):
                c = cells.get(kind)
                ok = ok and c is not None
                if c is not None:
                    off = pts[c[:, corners + k]] - 0.5 * (pts[c[:, a]] + pts[c[:, b]])
                    worst = max(worst, float(np.abs(off).max()))
        # Gmsh places them through the CAD surfaces (6e-14 off); a wrong
        # order puts them 0.2 away.
        ok = ok and worst < 1e-9
    check(ok, "vdmesh convert box_o2.mesh (Gmsh's TetrahedraP2) to .vtu: mid nodes on their edges' mid-points, "
          "worst %s %s" % (worst, run.stderr.strip()[:200]))
    mesh = meshio.read(src)
    tets = np.concatenate([c.data for c in mesh.cells if c.type == "tetra10"])
    mids = {}
    for t in tets:
        for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))):
            mids[frozenset((t[a], t[b]))] = t[4 + k]
    inverted = tets[:, [0, 2, 1, 3, 6, 5, 4, 7, 9, 8]]
    turned = os.path.join(tmp, "turned.vtu")
    meshio.write(turned, meshio.Mesh(mesh.points, [("tetra10", inverted)],
                                     cell_data={"region": [np.full(len(inverted), 5)]}), binary=False)
    plain = subprocess.run([binary, "convert", turned, os.path.join(tmp, "turned.inp")], capture_output=True,
                           text=True)
    check(plain.returncode == 0 and ("%d of %d tetrahedra" % (len(tets), len(tets))) in plain.stderr,
          "vdmesh convert of a mesh inverted throughout warns: %s" % plain.stderr.strip()[:200])
    # A deck without element sets: its tetrahedra have no region, and `info`
    # printed no volume for them until 2026-11-30.
    nosets = os.path.join(tmp, "nosets.inp")
    meshio.write(nosets, meshio.Mesh(mesh.points, [("tetra", tets[:, :4])]))
    info = subprocess.run([binary, "info", nosets], capture_output=True, text=True)
    unknown = re.search(r"no region: volume ([0-9.e+-]+)", info.stdout)
    check(info.returncode == 0 and unknown and abs(float(unknown.group(1)) - 2) < 1e-9,
          "vdmesh info of a deck without sets: 'no region: volume 2', got %s" % info.stdout.strip()[-200:])
    out = os.path.join(tmp, "reoriented.vtu")
    run = subprocess.run([binary, "convert", turned, out, "--reorient"], capture_output=True, text=True)
    info = subprocess.run([binary, "info", out], capture_output=True, text=True)
    back = meshio.read(out)
    tets_back = np.concatenate([c.data for c in back.cells if c.type == "tetra10"])
    p = back.points
    volumes = np.einsum("ij,ij->i", p[tets_back[:, 1]] - p[tets_back[:, 0]],
                        np.cross(p[tets_back[:, 2]] - p[tets_back[:, 0]], p[tets_back[:, 3]] - p[tets_back[:, 0]])) / 6
    on_their_edges = all(mids[frozenset((t[a], t[b]))] == t[4 + k] for t in tets_back
                         for k, (a, b) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))))
    check(run.returncode == 0 and run.stderr == "" and "inverted 0;" in info.stdout and (volumes > 0).all() and
          abs(volumes.sum() - 2) < 1e-9 and on_their_edges,
          "vdmesh convert --reorient: %d tetrahedra turned, volume %.12g, mid nodes on their edges: %s %s" %
          (len(tets_back), volumes.sum(), on_their_edges, run.stderr.strip()[:200]))


def read_vtu_with_vtk(path):
    """VTK's reading of a .vtu: points, cell types, connectivity, offsets,
    cell data, and the tetrahedra's node lists."""
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(path)
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    types = vtk_to_numpy(grid.GetCellTypesArray())
    conn = vtk_to_numpy(grid.GetCells().GetConnectivityArray())
    offsets = vtk_to_numpy(grid.GetCells().GetOffsetsArray())
    tets = np.array([conn[offsets[i]:offsets[i + 1]] for i in np.where(types == 10)[0]])
    return points, types, conn, offsets, grid.GetCellData(), tets


def vtk_sphere():
    """VTK's sphere of radius 2, 24 x 16 facets around."""
    import vtk
    sphere = vtk.vtkSphereSource()
    sphere.SetRadius(2)
    sphere.SetThetaResolution(24)
    sphere.SetPhiResolution(16)
    sphere.Update()
    return sphere.GetOutput()


def vtk_enclosed_volume(reader_class, path):
    """The volume VTK's vtkMassProperties gives the surface in `path`, read
    by `reader_class` (as vdmesh reads it: ASCII keeps 7 digits or so)."""
    import vtk
    reader = reader_class()
    reader.SetFileName(path)
    reader.Update()
    tri = vtk.vtkTriangleFilter()
    tri.SetInputData(reader.GetOutput())
    tri.Update()
    mass = vtk.vtkMassProperties()
    mass.SetInputData(tri.GetOutput())
    mass.Update()
    return mass.GetVolume()


def mesh_keeping_surface(binary, path):
    """vdmesh mesh PATH --no-flips (the surface keeps its shape, so the
    tetrahedra fill the volume it encloses): the .vtu written, None if it
    failed."""
    out = path + ".vtu"
    run = subprocess.run([binary, "mesh", path, "-o", out, "--no-flips", "--quiet"], capture_output=True, text=True)
    check(run.returncode == 0, "vdmesh mesh %s (exit %d %s)" % (os.path.basename(path), run.returncode,
                                                                run.stderr.strip()[:200]))
    return out if run.returncode == 0 else None


def check_meshes_vtk_polydata(binary, tmp):
    """Surfaces VTK's vtkPolyDataWriter makes (DATASET POLYDATA: the 5.1
    OFFSETS/CONNECTIVITY layout and 4.2's, ASCII and binary, quadrilaterals,
    triangle strips, a cell array "face") meshed by vdmesh: its tetrahedra fill
    the volume VTK's vtkMassProperties gives the surface (--no-flips keeps
    the surface's shape), and the faces keep their ids and areas. Refused
    with "DATASET POLYDATA is not supported" until 2026-12-01."""
    import vtk
    from vtk.util.numpy_support import numpy_to_vtk, vtk_to_numpy

    def write(data, name, binary_file, version):
        if not binary_file:
            # Double coordinates in the text: VTK reads "float" text into
            # float32 where vdmesh keeps double, 3e-9 apart in volume.
            points = vtk.vtkPoints()
            points.SetDataTypeToDouble()
            points.SetNumberOfPoints(data.GetNumberOfPoints())
            for i in range(data.GetNumberOfPoints()):
                points.SetPoint(i, data.GetPoint(i))
            copy = vtk.vtkPolyData()
            copy.DeepCopy(data)
            copy.SetPoints(points)
            data = copy
        w = vtk.vtkPolyDataWriter()
        w.SetInputData(data)
        w.SetFileName(os.path.join(tmp, name))
        if binary_file:
            w.SetFileTypeToBinary()
        if version:
            w.SetFileVersion(version)
        w.Write()
        return os.path.join(tmp, name)

    sphere = vtk_sphere()
    strips = vtk.vtkStripper()
    strips.SetInputData(sphere)
    strips.Update()
    # A 1 x 2 x 3 box of 6 quadrilaterals, face ids 1..6 in a cell array.
    cube = vtk.vtkCubeSource()
    cube.SetXLength(1)
    cube.SetYLength(2)
    cube.SetZLength(3)
    cube.Update()
    box = cube.GetOutput()
    ids = numpy_to_vtk(np.arange(1, 7, dtype=np.int32), deep=True)
    ids.SetName("face")
    box.GetCellData().AddArray(ids)
    cases = [(sphere, "sphere"), (strips.GetOutput(), "sphere_strips"), (box, "box")]
    check(strips.GetOutput().GetNumberOfStrips() > 0, "vtkStripper made triangle strips")
    for data, stem in cases:
        for binary_file, version in ((False, 0), (True, 0), (False, 42), (True, 42)):
            name = "%s_%s%s.vtk" % (stem, "bin" if binary_file else "ascii", "_v42" if version else "")
            path = write(data, name, binary_file, version)
            volume = vtk_enclosed_volume(vtk.vtkPolyDataReader, path)
            out = mesh_keeping_surface(binary, path)
            if out is None:
                continue
            points, types, conn, offsets, cell_data, tets = read_vtu_with_vtk(out)
            got = float(signed_volumes(points, tets).sum())
            check(abs(got - volume) <= 1e-9 * volume,
                  "%s: tetrahedra fill %.9g, VTK's volume of the surface %.9g" % (name, got, volume))
            if stem != "box":
                continue
            faces = vtk_to_numpy(cell_data.GetArray("face"))
            areas = {}
            for i in np.where(types == 5)[0]:
                a, b, c = points[conn[offsets[i]:offsets[i + 1]]]
                areas[int(faces[i])] = areas.get(int(faces[i]), 0.0) + 0.5 * np.linalg.norm(np.cross(b - a, c - a))
            want = sorted([2.0, 2.0, 3.0, 3.0, 6.0, 6.0])
            check(sorted(areas) == [1, 2, 3, 4, 5, 6] and np.allclose(sorted(areas.values()), want, rtol=1e-12),
                  "%s: faces 1..6 keep their areas (%s)" % (name, {k: round(v, 9) for k, v in sorted(areas.items())}))


def check_ply(binary, tmp):
    """Stanford PLY both ways. In: a sphere written by VTK's vtkPLYWriter
    (binary, float, both byte orders) and by meshio (ASCII and binary, double), meshed with
    --no-flips: the tetrahedra fill the volume VTK's vtkMassProperties or
    numpy over meshio's reading gives the file. Out: vdmesh's PLY of a tagged
    two-region surface read by VTK (counts) and meshio (ASCII: the face,
    front and back properties; meshio 5.0 reads a binary face element column
    by column and fails on any that has more than its list)."""
    import meshio
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy

    def mesh(path):
        out = mesh_keeping_surface(binary, path)
        if out is None:
            return None
        points, _, _, _, _, tets = read_vtu_with_vtk(out)
        return float(signed_volumes(points, tets).sum())

    sphere = vtk_sphere()
    for order in ("little", "big"):
        vtk_ply = os.path.join(tmp, "sphere_vtk_%s.ply" % order)
        writer = vtk.vtkPLYWriter()
        writer.SetInputData(sphere)
        writer.SetFileName(vtk_ply)
        writer.SetFileTypeToBinary()
        if order == "big":
            writer.SetDataByteOrderToBigEndian()
        else:
            writer.SetDataByteOrderToLittleEndian()
        writer.Write()
        volume = vtk_enclosed_volume(vtk.vtkPLYReader, vtk_ply)
        got = mesh(vtk_ply)
        if got is not None:
            check(abs(got - volume) <= 1e-9 * volume,
                  "%s: tetrahedra fill %.10g, VTK's volume of the file %.10g" % (os.path.basename(vtk_ply), got, volume))
    points = vtk_to_numpy(sphere.GetPoints().GetData()).astype(np.float64)
    polys = vtk_to_numpy(sphere.GetPolys().GetConnectivityArray()).reshape(-1, 3).astype(np.int32)
    for name, binary_file in (("sphere_meshio_ascii.ply", False), ("sphere_meshio_binary.ply", True)):
        path = os.path.join(tmp, name)
        meshio.write(path, meshio.Mesh(points, [("triangle", polys)]), binary=binary_file)
        back = meshio.read(path)
        tris = back.cells_dict["triangle"]
        a, b, c = (back.points[tris[:, k]].astype(np.float64) for k in range(3))
        volume = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)
        got = mesh(path)
        if got is not None:
            check(abs(got - volume) <= 1e-9 * volume,
                  "%s: tetrahedra fill %.10g, the volume of meshio's reading %.10g" % (name, got, volume))
    # Out: a surface of two regions with face ids.
    src = os.path.join(tmp, "two.off")
    with open(src, "w") as f:
        # Two unit cubes side by side, x in [0, 1] and [1, 2]: 11 quadrilaterals, the one at x = 1 shared.
        f.write("OFF\n12 11 0\n")
        for x in (0, 1, 2):
            for y, z in ((0, 0), (1, 0), (1, 1), (0, 1)):
                f.write("%d %d %d\n" % (x, y, z))
        for q in ((0, 3, 2, 1), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7), (4, 5, 6, 7),
                  (4, 5, 9, 8), (5, 6, 10, 9), (6, 7, 11, 10), (7, 4, 8, 11), (8, 9, 10, 11)):
            f.write("4 %d %d %d %d\n" % q)
    tagged = os.path.join(tmp, "two.vtu")
    run = subprocess.run([binary, "mesh", src, "-o", tagged, "--quiet"], capture_output=True, text=True)
    check(run.returncode == 0, "vdmesh mesh two.off (exit %d %s)" % (run.returncode, run.stderr.strip()[:200]))
    if run.returncode != 0:
        return
    source = meshio.read(tagged)
    want = {k: np.concatenate([d for d, c in zip(source.cell_data[k], source.cells) if c.type == "triangle"])
            for k in ("face", "front", "back")}
    for name, flags in (("two.ply", []), ("two_binary.ply", ["--binary"])):
        path = os.path.join(tmp, name)
        run = subprocess.run([binary, "convert", tagged, path] + flags, capture_output=True, text=True)
        check(run.returncode == 0, "vdmesh convert two.vtu %s (exit %d %s)" % (name, run.returncode, run.stderr[:200]))
        if run.returncode != 0:
            continue
        reader = vtk.vtkPLYReader()
        reader.SetFileName(path)
        reader.Update()
        check(reader.GetOutput().GetNumberOfCells() == len(want["face"]),
              "VTK reads %s: %d triangles (%d written)" % (name, reader.GetOutput().GetNumberOfCells(),
                                                           len(want["face"])))
        if flags:
            continue
        back = meshio.read(path)
        same = all(np.array_equal(np.asarray(back.cell_data[k][0]).astype(int), want[k]) for k in want)
        check(same, "meshio reads %s: face, front and back of every triangle as written (regions %s)" %
              (name, sorted(set(want["front"].tolist()) | set(want["back"].tolist()))))


def main():
    binary = os.environ.get("VDMESH_BIN", "")
    if not binary or not os.access(binary, os.X_OK):
        print("skipped: VDMESH_BIN (the vdmesh CLI) not set or not built: %r" % binary)
        return 0
    pts, tets, regions, tris, face_ids = block_mesh()
    volume = float(N ** 3)
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "block.mesh")
        write_medit(src, pts, tets, regions, tris, face_ids)
        outputs = {}
        for ext in ("msh", "vtu", "vtk", "inp", "mesh", "node"):
            out = os.path.join(tmp, "out." + ext)
            run = subprocess.run([binary, "convert", src, out], capture_output=True, text=True)
            check(run.returncode == 0, "vdmesh convert block.mesh out.%s (exit %d %s)" %
                  (ext, run.returncode, run.stderr.strip()[:200]))
            if run.returncode == 0:
                outputs[ext] = out
        # The binary and MSH 2.2 variants, read by meshio and Gmsh.
        for name, flags in (("bin.msh", ["--binary"]), ("v22.msh", ["--msh-version", "22"]),
                            ("bin22.msh", ["--binary", "--msh-version", "22"]), ("bin.vtu", ["--binary"]),
                            ("bin.vtk", ["--binary"])):
            out = os.path.join(tmp, name)
            run = subprocess.run([binary, "convert", src, out] + flags, capture_output=True, text=True)
            check(run.returncode == 0, "vdmesh convert block.mesh %s %s (exit %d %s)" %
                  (name, " ".join(flags), run.returncode, run.stderr.strip()[:200]))
            if run.returncode != 0:
                continue
            ext = name.split(".")[-1]
            try:
                check_meshio(out, ext, len(tets), len(tris), volume)
            except Exception as e:
                check(False, "meshio %s raised %s: %s" % (name, type(e).__name__, e))
            if ext == "msh":
                check_gmsh(out, len(tets), volume, True)
            if ext in ("vtk", "vtu"):
                check_vtk(out, len(tets), volume)
        for ext, out in outputs.items():
            fmt = "tetgen" if ext == "node" else ext
            path = out[:-5] + ".ele" if ext == "node" else out
            try:
                check_meshio(path, fmt, len(tets), len(tris), volume)
            except Exception as e:  # a reader that raises is a failed check
                check(False, "meshio %s raised %s: %s" % (fmt, type(e).__name__, e))
        if "msh" in outputs:
            check_gmsh(outputs["msh"], len(tets), volume, True)
        if "vtk" in outputs:
            check_gmsh(outputs["vtk"], len(tets), volume, False)
        for ext in ("vtk", "vtu"):
            if ext in outputs:
                check_vtk(outputs[ext], len(tets), volume)
        if "vtu" in outputs:
            vols = signed_volumes(pts, tets)
            expected = {r: float(vols[np.array(regions) == r].sum()) for r in (1, 2)}
            check_reads_vtk_writers(binary, outputs["vtu"], tmp, len(tets), expected)
        if "inp" in outputs:
            check_calculix(outputs["inp"], tmp)
        check_reads_gmsh_and_meshio_files(binary, tmp)
        check_meshb_with_meshio(binary, tmp)
        check_plc_hole_point_in_a_thin_slot(binary, tmp)
        check_plc_keeps_regions_and_cavities(binary, tmp)
        check_convert_reorients_inverted_tetrahedra(binary, tmp)
        check_meshes_vtk_polydata(binary, tmp)
        check_ply(binary, tmp)
        if "msh" in outputs:
            gmsh_check = subprocess.run(["gmsh", outputs["msh"], "-check"], capture_output=True, text=True, cwd=tmp)
            check(gmsh_check.returncode == 0, "gmsh -check out.msh (exit %d)" % gmsh_check.returncode)
    print("%d check(s) failed" % len(FAILED) if FAILED else "all checks passed")
    return 1 if FAILED else 0


if __name__ == "__main__":
    sys.exit(main())
