"""A CalculiX static analysis through FreeCAD's own FEM machinery, on any mesh object of a part.

The part: a cantilever 40 x 10 x 10 made of two solids (a BooleanFragments of two boxes 20 x 10 x 10
touching at x = 20), the first with a hole of diameter 5 across it (axis along y through x = 10,
z = 5). Solid1 is steel, Solid2 aluminium (one material object per solid, referencing Solid<i>);
the face x = 0 is fixed, the top face of Solid2 (z = 10) carries a pressure of 1 MPa.

Everything goes through ObjectsFem and femtools.ccxtools.FemToolsCcx, as the FEM workbench's
"Solver CalculiX" does: analysis, ccxtools solver, materials, constraints, mesh object, run, result
object.
"""
import time

import FreeCAD
from FreeCAD import Vector

LENGTH, WIDTH, HEIGHT = 40.0, 10.0, 10.0
HOLE_X, HOLE_Z, HOLE_R = 10.0, 5.0, 2.5
MATERIALS = (("Steel", "210000 MPa", "0.30"), ("Aluminium", "70000 MPa", "0.33"))
PRESSURE = 1.0  # MPa
# points where von Mises stress is compared: in the aluminium half, away from the load and supports,
# and in the steel half between the hole and the top face
POINTS = {"P_alu": (30.0, 5.0, 2.0), "P_steel_over_hole": (10.0, 5.0, 8.75)}


def make_part(doc):
    """The BooleanFragments of the two halves (Part features, so that it recomputes headless)."""
    import BOPTools.SplitFeatures
    import Part
    left = doc.addObject("Part::Feature", "SteelHalf")
    left.Shape = Part.makeBox(LENGTH / 2, WIDTH, HEIGHT).cut(
        Part.makeCylinder(HOLE_R, WIDTH + 2, Vector(HOLE_X, -1, HOLE_Z), Vector(0, 1, 0))).Solids[0]
    right = doc.addObject("Part::Feature", "AluminiumHalf")
    right.Shape = Part.makeBox(LENGTH / 2, WIDTH, HEIGHT, Vector(LENGTH / 2, 0, 0))
    doc.recompute()
    bf = BOPTools.SplitFeatures.makeBooleanFragments(name="Cantilever")
    bf.Objects = [left, right]
    bf.Mode = "Standard"
    doc.recompute()
    if len(bf.Shape.Solids) != 2:
        raise RuntimeError("the cantilever should have 2 solids, has %d" % len(bf.Shape.Solids))
    return bf


def solid_name(shape, pred):
    """Solid<i> of the solid whose centre of mass satisfies pred."""
    names = ["Solid%d" % i for i, s in enumerate(shape.Solids, 1) if pred(s.CenterOfMass)]
    if len(names) != 1:
        raise RuntimeError("expected one solid, found %s" % names)
    return names[0]


def face_name(shape, pred):
    """Face<j> of the planar face whose centre of mass satisfies pred."""
    names = ["Face%d" % j for j, f in enumerate(shape.Faces, 1)
             if f.Surface.__class__.__name__ == "Plane" and pred(f.CenterOfMass)]
    if len(names) != 1:
        raise RuntimeError("expected one face, found %s" % names)
    return names[0]


def make_analysis(doc, part, tag):
    """Analysis with solver, one material per solid, fixed face and pressure; returns (analysis, solver)."""
    import ObjectsFem
    shape = part.Shape
    analysis = ObjectsFem.makeAnalysis(doc, "Analysis" + tag)
    solver = ObjectsFem.makeSolverCalculixCcxTools(doc, "CalculiX" + tag)
    solver.AnalysisType = "static"
    solver.GeometricalNonlinearity = "linear"
    analysis.addObject(solver)
    for (name, young, poisson), half in zip(MATERIALS, (lambda c: c.x < LENGTH / 2, lambda c: c.x > LENGTH / 2)):
        m = ObjectsFem.makeMaterialSolid(doc, name + tag)
        mat = m.Material
        mat["Name"], mat["YoungsModulus"], mat["PoissonRatio"] = name, young, poisson
        m.Material = mat
        m.References = [(part, solid_name(shape, half))]
        analysis.addObject(m)
    fixed = ObjectsFem.makeConstraintFixed(doc, "Fixed" + tag)
    fixed.References = [(part, face_name(shape, lambda c: abs(c.x) < 1e-6))]
    analysis.addObject(fixed)
    load = ObjectsFem.makeConstraintPressure(doc, "Pressure" + tag)
    load.References = [(part, face_name(shape, lambda c: abs(c.z - HEIGHT) < 1e-6 and c.x > LENGTH / 2))]
    load.Pressure = PRESSURE
    analysis.addObject(load)
    return analysis, solver


