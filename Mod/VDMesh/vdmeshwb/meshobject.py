"""The vdmesh mesh object: a Fem::FemMeshObjectPython linked to a Part, parameters as properties.

Meshing happens before anything is added to the document: when vdmesh fails (bad geometry: exit 3,
unrecoverable facets: exit 4, ...) `create_mesh` raises VDMeshError and the document is unchanged.
Recompute re-runs vdmesh with the current properties.
"""
import contextlib
import hashlib
import json
import math
import os
import re
import shutil
import tempfile

import FreeCAD

from . import engine, femmesh, inpreader

TYPE = "Fem::FemMeshObjectPython"
ORACLES = ["dt", "lp", "sphere"]
# the values of FreeCAD's Gmsh mesh object's ElementOrder, so that both objects read alike
ELEMENT_ORDERS = ["1st", "2nd"]
# the temporary folders that keep each run's deck for Export (apply_result)
KEEP_PREFIX = "vdmesh-keep-"


def _add(obj, ptype, name, group, doc, value=None):
    if name not in obj.PropertiesList:
        obj.addProperty(ptype, name, group, doc)
        if value is not None:
            setattr(obj, name, value)


def params_of(obj):
    return engine.Parameters(size=obj.Size.Value if hasattr(obj.Size, "Value") else float(obj.Size),
                             interior=obj.Interior, flips=obj.Flips,
                             ridge_angle=float(getattr(obj.RidgeAngle, "Value", obj.RidgeAngle)),
                             oracle=obj.Oracle, lp_limit=obj.LPLimit,
                             # Documents saved when the panel went to 90: the mesher takes at most 70.5.
                             sliver_angle=min(70.5, float(getattr(obj.SliverAngle, "Value", obj.SliverAngle))),
                             seed=obj.Seed, order=ELEMENT_ORDERS.index(obj.ElementOrder) + 1)


def shape_of(part):
    if part is None:
        raise engine.VDMeshError("no part linked")
    shape = getattr(part, "Shape", None)
    if shape is None or shape.isNull():
        raise engine.VDMeshError("%s has no shape" % part.Label)
    return shape


class PartGone(engine.VDMeshError):
    """The part (or the mesh object a run is for) was deleted, or its document closed, while meshing:
    the run was stopped and nothing was made."""

    def __init__(self, label):
        super().__init__("%s was deleted, or its document closed, while meshing: meshing stopped" % label)


def is_alive(obj):
    """Whether obj is still in an open document (a deleted object raises ReferenceError, one kept
    for undo RuntimeError)."""
    if obj is None:
        return False
    try:
        doc = obj.Document
        return doc is not None and doc.getObject(obj.Name) is not None
    except (ReferenceError, RuntimeError):
        return False


def watching(idle, gone_label, cancel, gone):
    """idle, then a check that the watched objects are still there (gone_label: the label of one
    that is not, else None): the GUI's event loop runs while meshing, and a user may delete the
    part or close its document meanwhile (the run went on to its end, then failed with a
    ReferenceError and left its folder, and the panel stayed). gone gets the label."""
    def run():
        idle()
        if not gone:
            label = gone_label()
            if label is not None:
                gone.append(label)
                cancel.set()
    return run


def run_mesh(part, params, cancel=None, idle=None, watch=()):
    """Meshes part's shape; returns (FemMesh, info, inp path, report dict, report text).
    info["inputs"] is mesh_inputs of the shape meshed, taken before meshing: the part may change
    while idle runs. cancel, idle: see engine.mesh_shape; with idle, a deleted part or watch object
    stops the run (PartGone)."""
    if part is None:
        raise engine.VDMeshError("no part linked")
    if not is_alive(part):
        raise PartGone("the part")
    label = part.Label
    watched = [part] + list(watch)
    labels = [o.Label for o in watched]

    def gone_label():
        """The label of the first watched object gone (the part, or the mesh object remeshed)."""
        return next((l for o, l in zip(watched, labels) if not is_alive(o)), None)

    shape = shape_of(part)
    key = inputs_of_shape(shape, params)
    gone = []
    if idle is not None:
        cancel = cancel or engine.CancelRequest()
        idle = watching(idle, gone_label, cancel, gone)
    try:
        inp, report, text = engine.mesh_shape(shape, params, cancel=cancel, idle=idle, name=label)
    except engine.VDMeshCancelled:
        if gone:
            raise PartGone(gone[0])
        raise
    try:
        label_gone = gone_label()
        if label_gone is not None:
            raise PartGone(label_gone)
        deck = inpreader.read_inp(inp)
        if not deck.elements:
            raise engine.VDMeshError("vdmesh wrote no tetrahedra for %s" % label)
        fm, info = femmesh.to_femmesh(deck)
    except BaseException:
        shutil.rmtree(os.path.dirname(inp), ignore_errors=True)  # nobody's now
        raise
    info["nodes"] = len(deck.nodes)
    info["tetrahedra"] = len(deck.elements)
    info["nodes_per_tetrahedron"] = max(len(c) for c in deck.elements.values())
    info["inputs"] = key
    return fm, info, inp, report, text


