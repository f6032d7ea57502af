// OpenCASCADE's own verdict on a shape, asked when its tessellation fails in
// a way vdmesh cannot mend (the faces' triangles cross each other at every
// angular deflection): a user needs to know whether to fix the file or to
// try other options.
#include <BOPAlgo_CheckResult.hxx>
#include <BOPAlgo_CheckStatus.hxx>
#include <BOPAlgo_ArgumentAnalyzer.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>

#include <map>
#include <set>
#include <sstream>

#include "cad/cad_impl.h"

namespace vd::cad {

namespace {

const char* fault_name(BOPAlgo_CheckStatus status) {
  switch (status) {
    case BOPAlgo_SelfIntersect: return "crossings of edges or faces";
    case BOPAlgo_TooSmallEdge: return "edges too small for their tolerance";
    case BOPAlgo_NonRecoverableFace: return "faces that cannot be rebuilt";
    case BOPAlgo_IncompatibilityOfVertex: return "vertices incompatible with their neighbours";
    case BOPAlgo_IncompatibilityOfEdge: return "edges incompatible with their faces";
    case BOPAlgo_IncompatibilityOfFace: return "faces incompatible with their neighbours";
    case BOPAlgo_GeomAbs_C0: return "curves or surfaces with a kink (only C0)";
    case BOPAlgo_InvalidCurveOnSurface: return "edges whose 3D curve leaves their face's surface";
    case BOPAlgo_BadType: return "shapes of a type it cannot check";
    case BOPAlgo_OperationAborted: return "checks aborted";
    default: return "unknown faults";
  }
}

}  // namespace

std::string CadModel::geometry_faults() const {
  const Impl& cad = *impl_;
  // A faulty edge or vertex is named by the faces it bounds, the tags a user
  // sees (FreeCAD's Face<n>).
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces, vertex_faces;
  TopExp::MapShapesAndUniqueAncestors(cad.shape, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  TopExp::MapShapesAndUniqueAncestors(cad.shape, TopAbs_VERTEX, TopAbs_FACE, vertex_faces);
  const auto face_numbers = [&](const TopoDS_Shape& shape, std::set<int>& out) {
    const auto add_face = [&](const TopoDS_Shape& face) {
      const int i = cad.face_index.FindIndex(face);
      if (i > 0) out.insert(cad.face_number[i - 1]);
    };
    const TopTools_IndexedDataMapOfShapeListOfShape* up = nullptr;
    if (shape.ShapeType() == TopAbs_FACE) add_face(shape);
    if (shape.ShapeType() == TopAbs_EDGE) up = &edge_faces;
    if (shape.ShapeType() == TopAbs_VERTEX) up = &vertex_faces;
    if (up && up->Contains(shape))
      for (const TopoDS_Shape& face : up->FindFromKey(shape)) add_face(face);
  };

  struct Fault {
    int count = 0;
    std::set<int> faces;
  };
  std::map<int, Fault> faults;  // by BOPAlgo_CheckStatus, in the enum's order
  try {
    // BRepAlgoAPI_Check's tests plus continuity and curves on surfaces (the
    // set FreeCAD's "Check geometry" runs): on pythonocc_11752.stp the
    // crossing faces have edges whose curve leaves the face.
    BOPAlgo_ArgumentAnalyzer check;
    check.SetShape1(cad.shape);
    check.ArgumentTypeMode() = Standard_True;
    check.SelfInterMode() = Standard_True;
    check.SmallEdgeMode() = Standard_True;
    check.ContinuityMode() = Standard_True;
    check.CurveOnSurfaceMode() = Standard_True;
    check.Perform();
    if (!check.HasFaulty()) return {};
    for (const BOPAlgo_CheckResult& result : check.GetCheckResult()) {
      // One result per fault; its faulty shapes are the edge and its face,
      // or the two shapes that cross.
      Fault& fault = faults[static_cast<int>(result.GetCheckStatus())];
      ++fault.count;
      for (const TopoDS_Shape& shape : result.GetFaultyShapes1()) face_numbers(shape, fault.faces);
    }
  } catch (const Standard_Failure& e) {
    return std::string("OpenCASCADE's check of the shape failed: ") + e.GetMessageString();
  }
  if (faults.empty()) return {};
  std::ostringstream s;
  s << "OpenCASCADE's check of the shape (BOPAlgo_ArgumentAnalyzer) finds it faulty:";
  const char* separator = " ";
  for (const auto& [status, fault] : faults) {
    s << separator << fault.count << " " << fault_name(static_cast<BOPAlgo_CheckStatus>(status));
    separator = "; ";
    if (fault.faces.empty()) continue;
    s << " (on";
    int listed = 0;
    for (int face : fault.faces) {
      if (listed++ == 8) {
        s << " and " << fault.faces.size() - 8 << " more faces";
        break;
      }
      s << (listed > 1 ? ", " : " ") << "Face" << face;
    }
    s << ")";
  }
  return s.str();
}

}  // namespace vd::cad
