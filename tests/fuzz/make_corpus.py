"""Regenerates the fuzz seed corpus (tests/fuzz/corpus/<target>/) from one tiny mesh.

Usage: /usr/bin/python3 make_corpus.py VDMESH
VDMESH is the vdmesh program (build/bin/vdmesh); seeds are written by
`vdmesh convert`. One folder per fuzz target (tests/fuzz/targets.cmake); a
seed is the file's bytes as is, except for the "tetgen" target, whose inputs
are X.node, X.ele and X.face joined by NUL bytes (see fuzz_reader.cpp).
Seeds not made here stay: vtu/seed_vtu_zlib and vtu/seed_vtu_appended are the
files tests/unit/converters_vtu_test.cpp writes, and crash-* seeds are inputs
that once crashed a reader.
"""
import gzip
import os
import shutil
import struct
import subprocess
import sys
import tempfile

TWO_TETS = """MeshVersionFormatted 2
Dimension 3
Vertices
5
0 0 0 0
1 0 0 0
0 1 0 0
0 0 1 0
1 1 1 0
Triangles
3
1 3 2 1
2 3 4 2
2 5 3 3
Tetrahedra
2
1 2 3 4 1
2 3 4 5 2
End
"""

HOLED_POLY = """8 3 0 0
1 0 0 0
2 4 0 0
3 4 4 0
4 0 4 0
5 1 1 0
6 3 1 0
7 3 3 0
8 1 3 0
1 1
2 1 5
4 1 2 3 4
4 5 6 7 8
1 2 2 0
0
"""


def convert(vdmesh, src, out, opts):
    subprocess.run([vdmesh, "convert", src, out] + opts, check=True, capture_output=True)