def set_params(obj, p):
    """The mesh object's properties from Parameters p."""
    obj.Size, obj.Interior, obj.Flips, obj.RidgeAngle = p.size, p.interior, p.flips, p.ridge_angle
    obj.Oracle, obj.LPLimit, obj.SliverAngle, obj.Seed = p.oracle, p.lp_limit, p.sliver_angle, p.seed
    obj.ElementOrder = ELEMENT_ORDERS[p.order - 1]


class VDMeshObject:
    """Proxy of the mesh object."""

    def __init__(self, obj, params=None):
        obj.Proxy = self
        self.Type = "Fem::VDMesh"
        self.keep_folders = []  # see folders_made
        self.add_properties(obj, params or engine.Parameters())

    @staticmethod
    def add_properties(obj, p):
        _add(obj, "App::PropertyLink", "Part", "FEM Mesh", "Part, compound or BooleanFragments to mesh")
        _add(obj, "App::PropertyLength", "Size", "VDMesh", "Target edge length (0: bounding-box diagonal / 25)", p.size)
        _add(obj, "App::PropertyBool", "Interior", "VDMesh", "Interior vertices (off: surface vertices only)", p.interior)
        _add(obj, "App::PropertyBool", "Flips", "VDMesh", "Surface flips in Delaunayzation (off: splits only)", p.flips)
        _add(obj, "App::PropertyAngle", "RidgeAngle", "VDMesh", "Largest ridge angle a flip may create (--flip-angle)", p.ridge_angle)
        if "Oracle" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Oracle", "VDMesh", "Facet Delaunayhood oracle (LPLimit: lp)")
            obj.Oracle = ORACLES
            obj.Oracle = p.oracle
        _add(obj, "App::PropertyInteger", "LPLimit", "VDMesh", "Largest LP the lp oracle solves (0: no limit)", p.lp_limit)
        _add(obj, "App::PropertyAngle", "SliverAngle", "VDMesh", "Boundary slivers under this dihedral angle are removed", p.sliver_angle)
        _add(obj, "App::PropertyInteger", "Seed", "VDMesh", "Random seed: same part, options and seed give the same mesh", p.seed)
        if "ElementOrder" not in obj.PropertiesList:  # also added to objects saved before it existed
            obj.addProperty("App::PropertyEnumeration", "ElementOrder", "VDMesh",
                            "1st: 4-node tetrahedra; 2nd: 10-node tetrahedra (vdmesh --order 2)")
            obj.ElementOrder = ELEMENT_ORDERS
            obj.ElementOrder = ELEMENT_ORDERS[int(p.order) - 1]
        _add(obj, "App::PropertyFile", "OutputFile", "VDMesh", "vdmesh's Abaqus deck of the last run (used by Export)")
        _add(obj, "App::PropertyString", "Report", "VDMesh", "Report of the last run (JSON)")
        _add(obj, "App::PropertyString", "OutputDigest", "VDMesh", "SHA-256 of OutputFile as the last run wrote it")
        _add(obj, "App::PropertyLinkList", "Materials", "VDMesh",
             "The analysis's solid materials: a change of theirs renews the <Material>_Volumes groups")
        _add(obj, "App::PropertyString", "MeshInputs", "VDMesh",
             "What the last mesh was made from (shape, options), and what it was (counts, node checksum)")
        obj.setEditorMode("Report", 1)
        for hidden in ("OutputDigest", "Materials", "MeshInputs"):
            obj.setEditorMode(hidden, 2)

    def execute(self, obj):
        # Recompute: on failure the previous mesh stays and the error goes to the report view.
        if obj.Part is None:
            return
        try:
            key = mesh_inputs(obj.Part, params_of(obj))
            # The FemMesh counts too: undo restores the properties and MeshInputs but not the FemMesh.
            if not mesh_is_current(obj, key) or obj.FemMesh.VolumeCount == 0:
                fm, info, inp, report, text = run_mesh(obj.Part, params_of(obj))
                adopt_result(obj, fm, inp, report, info["inputs"])
            else:
                # Only a material changed (the mesh links them): its groups are renewed, the mesh kept.
                renew_material_groups(obj)
        except engine.VDMeshError as e:
            FreeCAD.Console.PrintError("VDMesh %s: %s\n" % (obj.Label, e.message))
            raise

    def onDocumentRestored(self, obj):
        self.add_properties(obj, engine.Parameters())

    def __getstate__(self):
        return {"Type": self.Type}

    def __setstate__(self, state):
        self.Type = (state or {}).get("Type", "Fem::VDMesh")
        self.keep_folders = []  # not saved: an earlier session's folder is found through OutputFile

    # FreeCAD 0.20 uses these names for Python < 3.11 compatibility shims
    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)


