"""Shared by the CAD command-line tests (test_cad.py, test_cad_plane.py):
a run with its report, and the tetrahedra read back by meshio."""
import json
import os

import numpy as np

from cli_support import check, run, tmpdir

out = tmpdir()


def mesh_as(name, path, *extra, timeout=600):
    """Meshes path to NAME.vtu with its report NAME.json; gives the exit
    code, the report (None unless exit 0), the mesh's path and stderr."""
    target = os.path.join(out, name + ".vtu")
    report = os.path.join(out, name + ".json")
    code, stdout, stderr = run("mesh", path, "-o", target, "--report", report, *extra, timeout=timeout)
    rep = json.load(open(report)) if code == 0 else None
    return code, rep, target, stderr


def tet_volumes(m):
    tets = m.cells_dict["tetra"]
    p = m.points[tets]
    return np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0]) / 6.0


def tets_in_solids(path, solids, name):
    """Tetrahedron volumes and regions of the mesh (meshio), checked: all
    positive, in the regions 1..solids."""
    import meshio
    m = meshio.read(path)
    vol = tet_volumes(m)
    region = [np.asarray(v) for b, v in zip(m.cells, m.cell_data["region"]) if b.type == "tetra"][0]
    check(len(vol) > 0 and vol.min() > 0 and sorted(set(region.tolist())) == list(range(1, solids + 1)),
          "%s: %d tetrahedra, all positive, in the %d solids (meshio)" % (name, len(vol), solids))
    return vol, region