def main():
    vdmesh = sys.argv[1]
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")

    def seed(target, name, data):
        os.makedirs(os.path.join(here, target), exist_ok=True)
        with open(os.path.join(here, target, name), "wb") as f:
            f.write(data)

    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "two.mesh")
        with open(src, "w") as f:
            f.write(TWO_TETS)
        variants = [(ext, []) for ext in [".off", ".stl", ".obj", ".ply", ".vtk", ".vtu", ".smesh", ".poly", ".mesh", ".meshb", ".inp", ".msh"]]
        variants += [(ext, ["--binary"]) for ext in [".stl", ".ply", ".vtk", ".vtu", ".msh"]]
        variants += [(".msh", ["--msh-version", "22"]), (".msh", ["--binary", "--msh-version", "22"])]
        for ext, opts in variants:
            out = os.path.join(tmp, "out" + ext)
            convert(vdmesh, src, out, opts)
            suffix = "".join("_" + o.strip("-").replace("msh-version", "") for o in opts if o != "--msh-version")
            seed(ext.strip("."), "seed_%s%s" % (ext.strip("."), suffix), open(out, "rb").read())
        seed("poly", "seed_poly_hole", HOLED_POLY.encode())
        seed("gz", "seed_off_gz", gzip.compress(open(os.path.join(tmp, "out.off"), "rb").read(), mtime=0))
        # TetGen: with and without the .face part, and first and second order.
        base = os.path.join(tmp, "tg")
        convert(vdmesh, src, base + ".node", [])
        parts = [open(base + ext, "rb").read() for ext in (".node", ".ele", ".face")]
        seed("tetgen", "seed_node_ele_face", b"\0".join(parts))
        seed("tetgen", "seed_node_ele", b"\0".join(parts[:2]))
        seed("tetgen", "seed_node_only", parts[0])
        # Second order from the real program: 10-node .ele, 3-node hull .face.
        if shutil.which("tetgen"):
            with open(os.path.join(tmp, "five.node"), "w") as f:
                f.write("5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n")
            subprocess.run(["tetgen", "-o2Q", "five.node"], cwd=tmp, check=True, capture_output=True)
            parts = [open(os.path.join(tmp, "five.1" + ext), "rb").read() for ext in (".node", ".ele", ".face")]
            seed("tetgen", "seed_tetgen_o2", b"\0".join(parts))
        else:
            print("make_corpus: tetgen not found, seed_tetgen_o2 not made", file=sys.stderr)
        # Legacy VTK with the names array in the data set's field data.
        names = b"region 1 Solid1\n"
        field = b"FIELD FieldData 1\nvdmesh_names 1 %d unsigned_char\n" % len(names)
        for suffix, values in (("", " ".join(str(b) for b in names).encode() + b"\n"), ("_binary", names + b"\n")):
            convert(vdmesh, src, os.path.join(tmp, "names.vtk"), ["--binary"] if suffix else [])
            vtk_file = open(os.path.join(tmp, "names.vtk"), "rb").read()
            seed("vtk", "seed_vtk_names" + suffix,
                 vtk_file.replace(b"DATASET UNSTRUCTURED_GRID\n", b"DATASET UNSTRUCTURED_GRID\n" + field + values, 1))
        # VTU as VTK writes it: LZ4, LZMA, big-endian, three pieces; and
        # vdmesh's names array (FieldData). Made by Debian's python3-vtk9.
        vtu = open(os.path.join(tmp, "out.vtu"), "rb").read()
        seed("vtu", "seed_vtu_names", vtu.replace(b"  <UnstructuredGrid>\n", b"  <UnstructuredGrid>\n    <FieldData>\n"
             b"      <DataArray type=\"UInt8\" Name=\"vdmesh_names\" NumberOfTuples=\"16\" format=\"ascii\">\n"
             + " ".join(str(b) for b in b"region 1 Solid1\n").encode() + b"\n      </DataArray>\n    </FieldData>\n", 1))
        try:
            import vtk
        except ImportError:
            print("make_corpus: no python3-vtk9, VTK's VTU variants not made", file=sys.stderr)
            return
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(os.path.join(tmp, "out.vtu"))
        reader.Update()
        for name, setup in (("lz4", lambda w: w.SetCompressorTypeToLZ4()),
                            ("lzma", lambda w: w.SetCompressorTypeToLZMA()),
                            ("big_endian", lambda w: (w.SetByteOrderToBigEndian(), w.SetDataModeToBinary())),
                            ("pieces", lambda w: (w.SetNumberOfPieces(3), w.SetDataModeToAscii()))):
            writer = vtk.vtkXMLUnstructuredGridWriter()
            writer.SetInputData(reader.GetOutput())
            writer.SetFileName(os.path.join(tmp, name + ".vtu"))
            setup(writer)
            writer.Write()
            seed("vtu", "seed_vtu_" + name, open(os.path.join(tmp, name + ".vtu"), "rb").read())
        # Legacy POLYDATA as VTK writes it: a box of quadrilaterals with a
        # cell array, and a small sphere in triangle strips; 5.1 and 4.2
        # layouts, ASCII and binary.
        cube = vtk.vtkCubeSource()
        cube.Update()
        box = cube.GetOutput()
        faces = vtk.vtkIntArray()
        faces.SetName("face")
        for i in range(box.GetNumberOfCells()):
            faces.InsertNextValue(i + 1)
        box.GetCellData().AddArray(faces)
        sphere = vtk.vtkSphereSource()
        sphere.SetThetaResolution(6)
        sphere.SetPhiResolution(4)
        strips = vtk.vtkStripper()
        strips.SetInputConnection(sphere.GetOutputPort())
        strips.Update()
        for stem, data in (("box", box), ("strips", strips.GetOutput())):
            for suffix, binary, version in (("", False, 0), ("_binary", True, 0), ("_42", False, 42)):
                writer = vtk.vtkPolyDataWriter()
                writer.SetInputData(data)
                path = os.path.join(tmp, stem + suffix + ".vtk")
                writer.SetFileName(path)
                if binary:
                    writer.SetFileTypeToBinary()
                if version:
                    writer.SetFileVersion(version)
                writer.Write()
                seed("vtk", "seed_vtk_polydata_" + stem + suffix, open(path, "rb").read())
        # PLY as VTK writes it: big-endian binary, and ASCII.
        for name, setup in (("big_endian", lambda w: (w.SetFileTypeToBinary(), w.SetDataByteOrderToBigEndian())),
                            ("vtk_ascii", lambda w: w.SetFileTypeToASCII())):
            writer = vtk.vtkPLYWriter()
            writer.SetInputData(strips.GetOutput())
            path = os.path.join(tmp, name + ".ply")
            writer.SetFileName(path)
            setup(writer)
            writer.Write()
            seed("ply", "seed_ply_" + name, open(path, "rb").read())
    # PLY triangle strips (old scanner files): a unit cube, -1 between
    # strips, ASCII and big-endian binary.
    corners = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    strip = [0, 3, 1, 2, -1, 4, 5, 7, 6, -1, 0, 1, 4, 5, -1, 3, 7, 2, 6, -1, 0, 4, 3, 7, 7, 1, 1, 2, 5, 6]
    for name, fmt in (("tristrips", "ascii"), ("tristrips_big_endian", "binary_big_endian")):
        head = ("ply\nformat %s 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
                "element tristrips 1\nproperty list int int vertex_indices\nend_header\n" % fmt).encode()
        if fmt == "ascii":
            body = "".join("%d %d %d\n" % c for c in corners) + " ".join(map(str, [len(strip)] + strip)) + "\n"
            seed("ply", "seed_ply_" + name, head + body.encode())
        else:
            body = b"".join(struct.pack(">3f", *c) for c in corners) + struct.pack(">%di" % (len(strip) + 1), len(strip), *strip)
            seed("ply", "seed_ply_" + name, head + body)


if __name__ == "__main__":
    main()