def file_digest(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


# a number in BREP text; a line of the seven 0/1 flags of a TShape (Free Modified Checked Orientable ...)
BREP_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")
BREP_FLAGS = re.compile(r"^[01]{7}$", re.M)


def brep_quantum(shape):
    """The step BREP numbers are rounded to: a power of ten near 1e-9 of the bounding-box diagonal
    (a power of ten, so that the diagonal's own last digits cannot move every rounded number)."""
    diagonal = shape.BoundBox.DiagonalLength or 1.0
    return 10.0 ** math.floor(math.log10(1e-9 * diagonal))


def stable_brep(shape):
    """The shape's BREP text in a form that survives save and reload: FreeCAD saves numbers with 17
    decimals (-7.3478807948841188e-16 comes back as -7.3000000000000003e-16, -0 as 0) and the
    flags' Checked bit changes, so every number is rounded to brep_quantum and the flag lines left
    out. Copied without the triangulation the 3D view may store in the shape: not the geometry."""
    shape = shape.copy(True, False)
    quantum = brep_quantum(shape)

    def rounded(m):
        steps = float(m.group()) / quantum
        return "%d" % round(steps) if math.isfinite(steps) else m.group()

    return BREP_NUMBER.sub(rounded, BREP_FLAGS.sub("", shape.exportBrepToString()))


def mesh_inputs(part, params):
    """What a mesh is made from: the part's shape (its BREP text, see stable_brep) and the options.
    Until 2026-11-30 the raw BREP text was hashed, and every recompute after reopening a document
    meshed again."""
    return inputs_of_shape(shape_of(part), params)


def inputs_of_shape(shape, params):
    brep = stable_brep(shape)
    return hashlib.sha256(brep.encode()).hexdigest() + " " + json.dumps(params_key(params))


def params_key(p):
    """The parameters as the properties give them back (floats where they are quantities): a run
    given size=5 and the object's Size (5.0) are the same mesh; the raw values differed, and every
    mesh made from integer parameters was said to be of a part changed while meshing."""
    return [["flips", bool(p.flips)], ["interior", bool(p.interior)], ["lp_limit", int(p.lp_limit)],
            ["oracle", str(p.oracle)], ["order", int(p.order)], ["ridge_angle", float(p.ridge_angle)],
            ["seed", int(p.seed)], ["size", float(p.size)], ["sliver_angle", float(p.sliver_angle)]]


def mesh_signature(fm):
    """What a FemMesh is: node and tetrahedron counts and a checksum of the node coordinates
    (0.2 s for 71,000 nodes, against 10 s to mesh them). The groups are left out: materials renew
    theirs without a new mesh. 12 digits, so that the UNV a document keeps the mesh in may round."""
    h = hashlib.sha256()
    nodes = fm.Nodes
    for n in sorted(nodes):
        v = nodes[n]
        h.update(b"%d %.12g %.12g %.12g\n" % (n, v.x, v.y, v.z))
    return "mesh %d %d %s" % (fm.NodeCount, fm.VolumeCount, h.hexdigest()[:32])


def mesh_record(key, fm):
    """MeshInputs: what the mesh was made from (mesh_inputs) and what it is (mesh_signature)."""
    return "%s | %s" % (key, mesh_signature(fm))


def mesh_is_current(obj, key):
    """Whether obj's FemMesh is the one its last run made from key (the part and the properties now).

    Undo restores the properties, MeshInputs and OutputFile but not the FemMesh: until 2026-11-30 a
    box meshed at Size 3 (1,556 tetrahedra), set to 5 (437) and undone kept the 437 through
    recompute, touch and save."""
    return obj.MeshInputs == mesh_record(key, obj.FemMesh)


def deck_is_of_femmesh(obj):
    """Whether the run that wrote OutputFile made the FemMesh the object holds (after an undo or redo
    OutputFile and MeshInputs are another run's, the FemMesh is not)."""
    return obj.MeshInputs.endswith(" | " + mesh_signature(obj.FemMesh))


def apply_result(obj, fm, inp, report):
    obj.FemMesh = fm
    # A folder of its own for each run: one named after the document and the
    # object was shared by every document of the same name (all new ones are
    # "Unnamed"), and Export wrote another document's mesh.
    keep = make_keep_folder(obj)
    kept = os.path.join(keep, "mesh.inp")
    try:
        shutil.copyfile(inp, kept)
        shutil.rmtree(os.path.dirname(inp), ignore_errors=True)
    except OSError:
        kept = inp
    remove_keep_folders(obj, but=keep)
    obj.OutputFile = kept
    obj.OutputDigest = file_digest(kept)
    obj.Report = json.dumps(report or {})


def is_vdmesh_object(obj):
    # by the proxy's Type, not its class: a reload of this module makes another class
    return getattr(getattr(obj, "Proxy", None), "Type", None) == "Fem::VDMesh"


def folders_made(obj):
    """The list of keep folders obj's runs made in this session (kept in its proxy, which undo does
    not touch: undo gives OutputFile an older run's path, and the newer run's folder is known only
    here). Empty for an object that is not a VDMesh object."""
    if not is_vdmesh_object(obj):
        return []
    return obj.Proxy.__dict__.setdefault("keep_folders", [])


def make_keep_folder(obj):
    """A new temporary folder for a run's deck, listed as obj's."""
    folder = tempfile.mkdtemp(prefix=KEEP_PREFIX)
    folders_made(obj).append(folder)
    return folder


def is_keep_folder(folder):
    """Whether folder is one make_keep_folder makes: vdmesh-keep-* right in the temporary folder.
    A document says what its OutputFile is, and nothing else is removed on its word."""
    return (os.path.basename(folder).startswith(KEEP_PREFIX)
            and os.path.realpath(os.path.dirname(folder)) == os.path.realpath(tempfile.gettempdir()))


def keep_folders_of(obj):
    """obj's keep folders: those its runs made in this session, and its OutputFile's (a run of an
    earlier session, when the document was reopened)."""
    folders = list(folders_made(obj))
    current = os.path.dirname(getattr(obj, "OutputFile", "") or "")
    if current and current not in folders and is_keep_folder(current):
        folders.append(current)
    return folders


def remove_keep_folders(obj, but=None):
    """Removes obj's keep folders except `but`. The previous run's folder alone was removed: after
    an undo or redo OutputFile names an older run's, and the newer run's folder stayed, as did every
    folder of a deleted object or a closed document (a session of tests left over 200 in /tmp).
    No deck is lost that Export needs: it takes the kept deck only while that run made the
    FemMesh (kept_deck), else it writes the FemMesh."""
    for folder in keep_folders_of(obj):
        if folder != but:
            shutil.rmtree(folder, ignore_errors=True)
    made = folders_made(obj)
    made[:] = [f for f in made if f == but]


def solid_materials(analysis):
    return [m for m in analysis.Group
            if m.isDerivedFrom("App::MaterialObjectPython") and getattr(m, "Category", "Solid") == "Solid"]


def materials_of(obj):
    """The solid materials of the analyses holding obj, in renew_material_groups' order."""
    out = []
    for analysis in analyses_of(obj):
        out += [m for m in solid_materials(analysis) if m not in out]
    return out


class AnalysisWatcher:
    """A document observer that marks a mesh object for recompute when an analysis holding it gains
    or loses a material, or when the mesh joins an analysis: its <Material>_Volumes groups are made
    on recompute (without meshing again when the part did not change). Neither touches the mesh
    object itself: a mesh made before its analysis had no material groups, and FreeCAD's CalculiX
    writer fell back to a geometric search that gave 3,347 of 5,003 second-order tetrahedra a
    material."""

    def slotChangedObject(self, obj, prop):
        if prop != "Group" or not obj.isDerivedFrom("Fem::FemAnalysis"):
            return
        if getattr(obj.Document, "Restoring", False):
            return  # a document being read: its groups were saved with it
        for o in obj.Group:
            if is_vdmesh_object(o) and list(o.Materials) != materials_of(o):
                o.touch()


class KeepFolderJanitor:
    """A document observer that removes a mesh object's keep folders when it leaves its document
    (deleted, or its creation undone: redo brings it back without them, and Export writes its
    FemMesh) and when its document closes (FreeCAD closes every document on exit, headless too).
    FreeCAD 0.20 tells a Python feature's proxy of neither: only the GUI's view provider has an
    onDelete, and it is not called when a document closes."""

    def slotDeletedObject(self, obj):
        if is_vdmesh_object(obj):
            remove_keep_folders(obj)

    def slotDeletedDocument(self, doc):
        for obj in doc.Objects:
            if is_vdmesh_object(obj):
                remove_keep_folders(obj)


_janitor = None
_watcher = None


def watch_documents():
    """Registers the KeepFolderJanitor and the AnalysisWatcher once (on import: any mesh object,
    made or restored, imports this module first)."""
    global _janitor, _watcher
    if _janitor is None:
        _janitor = KeepFolderJanitor()
        FreeCAD.addDocumentObserver(_janitor)
    if _watcher is None:
        _watcher = AnalysisWatcher()
        FreeCAD.addDocumentObserver(_watcher)


def kept_deck(obj):
    """The deck of the object's last run when it is still the one that run wrote and that run made
    the FemMesh, else None (Export then writes the FemMesh)."""
    src = getattr(obj, "OutputFile", "")
    digest = getattr(obj, "OutputDigest", "")
    if not src or not digest or not os.path.isfile(src):
        return None
    if not deck_is_of_femmesh(obj):
        return None
    return src if file_digest(src) == digest else None


def analyses_of(obj):
    return [o for o in obj.InList if o.isDerivedFrom("Fem::FemAnalysis")]


def add_material_groups(obj, analysis):
    """Adds a volume group <Material>_Volumes for each solid material object of the analysis: the
    union of the Solid<i>_Volumes groups its References name; for a material without References the
    tetrahedra no other material claims (all of them when it is the only material), as FreeCAD
    reads a material without references beside others.

    FreeCAD's CalculiX writer takes a material's elements from the group named <Material>_...;
    without one it searches the mesh geometrically, which is slow and misses elements whose nodes
    are classified outside the solid (it failed on second-order meshes of curved parts)."""
    fm = obj.FemMesh
    groups = femmesh.group_ids(fm)
    materials = solid_materials(analysis)
    changed = False
    for m in materials:
        if m.Name + "_Volumes" in groups:
            fm.removeGroup(groups[m.Name + "_Volumes"])
            changed = True
    claims = referenced_volumes(obj, fm, groups, materials)
    claimed = set().union(*claims.values())
    rest = [e for e in fm.Volumes if e not in claimed]
    for m in materials:
        elems = claims.get(m.Name, rest if not m.References else None)
        if elems is None:
            continue  # refers to another part or to faces: not ours to say
        g = fm.addGroup(m.Name + "_Volumes", "Volume")
        fm.addGroupElements(g, elems)
        changed = True
    if changed:
        obj.FemMesh = fm
    return materials


def referenced_volumes(obj, fm, groups, materials):
    """{material's Name: its tetrahedra} for the materials whose References name solids of obj's part.

    Until 2026-11-30 a material without References took every tetrahedron even beside one that
    named Solid2: Steel_Volumes held all 7,741 of two boxes, Alu_Volumes 3,903 of them too, and
    FreeCAD's CalculiX writer said femelements_count_ok() failed."""
    claims = {}
    for m in materials:
        solids = [sub for o, subs in m.References if o == obj.Part for sub in subs if sub.startswith("Solid")]
        if not solids:
            continue
        missing = [s for s in solids if s + "_Volumes" not in groups]
        if missing:
            raise engine.VDMeshError("%s refers to %s, which the mesh does not have" % (m.Label, ", ".join(missing)))
        claims[m.Name] = sorted({e for s in solids for e in fm.getGroupElements(groups[s + "_Volumes"])})
    return claims


def renew_material_groups(obj):
    """add_material_groups for every analysis holding the mesh, and the mesh linked to their materials.

    A material's References are its, not the mesh's: linked, a change of theirs makes recompute
    renew the groups (until 2026-11-29 Steel_Volumes kept the solid it named before, and CalculiX
    would have given each solid the other's material)."""
    materials = []
    for analysis in analyses_of(obj):
        materials += [m for m in add_material_groups(obj, analysis) if m not in materials]
    if list(obj.Materials) != materials:
        obj.Materials = materials
    return [m.Name for m in materials]


def adopt_result(obj, fm, inp, report, key):
    """The mesh of a run, with what goes with it. key: mesh_inputs of the shape and parameters that
    run meshed (run_mesh's info["inputs"]), taken before it: until 2026-11-30 it was taken after,
    and a part moved while the panel meshed kept the old mesh as current through every recompute."""
    apply_result(obj, fm, inp, report)
    obj.MeshInputs = mesh_record(key, obj.FemMesh)
    print_warnings(obj, report)
    renew_material_groups(obj)


def touch_if_part_changed(obj):
    """Marks obj for recompute when its part changed while it was meshed (the GUI runs meanwhile);
    returns whether it did."""
    if mesh_is_current(obj, mesh_inputs(obj.Part, params_of(obj))):
        return False
    obj.touch()
    FreeCAD.Console.PrintWarning("VDMesh %s: %s changed while it was meshed: recompute to mesh it again\n"
                                 % (obj.Label, obj.Part.Label))
    return True


def find_analysis(doc):
    """The active analysis (GUI), else None."""
    try:
        import FemGui
        a = FemGui.getActiveAnalysis()
        if a is not None and a.Document == doc:
            return a
    except Exception:
        pass
    return None


def create_mesh(part, params=None, analysis=None, name="VDMesh", cancel=None, idle=None):
    """Meshes part and only then adds the mesh object (and puts it into analysis, or the active one).

    Raises engine.VDMeshError, leaving the document unchanged, when vdmesh fails or is cancelled
    (engine.VDMeshCancelled). Returns (object, info dict, report dict, report text)."""
    params = params or engine.Parameters()
    fm, info, inp, report, text = run_mesh(part, params, cancel, idle)
    doc = part.Document
    made = []
    try:
        with transaction(doc, "VDMesh"):
            obj = doc.addObject(TYPE, name)
            made.append(obj)
            VDMeshObject(obj, params)
            if FreeCAD.GuiUp:
                from . import viewprovider
                viewprovider.ViewProviderVDMesh(obj.ViewObject)
            obj.Part = part
            analysis = analysis or find_analysis(doc)
            if analysis is not None:
                analysis.addObject(obj)
            adopt_result(obj, fm, inp, report, info["inputs"])
            obj.purgeTouched()
            info["stale"] = touch_if_part_changed(obj)
    except Exception:
        discard(made, inp)
        raise
    return obj, info, report, text


@contextlib.contextmanager
def transaction(doc, name):
    """One undo step, aborted on an exception; none when the document records no undo (freecadcmd's
    default): there doc.openTransaction opens the application's transaction and commitTransaction
    leaves it open, and the next change of any other document was recorded under its name."""
    undo = bool(doc.UndoMode)
    if undo:
        doc.openTransaction(name)
    try:
        yield
    except BaseException:
        if undo:
            doc.abortTransaction()
        raise
    if undo:
        doc.commitTransaction()


def discard(made, inp):
    """Removes what a failed create_mesh made. abortTransaction does it only when the document
    records undo, which freecadcmd's documents do not: the object stayed, in the analysis too."""
    shutil.rmtree(os.path.dirname(inp), ignore_errors=True)
    for obj in made:
        if is_alive(obj):
            remove_keep_folders(obj)
            obj.Document.removeObject(obj.Name)  # also takes it out of the analysis


def remesh(obj, params, cancel=None, idle=None):
    """The task panel's Remesh (and OK after a change): meshes obj's part with params, then sets the
    properties and the mesh in one transaction, so that undo gives back the previous size (and,
    on recompute, its mesh): without one, Undo undid the object's creation. A failed or stopped
    run changes nothing. Returns (info, report dict, report text); info["stale"] as create_mesh."""
    fm, info, inp, report, text = run_mesh(obj.Part, params, cancel, idle, watch=[obj])
    try:
        # A material naming a solid the new mesh lacks raised inside the transaction, after the
        # size and the mesh had changed (without undo they stayed so; with it the FemMesh did).
        for analysis in analyses_of(obj):
            referenced_volumes(obj, fm, femmesh.group_ids(fm), solid_materials(analysis))
        with transaction(obj.Document, "VDMesh remesh"):
            set_params(obj, params)
            adopt_result(obj, fm, inp, report, info["inputs"])
            obj.purgeTouched()
            info["stale"] = touch_if_part_changed(obj)
    except Exception:
        shutil.rmtree(os.path.dirname(inp), ignore_errors=True)
        raise
    return info, report, text


def warnings_of(report):
    """Lines a user must see: solids that overlap (the lower number meshes the common volume, so a
    solid inside another is not in the mesh at all: nothing said so in FreeCAD until 2026-11-29)."""
    cad = (report or {}).get("cad", {})
    meshed = {v.get("name") for v in cad.get("volumes", [])}
    out = []
    for o in cad.get("overlaps", []):
        a, b = ("Solid%d" % n for n in o["solids"][:2])
        gone = " (%s is not in the mesh)" % b if b not in meshed else ""
        out.append("overlapping solids: %s and %s share a volume of %.6g, meshed as %s%s; make them touch "
                   "(Part BooleanFragments) to mesh both" % (a, b, o.get("volume", 0), a, gone))
    return out


def print_warnings(obj, report):
    for w in warnings_of(report):
        FreeCAD.Console.PrintWarning("VDMesh %s: %s\n" % (obj.Label, w))


def mesh_summary(info, report):
    lines = ["warning: " + w for w in warnings_of(report)]
    lines.append("%d nodes, %d %d-node tetrahedra, groups: %s; %s" % (info.get("nodes", 0), info.get("tetrahedra", 0),
                                                                   info.get("nodes_per_tetrahedron", 4),
                                                                   ", ".join(info.get("solids", [])),
                                                                   ", ".join(info.get("faces", []))))
    if report:
        q = report.get("quality", {})
        cad = report.get("cad", {})
        if cad:
            lines.append("size %s%s, chord height %.4g" % (cad.get("size"), " (chosen)" if cad.get("size_chosen") else "",
                                                             cad.get("deflection", 0)))
            thinnest = cad.get("thinnest_solid", 0)
            if cad.get("thin_faces"):
                lines.append("%d faces of a thin part at sizes down to %.4g (4 x its mean thickness %.4g)"
                             % (cad["thin_faces"], cad.get("thin_size", 0), thinnest))
            elif thinnest and 4 * thinnest < cad.get("size", 0):
                lines.append("a solid is %.4g thick (2V/A): its tetrahedra are flat across it; give a smaller Size"
                             % thinnest)
            for v in cad.get("volumes", []):
                err = abs(v["mesh"] - v["cad"]) / v["cad"] * 100 if v.get("cad") else 0
                lines.append("volume %s: CAD %.6g, mesh %.6g (%.3f %%)" % (v["name"], v["cad"], v["mesh"], err))
        if q:
            lines.append("dihedral angle min %.3g, max %.4g deg; radius ratio min %.3g, mean %.3g; tets under 5 / 10 deg: %s / %s"
                         % (q.get("min_dihedral_deg", 0), q.get("max_dihedral_deg", 0), q.get("min_radius_ratio", 0),
                            q.get("mean_radius_ratio", 0), q.get("tets_below_5_deg"), q.get("tets_below_10_deg")))
        hist = q.get("dihedral_histogram_10deg")
        if hist:
            lines.append("dihedral angles (10 deg bins):")
            top = max(hist) or 1
            for i, n in enumerate(hist):
                lines.append("%3d-%3d %7d %s" % (10 * i, 10 * i + 10, n, "#" * int(round(40.0 * n / top))))
    return "\n".join(lines)


# formats `vdmesh convert` writes, for the Export dialog (converters' registry by extension)
EXPORT_FILTERS = [
    ("Abaqus / CalculiX (*.inp)", ".inp"),
    ("Gmsh (*.msh)", ".msh"),
    ("VTK XML unstructured grid (*.vtu)", ".vtu"),
    ("VTK legacy (*.vtk)", ".vtk"),
    ("Medit (*.mesh)", ".mesh"),
    ("TetGen (*.node)", ".node"),
]


def abaqus_number(v):
    """v as the deck's text: CalculiX reads each field through 20 characters, and a longer number
    stops it ("ERROR reading *NODE"); vdmesh's writer does the same (abaqus_number in
    converters/formats/abaqus.cpp). repr writes up to 17 digits: -4.8502286207676093e-05 is 23
    characters."""
    text = repr(v)
    digits = 16
    while len(text) > 20 and digits > 0:
        text = "%.*g" % (digits, v)
        digits -= 1
    return text


def node_lines(ids):
    """Node ids 16 to a line, as vdmesh writes its node sets."""
    ids = list(ids)
    return "".join(", ".join(str(n) for n in ids[i:i + 16]) + "\n" for i in range(0, len(ids), 16))


def region_sets(fm, groups):
    """[(region name, its tetrahedra)] from the FemMesh's region groups: each <Name>_Volumes that
    to_femmesh made beside a <Name>_Nodes. A material's <Material>_Volumes has no _Nodes group and is
    not a region: taken as one, it named the deck's element sets after the analysis's materials
    (sorted first, "Alu" before "Solid1") instead of the Solid<i> the kept deck has. Tetrahedra in
    no region group go into one more region."""
    names = [n[:-len("_Volumes")] for n in groups
             if n.endswith("_Volumes") and fm.getGroupElementType(groups[n]) == "Volume"]
    regions = [n for n in names if n + "_Nodes" in groups] or names
    out, seen = [], set()
    for name in sorted(regions, key=femmesh._natural):
        elems = sorted(e for e in fm.getGroupElements(groups[name + "_Volumes"]) if e not in seen)
        seen.update(elems)
        out.append((name, elems))
    rest = [e for e in sorted(fm.Volumes) if e not in seen]
    if rest:
        out.append(("Solid%d" % (len(out) + 1), rest))
    return [(name, elems) for name, elems in out if elems]


def face_sets(fm, groups):
    """[(face name, its face element ids)] from the FemMesh's <Name>_Faces groups, in vdmesh's order
    (Face1, Face2, ... Face10). A facet on two CAD faces is a face element in each group."""
    names = [n[:-len("_Faces")] for n in groups
             if n.endswith("_Faces") and fm.getGroupElementType(groups[n]) == "Face"]
    return [(name, sorted(fm.getGroupElements(groups[name + "_Faces"])))
            for name in sorted(names, key=femmesh._natural)]


def tetrahedra_in_abaqus_order(fm, elems):
    """{element id: node ids in Abaqus order} (FemMesh keeps tetrahedra negative, see femmesh)."""
    return {e: femmesh.swap_orientation(fm.getElementNodes(e)) for e in elems}


def element_sides(fm, tets, faces):
    """{face element id: (tetrahedron id, side 0..3)}: the side of a tetrahedron a face element is.

    to_femmesh added each face element with its normal out of the tetrahedron whose side vdmesh's
    deck named (inpreader.InpMesh.face_nodes), so of the two tetrahedra at an interface the one
    whose outward corner order is the face element's is that side: the kept deck's choice, found
    by the node order alone. A face element whose order matches neither (not one to_femmesh made)
    takes the first tetrahedron that has it."""
    wanted = {}
    for _, elems in faces:
        for fe in elems:
            wanted.setdefault(tuple(sorted(fm.getElementNodes(fe)[:3])), [])
    for e, c in tets.items():
        for k, (i, j, l) in enumerate(inpreader.TET_FACES):
            key = tuple(sorted((c[i], c[j], c[l])))
            if key in wanted:
                wanted[key].append((e, k))
    sides = {}
    for _, elems in faces:
        for fe in elems:
            corners = tuple(fm.getElementNodes(fe)[:3])
            candidates = wanted[tuple(sorted(corners))]
            outward = [(e, k) for e, k in candidates if is_rotation(corners, outward_corners(tets[e], k))]
            if outward or candidates:
                sides[fe] = (outward or candidates)[0]
    return sides


def outward_corners(tet, side):
    """The corners of a side of a tetrahedron (Abaqus order) with the normal pointing out of it."""
    i, j, k = inpreader.TET_FACES[side]
    return (tet[i], tet[k], tet[j])


def is_rotation(a, b):
    return any(tuple(b[m:] + b[:m]) == tuple(a) for m in range(3))


def face_nodes_of(fm, groups, name, elems):
    """The nodes of face group name: its <Name>_Nodes group (vdmesh's node set, read into the FemMesh),
    else the nodes of its face elements."""
    if name + "_Nodes" in groups:
        return sorted(fm.getGroupElements(groups[name + "_Nodes"]))
    return sorted({n for fe in elems for n in fm.getElementNodes(fe)})


def write_inp_from_femmesh(fm, path):
    """Our deck from a FemMesh alone (the kept deck is gone: undo or redo, a removed temporary
    folder, a reopened document), laid out and named as vdmesh writes it: nodes, one *ELEMENT block
    (4 or 10 nodes, back in Abaqus order) and one *NSET <Name>_Nodes per region, then an element
    *SURFACE and an *NSET <Face>_Nodes per face group.

    The face groups come from the FemMesh's <Face>_Faces groups, which hold vdmesh's face sets as
    they were (a facet on two CAD faces in both, each with the side the deck named): the boundary
    of the tetrahedra alone would not say which CAD face a facet is on, nor give the interfaces
    between solids. Until 2026-11-30 the faces were left out, and an exported deck had no surface
    for a *DSLOAD or a *BOUNDARY to name."""
    nodes = fm.Nodes
    groups = femmesh.group_ids(fm)
    regions = region_sets(fm, groups)
    tets = tetrahedra_in_abaqus_order(fm, fm.Volumes)
    faces = face_sets(fm, groups)
    sides = element_sides(fm, tets, faces)
    with open(path, "w") as f:
        f.write("** Mesh written by the vdmesh FreeCAD workbench from a FemMesh\n*NODE, NSET=NALL\n")
        for n in sorted(nodes):
            v = nodes[n]
            f.write("%d, %s, %s, %s\n" % (n, abaqus_number(v.x), abaqus_number(v.y), abaqus_number(v.z)))
        for name, elems in regions:
            for n_nodes, etype in ((4, "C3D4"), (10, "C3D10")):
                block = [e for e in elems if len(tets[e]) == n_nodes]
                if not block:
                    continue
                f.write("*ELEMENT, TYPE=%s, ELSET=%s\n" % (etype, name))
                for e in block:
                    f.write("%d, %s\n" % (e, ", ".join(str(n) for n in tets[e])))
        for name, elems in regions:
            f.write("*NSET, NSET=%s_Nodes\n" % name)
            f.write(node_lines(sorted({n for e in elems for n in tets[e]})))
        for name, elems in faces:
            listed = [sides[fe] for fe in elems if fe in sides]
            if listed:
                f.write("*SURFACE, NAME=%s, TYPE=ELEMENT\n" % name)
                f.write("".join("%d, S%d\n" % (e, k + 1) for e, k in listed))
        for name, elems in faces:
            f.write("*NSET, NSET=%s_Nodes\n" % name)
            f.write(node_lines(face_nodes_of(fm, groups, name, elems)))
    return path


def export_mesh(obj, path, extra=()):
    """Writes the mesh object's mesh to path (format by extension) through `vdmesh convert`."""
    src = kept_deck(obj)
    tmpdir = None
    if src is None:
        tmpdir = tempfile.mkdtemp(prefix="vdmesh-export-")
        src = write_inp_from_femmesh(obj.FemMesh, os.path.join(tmpdir, "mesh.inp"))
    try:
        if os.path.splitext(path)[1].lower() == ".inp" and not extra:
            try:
                shutil.copyfile(src, path)
            except OSError as e:  # the GUI shows VDMeshError in a dialog, an OSError as a traceback
                raise engine.VDMeshError("could not write %s: %s" % (path, e.strerror or e))
            return path
        return engine.convert(src, path, extra)
    finally:
        if tmpdir:
            shutil.rmtree(tmpdir, ignore_errors=True)


watch_documents()
