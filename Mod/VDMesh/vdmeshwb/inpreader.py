"""Reader of the Abaqus deck vdmesh writes (converters/formats/abaqus.cpp).

Understands: *NODE; *ELEMENT, TYPE=C3D4 (or C3D10), ELSET=<region> (one block per region);
*ELSET, ELSET=<name>; *SURFACE, NAME=<Face j>, TYPE=ELEMENT with lines "element, S1..S4";
*NSET, NSET=<name> (id lists, or names of earlier sets as FreeCAD writes them). Other keywords and
** comments are skipped.
"""

# C3D4 faces S1..S4 by corner (0-based), as in abaqus.cpp. On a positive tetrahedron
# (det(v1-v0, v2-v0, v3-v0) > 0) each of these triples has its right-hand normal pointing inwards.
TET_FACES = ((0, 1, 2), (0, 3, 1), (1, 3, 2), (2, 3, 0))
# C3D10: the mid-edge node of corners (i, j) is node TET10_MID[i, j] (0-based: 01, 12, 20, 03, 13, 23)
TET10_MID = {}
for _k, (_i, _j) in enumerate(((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3))):
    TET10_MID[_i, _j] = TET10_MID[_j, _i] = 4 + _k


class InpMesh:
    def __init__(self):
        self.nodes = {}      # id -> (x, y, z)
        self.elements = {}   # id -> tuple of node ids (4 or 10), Abaqus order
        self.elsets = {}     # name -> [element ids], in file order
        self.surfaces = {}   # name -> [(element id, face index 0..3)]
        self.nsets = {}      # name -> [node ids]

    def face_nodes(self, element, face, outward=True):
        """Node ids of a tetrahedron face: 3 corners, then for C3D10 the mid-edge nodes of the edges
        corner1-corner2, corner2-corner3, corner3-corner1. outward=True: normal out of the element."""
        e = self.elements[element]
        i, j, k = TET_FACES[face]
        if outward:
            j, k = k, j
        corners = (i, j, k)
        if len(e) == 4:
            return tuple(e[c] for c in corners)
        return tuple(e[c] for c in corners) + tuple(e[TET10_MID[corners[m], corners[(m + 1) % 3]]] for m in range(3))


def _options(line):
    parts = [p.strip() for p in line.split(",")]
    name = parts[0][1:].strip().upper()
    opts = {}
    for p in parts[1:]:
        if "=" in p:
            k, v = p.split("=", 1)
            opts[k.strip().upper()] = v.strip()
        elif p:
            opts[p.upper()] = ""
    return name, opts


def read_inp(path):
    m = InpMesh()
    mode, target, pending = None, None, []
    with open(path) as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.strip()
            if not line or line.startswith("**"):
                continue
            if line.startswith("*"):
                name, opts = _options(line)
                mode, target = None, None
                if name == "NODE":
                    mode = "node"
                    target = opts.get("NSET")
                    if target:
                        m.nsets.setdefault(target, [])
                elif name == "ELEMENT":
                    etype = opts.get("TYPE", "").upper()
                    if etype not in ("C3D4", "C3D10"):
                        mode = "skip"
                        continue
                    mode = "element"
                    target = opts.get("ELSET")
                    if target:
                        m.elsets.setdefault(target, [])
                elif name == "ELSET":
                    mode, target = "elset", opts.get("ELSET")
                    m.elsets.setdefault(target, [])
                elif name == "NSET":
                    mode, target = "nset", opts.get("NSET")
                    m.nsets.setdefault(target, [])
                elif name == "SURFACE":
                    mode, target = "surface", opts.get("NAME")
                    m.surfaces.setdefault(target, [])
                else:
                    mode = "skip"
                continue
            if mode in (None, "skip"):
                continue
            fields = [x.strip() for x in line.split(",") if x.strip()]
            try:
                if mode == "node":
                    nid = int(fields[0])
                    m.nodes[nid] = (float(fields[1]), float(fields[2]), float(fields[3]))
                    if target:
                        m.nsets[target].append(nid)
                elif mode == "element":
                    # an element line may continue on the next line (C3D10: 11 numbers)
                    pending += [int(x) for x in fields]
                    if raw.rstrip().endswith(","):
                        continue
                    eid, conn = pending[0], tuple(pending[1:])
                    pending = []
                    if len(conn) not in (4, 10):
                        raise ValueError("element %d has %d nodes" % (eid, len(conn)))
                    m.elements[eid] = conn
                    if target:
                        m.elsets[target].append(eid)
                elif mode in ("elset", "nset"):
                    sets = m.elsets if mode == "elset" else m.nsets
                    for x in fields:  # Abaqus allows names of earlier sets among the ids
                        sets[target].extend([int(x)] if x.lstrip("-").isdigit() else sets.get(x, []))
                elif mode == "surface":
                    face = fields[1].upper()
                    if face not in ("S1", "S2", "S3", "S4"):
                        raise ValueError("tetrahedron faces are S1..S4, not %r" % fields[1])
                    m.surfaces[target].append((int(fields[0]), int(face[1]) - 1))
            except (ValueError, IndexError) as e:
                raise ValueError("%s:%d: %s (%s)" % (path, lineno, e, line[:60]))
    return m