def gmsh_mesh(doc, part, size, order, tag):
    """FreeCAD's Gmsh mesh object (FemMeshGmsh) of the part at a maximum element size."""
    import ObjectsFem
    from femmesh.gmshtools import GmshTools
    obj = ObjectsFem.makeMeshGmsh(doc, "Gmsh" + tag)
    obj.Part = part
    obj.CharacteristicLengthMax = size
    obj.ElementOrder = "2nd" if order == 2 else "1st"
    obj.SecondOrderLinear = False
    doc.recompute()
    error = GmshTools(obj).create_mesh()
    if error:
        raise RuntimeError("Gmsh failed: %s" % error)
    return obj


def run_ccx(analysis, solver, mesh_obj):
    """Runs CalculiX on mesh_obj; returns a dict of figures (max displacement, von Mises at POINTS)."""
    from femtools import ccxtools
    if mesh_obj not in analysis.Group:
        analysis.addObject(mesh_obj)
    analysis.Document.recompute()
    t = time.time()
    fea = ccxtools.FemToolsCcx(analysis, solver)
    fea.update_objects()
    fea.setup_working_dir()
    if not fea.run():
        raise RuntimeError("CalculiX did not run through FemToolsCcx (see the report view)")
    results = [o for o in analysis.Group if o.isDerivedFrom("Fem::FemResultObject")]
    if not results:
        raise RuntimeError("CalculiX ran but FreeCAD loaded no result object")
    r = results[0]
    fm = mesh_obj.FemMesh
    figures = {"nodes": fm.NodeCount, "tetrahedra": fm.VolumeCount,
               "nodes_per_tetrahedron": len(fm.getElementNodes(fm.Volumes[0])),
               "max_displacement": max(r.DisplacementLengths), "ccx_seconds": time.time() - t,
               "inp_file": fea.inp_file_name}
    von_mises = dict(zip(r.NodeNumbers, r.vonMises))
    for name, p in POINTS.items():
        figures[name] = interpolate(fm, von_mises, p)
    return figures


def _barycentric(p, q):
    """Barycentric coordinates of q in the tetrahedron p[0..3] (Cramer's rule)."""
    def det(a, b, c):
        return (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
    e = [[p[k][i] - p[0][i] for i in range(3)] for k in (1, 2, 3)]
    d = [q[i] - p[0][i] for i in range(3)]
    v = det(*e)
    if v == 0:
        return None
    l1, l2, l3 = det(d, e[1], e[2]) / v, det(e[0], d, e[2]) / v, det(e[0], e[1], d) / v
    return (1 - l1 - l2 - l3, l1, l2, l3)


# mid-edge nodes of a 10-node tetrahedron in FemMesh order: corners (i, j) of nodes 4..9
_MID = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))


def interpolate(fm, values, q):
    """The nodal field `values` (node id -> value) at point q, with the element's shape functions
    (linear, or quadratic for 10-node tetrahedra)."""
    nodes = fm.Nodes
    lo, hi = [c - 1e-9 for c in q], [c + 1e-9 for c in q]
    for e in fm.Volumes:
        c = fm.getElementNodes(e)
        p = [nodes[n] for n in c[:4]]
        if any(min(v[i] for v in p) > hi[i] or max(v[i] for v in p) < lo[i] for i in range(3)):
            continue
        b = _barycentric(p, q)
        if b is None or min(b) < -1e-9:
            continue
        if len(c) == 4:
            return sum(b[k] * values[c[k]] for k in range(4))
        value = sum(b[k] * (2 * b[k] - 1) * values[c[k]] for k in range(4))
        return value + sum(4 * b[i] * b[j] * values[c[4 + m]] for m, (i, j) in enumerate(_MID))
    raise RuntimeError("point %s is in no element" % (q,))
