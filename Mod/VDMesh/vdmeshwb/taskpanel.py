"""Task panel of the Mesh command: parameters, Mesh / Apply, the report (or the error) below.

With a part: meshing creates the mesh object only when vdmesh succeeded (the document is left as
it was otherwise, and the error shows in the panel). With a mesh object (double-click): Remesh, or
OK after a change, writes the parameters to its properties with the new mesh, in one transaction
(meshobject.remesh). Deleting the part or the mesh object, or closing their document, closes the
panel; while meshing it stops the run first.
"""
import FreeCAD
import FreeCADGui
from PySide import QtCore, QtGui

from . import engine, icon, meshobject


class PanelWatcher:
    """A document observer for an open panel: FreeCAD closes no task dialog when the document it is
    about closes, and the panel stayed on a closed document, its Mesh button raising a
    ReferenceError from the deleted part. A run in progress notices by itself (meshobject.PartGone)
    and stops first."""

    def __init__(self, panel):
        self.panel = panel
        doc = (panel.part or panel.obj).Document if (panel.part or panel.obj) else None
        self.document = doc.Name if doc else None
        self.objects = {o.Name for o in (panel.part, panel.obj) if o is not None}

    def slotDeletedDocument(self, doc):
        if doc.Name == self.document:
            self.panel.close_when_idle("%s was closed" % doc.Label)

    def slotDeletedObject(self, obj):
        if obj.Document.Name == self.document and obj.Name in self.objects:
            self.panel.close_when_idle("%s was deleted" % obj.Label)


