"""Regenerates the fuzz seed corpus (tests/fuzz/corpus/) from one tiny mesh.

Usage: python3 make_corpus.py CONVERTER
CONVERTER is a program called as `CONVERTER IN OUT [binary] [22]` that
converts with vd::io (the dev helper in build folders does). Each seed is
the selector byte of its extension (see kExtensions in fuzz_readers.cpp)
followed by the file's bytes. seed_vtu_zlib and seed_vtu_appended are the
files tests/unit/converters_vtu_test.cpp writes, with the selector byte 5.
"""
import gzip
import os
import subprocess
import sys
import tempfile

EXTENSIONS = [".off", ".stl", ".obj", ".msh", ".vtk", ".vtu", ".node", ".poly", ".smesh", ".mesh", ".inp", ".off.gz"]

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


def main():
    converter = sys.argv[1]
    here = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
    os.makedirs(here, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "two.mesh")
        with open(src, "w") as f:
            f.write(TWO_TETS)
        variants = []
        for ext in [".off", ".stl", ".obj", ".vtk", ".vtu", ".smesh", ".poly", ".mesh", ".inp", ".msh"]:
            variants.append((ext, []))
        for ext in [".stl", ".vtk", ".vtu", ".msh"]:
            variants.append((ext, ["binary"]))
        variants += [(".msh", ["22"]), (".msh", ["binary", "22"]), (".node", [])]
        for ext, opts in variants:
            out = os.path.join(tmp, "out" + ext)
            subprocess.run([converter, src, out] + opts, check=True, capture_output=True)
            data = open(out, "rb").read()
            name = "seed_%s%s" % (ext.strip("."), "_" + "_".join(opts) if opts else "")
            with open(os.path.join(here, name), "wb") as f:
                f.write(bytes([EXTENSIONS.index(ext)]) + data)
        with open(os.path.join(here, "seed_poly_hole"), "wb") as f:
            f.write(bytes([EXTENSIONS.index(".poly")]) + HOLED_POLY.encode())
        off = open(os.path.join(tmp, "out.off"), "rb").read()
        with open(os.path.join(here, "seed_off_gz"), "wb") as f:
            f.write(bytes([EXTENSIONS.index(".off.gz")]) + gzip.compress(off))


if __name__ == "__main__":
    main()
