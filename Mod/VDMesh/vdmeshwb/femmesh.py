"""Builds a Fem.FemMesh from vdmesh's deck, with the groups FreeCAD FEM uses.

Groups (named like FreeCAD's Gmsh mesher names a physical group <Name>):
  Solid<i>_Volumes, Solid<i>_Nodes  per solid (region) i
  Face<j>_Faces, Face<j>_Nodes      per CAD face j (triangle face elements are added for them)

Orientation: vdmesh writes positive tetrahedra (det(v1-v0, v2-v0, v3-v0) > 0, as Abaqus); a FemMesh
(SMESH) stores them negative and its Abaqus writer swaps the first two nodes, so the first two nodes
are swapped here (for C3D10 with their mid-edge nodes). Face triangles (6-node ones for C3D10) are
added with their normal pointing out of the tetrahedron that owns them (for an outer face: out of the
part).
"""
import Fem


def signed_volume6(p0, p1, p2, p3):
    a = [p1[i] - p0[i] for i in range(3)]
    b = [p2[i] - p0[i] for i in range(3)]
    c = [p3[i] - p0[i] for i in range(3)]
    return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
            + a[2] * (b[0] * c[1] - b[1] * c[0]))


# Abaqus (positive) node order -> FemMesh (negative) node order, and back: swapping corners 0 and 1
# swaps the mid-edge nodes of 12 / 02 and of 13 / 03 too (Abaqus C3D10: 01 12 20 03 13 23).
# The permutation is its own inverse.
TET4_SWAP = (1, 0, 2, 3)
TET10_SWAP = (1, 0, 2, 3, 4, 6, 5, 8, 7, 9)


def swap_orientation(nodes):
    order = TET4_SWAP if len(nodes) == 4 else TET10_SWAP
    return [nodes[i] for i in order]


def to_femmesh(inp):
    """inp: inpreader.InpMesh. Returns (Fem.FemMesh, info dict)."""
    fm = Fem.FemMesh()
    for nid in sorted(inp.nodes):
        x, y, z = inp.nodes[nid]
        fm.addNode(x, y, z, nid)
    for eid in sorted(inp.elements):
        fm.addVolume(swap_orientation(inp.elements[eid]), eid)
    next_id = max(inp.elements) + 1 if inp.elements else 1
    info = {"solids": [], "faces": []}
    for name, elems in sorted(inp.elsets.items(), key=lambda kv: _natural(kv[0])):
        elems = [e for e in elems if e in inp.elements]
        if not elems:
            continue
        gv = fm.addGroup(name + "_Volumes", "Volume")
        fm.addGroupElements(gv, elems)
        nodes = sorted({n for e in elems for n in inp.elements[e]})
        gn = fm.addGroup(name + "_Nodes", "Node")
        fm.addGroupElements(gn, nodes)
        info["solids"].append(name)
    for name, faces in sorted(inp.surfaces.items(), key=lambda kv: _natural(kv[0])):
        ids = []
        for eid, k in faces:
            fm.addFace(list(inp.face_nodes(eid, k, outward=True)), next_id)
            ids.append(next_id)
            next_id += 1
        gf = fm.addGroup(name + "_Faces", "Face")
        fm.addGroupElements(gf, ids)
        nodes = inp.nsets.get(name + "_Nodes") or sorted({n for eid, k in faces for n in inp.face_nodes(eid, k)})
        gn = fm.addGroup(name + "_Nodes", "Node")
        fm.addGroupElements(gn, sorted(nodes))
        info["faces"].append(name)
    return fm, info


def _natural(name):
    head = name.rstrip("0123456789")
    tail = name[len(head):]
    return (head, int(tail) if tail else -1)


def group_ids(femmesh):
    """{group name: group id}"""
    return {femmesh.getGroupName(g): g for g in femmesh.Groups}


def tet_volumes(femmesh, element_ids=None):
    """Sum of |volume| of the 4-node tetrahedra (FemMesh.Volume is 0 for them); also returns the
    number of tetrahedra with FemMesh's (negative) orientation."""
    nodes = femmesh.Nodes
    total, negative, count = 0.0, 0, 0
    for e in (element_ids if element_ids is not None else femmesh.Volumes):
        c = femmesh.getElementNodes(e)
        p = [nodes[n] for n in c[:4]]
        v6 = signed_volume6(*p)
        negative += v6 < 0
        total += abs(v6) / 6.0
        count += 1
    return total, negative, count