class MeshTaskPanel:
    def __init__(self, part=None, mesh_object=None, others=()):
        """others: further selected parts, which are not meshed (said in the panel)."""
        self.part = part if part is not None else (mesh_object.Part if mesh_object else None)
        self.obj = mesh_object
        self.watcher = None
        if self.part is not None or self.obj is not None:
            self.watcher = PanelWatcher(self)
            FreeCAD.addDocumentObserver(self.watcher)
        self.form = QtGui.QWidget()
        self.form.setObjectName("VDMeshTaskPanel")  # the GUI test finds the panel and its widgets by name
        self.form.setWindowTitle("vdmesh: tetrahedral mesh")
        self.form.setWindowIcon(QtGui.QIcon(icon()))
        lay = QtGui.QVBoxLayout(self.form)
        self.target = QtGui.QLabel("Part: %s" % (self.part.Label if self.part else "(none)"))
        lay.addWidget(self.target)
        grid = QtGui.QFormLayout()
        p = meshobject.params_of(mesh_object) if mesh_object else engine.Parameters()
        self.size = QtGui.QDoubleSpinBox()
        self.size.setObjectName("size")
        self.size.setRange(0.0, 1e9)
        self.size.setDecimals(4)
        self.size.setSuffix(" mm")  # the Size property is a length in mm
        self.size.setSpecialValueText("automatic (diagonal / 25)")
        self.size.setValue(p.size)
        grid.addRow("Size", self.size)
        self.interior = QtGui.QCheckBox("interior vertices")
        self.interior.setObjectName("interior")
        self.interior.setChecked(p.interior)
        grid.addRow("", self.interior)
        self.flips = QtGui.QCheckBox("flips (off: splits only)")
        self.flips.setObjectName("flips")
        self.flips.setChecked(p.flips)
        grid.addRow("", self.flips)
        self.ridge = QtGui.QDoubleSpinBox()
        self.ridge.setObjectName("ridge")
        self.ridge.setRange(0.0, 180.0)
        self.ridge.setSuffix(" deg")
        self.ridge.setValue(p.ridge_angle)
        grid.addRow("Ridge angle", self.ridge)
        self.oracle = QtGui.QComboBox()
        self.oracle.setObjectName("oracle")
        self.oracle.addItems(meshobject.ORACLES)
        self.oracle.setCurrentIndex(meshobject.ORACLES.index(p.oracle))
        grid.addRow("Oracle", self.oracle)
        self.lp = QtGui.QSpinBox()
        self.lp.setObjectName("lp")
        self.lp.setRange(0, 10 ** 8)
        self.lp.setSpecialValueText("no limit")
        self.lp.setValue(p.lp_limit)
        grid.addRow("LP size limit", self.lp)
        self.sliver = QtGui.QDoubleSpinBox()
        self.sliver.setObjectName("sliver")
        self.sliver.setRange(0.0, 70.5)  # the mesher refuses more (no tetrahedron has all angles over 70.53 deg)
        self.sliver.setSuffix(" deg")
        self.sliver.setValue(p.sliver_angle)
        grid.addRow("Sliver angle", self.sliver)
        self.seed = QtGui.QSpinBox()
        self.seed.setObjectName("seed")
        self.seed.setRange(0, 2 ** 31 - 1)
        self.seed.setValue(p.seed)
        grid.addRow("Seed", self.seed)
        self.order = QtGui.QComboBox()
        self.order.setObjectName("order")
        self.order.addItems(["1st (4-node tetrahedra)", "2nd (10-node tetrahedra)"])
        self.order.setCurrentIndex(int(p.order) - 1)
        grid.addRow("Element order", self.order)
        lay.addLayout(grid)
        self.run = QtGui.QPushButton("Mesh" if mesh_object is None else "Remesh")
        self.run.setObjectName("run")
        self.run.clicked.connect(self.mesh)
        # Meshing runs beside the GUI (engine.mesh_shape's idle loop); Stop cancels it.
        self.stop = QtGui.QPushButton("Stop")
        self.stop.setObjectName("stop")
        self.stop.setEnabled(False)
        self.stop.clicked.connect(self.request_stop)
        self.cancel = None
        buttons = QtGui.QHBoxLayout()
        buttons.addWidget(self.run)
        buttons.addWidget(self.stop)
        lay.addLayout(buttons)
        self.status = QtGui.QLabel("")
        self.status.setObjectName("status")
        self.status.setWordWrap(True)
        lay.addWidget(self.status)
        self.report = QtGui.QPlainTextEdit()
        self.report.setObjectName("report")
        self.report.setReadOnly(True)
        font = QtGui.QFont("Monospace")
        font.setStyleHint(QtGui.QFont.TypeWriter)
        self.report.setFont(font)
        self.report.setMinimumHeight(220)
        lay.addWidget(self.report)
        self.applied = vars(self.params())  # OK meshes again when the settings differ from these
        if others:
            self.say_only_one(others)

    def say_only_one(self, others):
        """One mesh per part, as FEM's Gmsh and Netgen meshers: the other selected parts were left
        out without a word."""
        names = ", ".join(o.Label for o in others)
        text = ("%d parts selected: only %s is meshed; %s not. Mesh each on its own, or join them with "
                "Part BooleanFragments for one mesh." % (len(others) + 1, self.part.Label, names))
        self.target.setText("Part: %s (%s not meshed)" % (self.part.Label, names))
        self.status.setText('<span style="color:#b06000">%s</span>' % text)
        FreeCAD.Console.PrintWarning("VDMesh: %s\n" % text)

    def params(self):
        return engine.Parameters(size=self.size.value(), interior=self.interior.isChecked(),
                                 flips=self.flips.isChecked(), ridge_angle=self.ridge.value(),
                                 oracle=self.oracle.currentText(), lp_limit=self.lp.value(),
                                 sliver_angle=self.sliver.value(), seed=self.seed.value(),
                                 order=self.order.currentIndex() + 1)

    def request_stop(self):
        if self.cancel is not None:
            self.cancel.set()
            self.status.setText("stopping ...")

    def show_error(self, e):
        if isinstance(e, engine.VDMeshCancelled):
            self.status.setText("<b>stopped</b> (document unchanged)")
            self.report.setPlainText("")
            FreeCAD.Console.PrintMessage("VDMesh: meshing stopped\n")
            return
        self.status.setText('<span style="color:#b00000"><b>vdmesh failed</b> (document unchanged)</span>')
        self.report.setPlainText(e.message)
        FreeCAD.Console.PrintError("VDMesh: %s\n" % e.message)

    def mesh(self):
        if self.part is None:
            self.status.setText("Select a Part solid, compound or BooleanFragments first.")
            return False
        if self.cancel is not None:
            return False  # already meshing (the idle loop lets a second click through)
        self.status.setText("meshing ... (Stop cancels)")
        self.cancel = engine.CancelRequest()
        self.run.setEnabled(False)
        self.stop.setEnabled(True)
        QtGui.QApplication.processEvents()
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.BusyCursor)
        idle = QtGui.QApplication.processEvents
        p = self.params()
        gone = None
        try:
            if self.obj is None:
                self.obj, info, report, text = meshobject.create_mesh(self.part, p, cancel=self.cancel, idle=idle)
            else:
                # The properties change only with the mesh: a failed or stopped run leaves both.
                info, report, text = meshobject.remesh(self.obj, p, self.cancel, idle)
        except meshobject.PartGone as e:
            gone = e
        except engine.VDMeshError as e:
            self.show_error(e)
            return False
        finally:
            QtGui.QApplication.restoreOverrideCursor()
            self.cancel = None
            self.run.setEnabled(True)
            self.stop.setEnabled(False)
        if gone is not None:  # after the finally: closing the panel deletes its widgets
            self.close_for_gone(gone)
            return False
        self.applied = vars(p)
        if self.watcher is not None:
            self.watcher.objects.add(self.obj.Name)  # the new mesh object goes with the panel too
        summary = meshobject.mesh_summary(info, report)
        self.status.setText("<b>%s</b>: %d tetrahedra" % (self.obj.Label, info["tetrahedra"]))
        self.report.setPlainText(summary)
        FreeCAD.Console.PrintMessage("VDMesh %s:\n%s\n" % (self.obj.Label, summary))
        self.run.setText("Remesh")
        if info.get("stale"):
            # no recompute here: it would mesh again with the GUI blocked and no Stop
            self.status.setText(self.status.text() + '<br><span style="color:#b06000">%s changed while meshing: '
                                'this mesh is of it as it was; Remesh or recompute to mesh it again</span>'
                                % self.part.Label)
        else:
            self.obj.Document.recompute()
        return True

    def close_for_gone(self, e):
        """The part or the mesh object was deleted, or its document closed, while meshing: the run
        was stopped (its folder removed); the panel is for nothing now."""
        FreeCAD.Console.PrintWarning("VDMesh: %s\n" % e.message)
        self.close_gone()

    def close_when_idle(self, why):
        """From the PanelWatcher: closed after the observer's call returns (not from inside it).
        While meshing, the run stops itself and close_for_gone follows."""
        if self.cancel is not None or self.watcher is None:
            return
        if not self.shown():  # closed by FreeCAD's Control.closeDialog, which tells no panel
            self.stop_watching()
            return
        FreeCAD.Console.PrintMessage("VDMesh: %s; its mesh panel is closed\n" % why)
        self.part = self.obj = None
        QtCore.QTimer.singleShot(0, self.close_gone)

    def shown(self):
        """Whether this panel's dialog is still open: its widget lives until the dialog closes
        (visible it is not while another tab of the combo view is shown, where a user deletes the
        part in the tree; a review of 2026-11-30)."""
        try:
            self.form.objectName()
            return bool(FreeCADGui.Control.activeDialog())
        except (RuntimeError, AttributeError):  # the widget went with its dialog, or form is None
            return False

    def close_gone(self):
        self.part = self.obj = None
        self.stop_watching()
        if not self.shown():
            return  # another panel may be open by now: not ours to close
        FreeCADGui.Control.closeDialog()
        gui_doc = FreeCADGui.ActiveDocument
        if gui_doc is not None and gui_doc.getInEdit():
            gui_doc.resetEdit()

    def stop_watching(self):
        if self.watcher is not None:
            FreeCAD.removeDocumentObserver(self.watcher)
            self.watcher = None

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Ok | QtGui.QDialogButtonBox.Close)

    def accept(self):
        """OK: mesh (when Mesh was not pressed yet, or the settings changed since the last mesh) and
        close; on failure the panel stays open with the error, as after Mesh. OK in edit mode closed
        the panel and dropped a changed Size without a word."""
        if self.cancel is not None:
            return False  # meshing: OK waits for it (Close stops it)
        if (self.obj is None or vars(self.params()) != self.applied) and not self.mesh():
            return False
        return self.reject()

    def reject(self):
        if self.cancel is not None:  # Close while meshing: stop first, the panel stays until then
            self.request_stop()
            return False
        self.stop_watching()
        FreeCADGui.Control.closeDialog()
        if self.obj is not None and FreeCADGui.ActiveDocument and FreeCADGui.ActiveDocument.getInEdit():
            FreeCADGui.ActiveDocument.resetEdit()
        return True
