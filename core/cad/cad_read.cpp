// Reading CAD files and making their solids conformal (general fuse), with
// the FreeCAD numbering of solids and faces carried through the fuse.
#include <BRepAlgoAPI_BuilderAlgo.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Copy.hxx>
#include <BRepBuilderAPI_MakeSolid.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRepLib.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <TCollection_AsciiString.hxx>
#include <OSD.hxx>
#include <OSD_Signal.hxx>
#include <Interface_Static.hxx>
#include <STEPControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_MapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shell.hxx>

#include <algorithm>
#include <cerrno>
#include <array>
#include <csignal>
#include <chrono>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "cad/cad_impl.h"
#include "mesh/error.h"
#include "mesh/parallel.h"

namespace vd::cad {
namespace {

using Clock = std::chrono::steady_clock;

// OpenCASCADE's handlers of the fault signals while a file is read: its
// readers dereference what a broken file leaves null (a garbled STEP entity:
// a segmentation fault in StepToTopoDS_TranslateFace), and its handlers turn
// the fault into a Standard_Failure (OSD_SIGSEGV) thrown where it happened.
// OSD::SetSignal also takes SIGHUP, SIGINT and SIGQUIT, which are given back
// at once (Ctrl-C still stops the program); every handler before (the
// program's, ASan's, FreeCAD's) is put back afterwards.
class OccSignalsWhileReading {
 public:
  OccSignalsWhileReading() {
    for (size_t i = 0; i < kTaken.size(); ++i) sigaction(kTaken[i], nullptr, &saved_[i]);
    OSD::SetSignal(OSD_SignalMode_Set, /*theFloatingSignal=*/false);
    for (size_t i = 0; i < kTaken.size(); ++i)
      if (!is_fault(kTaken[i])) sigaction(kTaken[i], &saved_[i], nullptr);
  }
  ~OccSignalsWhileReading() {
    for (size_t i = 0; i < kTaken.size(); ++i) sigaction(kTaken[i], &saved_[i], nullptr);
  }
  OccSignalsWhileReading(const OccSignalsWhileReading&) = delete;
  OccSignalsWhileReading& operator=(const OccSignalsWhileReading&) = delete;

 private:
  // What OSD::SetSignal sets on Linux (OpenCASCADE 7.6, measured).
  static constexpr std::array<int, 8> kTaken = {SIGHUP, SIGINT, SIGQUIT, SIGILL, SIGBUS, SIGFPE, SIGSEGV, SIGSYS};
  static bool is_fault(int s) { return s == SIGILL || s == SIGBUS || s == SIGFPE || s == SIGSEGV || s == SIGSYS; }
  std::array<struct sigaction, 8> saved_{};
};

// OpenCASCADE's messages while a file is read go to vdmesh's error instead
// of the default messenger's printers: the IGES reader prints "Total number
// of loaded entities 2932." to standard output (in colour) under --quiet,
// and the STEP reader its syntax errors ("**** ERR StepFile : ... Line 2:
// Incorrect syntax", until 2026-11-30), which say what vdmesh's own message
// cannot. Whoever set the printers (FreeCAD) gets them back afterwards.
class OccMessagesCollected {
 public:
  OccMessagesCollected() : collector_(new Collector) {
    const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
    for (Message_SequenceOfPrinters::Iterator it(messenger->Printers()); it.More(); it.Next())
      saved_.push_back(it.Value());
    for (const auto& printer : saved_) messenger->RemovePrinter(printer);
    collector_->SetTraceLevel(Message_Fail);
    messenger->AddPrinter(collector_);
  }
  ~OccMessagesCollected() {
    const Handle(Message_Messenger)& messenger = Message::DefaultMessenger();
    messenger->RemovePrinter(collector_);
    for (const auto& printer : saved_) messenger->AddPrinter(printer);
  }
  OccMessagesCollected(const OccMessagesCollected&) = delete;
  OccMessagesCollected& operator=(const OccMessagesCollected&) = delete;
  // "; OpenCASCADE says: ..." with the first failure reported, or "".
  std::string said() const {
    std::string text = collector_->first;
    const auto not_space = [](char c) { return c != ' ' && c != '*'; };
    text.erase(text.begin(), std::find_if(text.begin(), text.end(), not_space));
    text.erase(std::find_if(text.rbegin(), text.rend(), not_space).base(), text.end());
    return text.empty() ? "" : "; OpenCASCADE says: " + text;
  }

 private:
  class Collector : public Message_Printer {
   public:
    mutable std::string first;

   protected:
    void send(const TCollection_AsciiString& text, const Message_Gravity gravity) const override {
      if (gravity >= Message_Fail && first.empty()) first = text.ToCString();
    }
  };
  Handle(Collector) collector_;
  std::vector<Handle(Message_Printer)> saved_;
};

// Whether a BREP text has the line of its format's version, which
// OpenCASCADE's reader looks for anywhere in the text; without it the reader
// prints "File was not written with this version of the topology" on
// standard output, past the collected messages, and fails.
bool has_brep_version_line(std::istream& in) {
  static const char* const kVersions[] = {"CASCADE Topology V1, (c) Matra-Datavision",
                                          "CASCADE Topology V2, (c) Matra-Datavision",
                                          "CASCADE Topology V3, (c) Open Cascade"};
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    for (const char* v : kVersions)
      if (line == v) return true;
  }
  return false;
}

TopoDS_Shape read_file(const std::string& path, std::string& units, OccCancel& cancel) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw FileError(path + ": a folder, not a CAD file", path, EISDIR);
  if (!std::filesystem::exists(path, ec)) throw FileError(path + ": no such file", path, ENOENT);
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": not a regular file");
  if (std::filesystem::file_size(path, ec) == 0) throw InputError(path + ": empty file");
  const std::string ext = lower_extension(path);
  TopoDS_Shape shape;
  const OccSignalsWhileReading signals;
  const OccMessagesCollected messages;
  if (ext == ".step" || ext == ".stp") {
    STEPControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      throw InputError(path + ": not a readable STEP file (OpenCASCADE's STEP reader failed)" + messages.said());
    const int roots = reader.TransferRoots(cancel.range());
    cancel.check();
    if (roots == 0)
      throw InputError(path + ": the STEP file has no shape OpenCASCADE could transfer (none, or broken ones: "
                              "a reference to a missing entity, say)" + messages.said());
    shape = reader.OneShape();
    units = "mm";  // OpenCASCADE converts STEP lengths to millimetres
  } else if (ext == ".iges" || ext == ".igs") {
    IGESControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      throw InputError(path + ": not a readable IGES file (OpenCASCADE's IGES reader failed)" + messages.said());
    const int roots = reader.TransferRoots(cancel.range());
    cancel.check();
    if (roots == 0)
      throw InputError(path + ": the IGES file has no shape OpenCASCADE could transfer (none, or broken ones)" +
                       messages.said());
    shape = reader.OneShape();
    units = "mm";
  } else if (ext == ".brep" || ext == ".brp") {
    std::ifstream text(path);
    if (!has_brep_version_line(text))
      throw InputError(path + ": not a BREP file (no line \"CASCADE Topology V1/V2/V3\", which starts the shapes)");
    BRep_Builder builder;
    const bool read = BRepTools::Read(shape, path.c_str(), builder, cancel.range());
    cancel.check();
    if (!read)
      throw InputError(path + ": not a readable BREP file (OpenCASCADE's BREP reader failed)" + messages.said());
    units = "as given (BREP has no units)";
  } else {
    throw InputError(path + ": not a CAD file (expected .step .stp .iges .igs .brep .brp)");
  }
  if (shape.IsNull()) throw InputError(path + ": the file holds no shape" + messages.said());
  return shape;
}

// Edges of a solid that bound only one of its faces (seams and degenerate
// edges excepted): the shell is open there.
int free_edges(const TopoDS_Shape& solid) {
  TopTools_IndexedDataMapOfShapeListOfShape edge_faces;
  TopExp::MapShapesAndUniqueAncestors(solid, TopAbs_EDGE, TopAbs_FACE, edge_faces);
  // An edge lying inside its face (INTERNAL or EXTERNAL in it) bounds no
  // side: FreeCAD's fuse leaves one in a wall where a boss touches it along
  // a line, and the closed solid was refused as open (a FreeCAD tester's
  // BREP, 2026-11-30). Kept in the face, it makes the wall's triangles
  // meet the boss's along the line (taken out, they crossed there).
  TopTools_MapOfShape inside;
  for (TopExp_Explorer e(solid, TopAbs_EDGE); e.More(); e.Next())
    if (e.Current().Orientation() == TopAbs_INTERNAL || e.Current().Orientation() == TopAbs_EXTERNAL)
      inside.Add(e.Current());
  int open = 0;
  for (int i = 1; i <= edge_faces.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(edge_faces.FindKey(i));
    if (BRep_Tool::Degenerated(e) || inside.Contains(e)) continue;
    const TopTools_ListOfShape& faces = edge_faces(i);
    if (faces.Extent() == 1 && !BRep_Tool::IsClosed(e, TopoDS::Face(faces.First()))) ++open;
  }
  return open;
}

// Surfaces only (IGES often): sew them; closed shells become solids.
TopoDS_Shape solids_from_faces(const TopoDS_Shape& shape, const std::string& path, int nfaces, OccCancel& cancel) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box);
  const double diag = box.IsVoid() ? 1.0 : std::sqrt(box.SquareExtent());
  BRepBuilderAPI_Sewing sewing(1e-6 * diag);
  for (TopExp_Explorer f(shape, TopAbs_FACE); f.More(); f.Next()) sewing.Add(f.Current());
  sewing.Perform(cancel.range());
  cancel.check();
  const TopoDS_Shape sewn = sewing.SewedShape();
  TopoDS_Compound solids;
  BRep_Builder builder;
  builder.MakeCompound(solids);
  int closed = 0, shells = 0, worst_open = 0;
  for (TopExp_Explorer s(sewn, TopAbs_SHELL); s.More(); s.Next()) {
    ++shells;
    const TopoDS_Shell& shell = TopoDS::Shell(s.Current());
    const int open = free_edges(shell);
    worst_open = std::max(worst_open, open);
    if (open > 0) continue;
    BRepBuilderAPI_MakeSolid make(shell);
    if (!make.IsDone()) continue;
    TopoDS_Solid solid = make.Solid();
    BRepLib::OrientClosedSolid(solid);
    builder.Add(solids, solid);
    ++closed;
  }
  if (closed == 0)
    throw InputError(path + ": no solid: " + std::to_string(nfaces) + " faces only; sewn into " +
                     std::to_string(shells) + " shell(s), none closed (up to " + std::to_string(worst_open) +
                     " free edges): a volume needs closed shells");
  return solids;
}

}  // namespace

int CadModel::Impl::index_of_face_number(int number) const {
  auto it = std::find(face_number.begin(), face_number.end(), number);
  return it == face_number.end() ? -1 : static_cast<int>(it - face_number.begin());
}

namespace {

// Numbers the solids and faces of `result` after those of `input` they came
// from (FreeCAD's numbering of the input); pieces without an origin get
// numbers past the input's. A piece that came from two or more input
// shapes (the common piece of overlapping solids) takes the first one's
// number.
// `origins` (optional): every input number each result shape came from.
// `shared` (optional, for faces): a face that came from two input faces
// (touching solids: an interface that lies on a face of each) keeps the
// first one's number only when that face has no other kind of piece, else
// it gets a number of its own; `shared` maps each such number to the input
// faces its facets belong to (Mesh::face_groups). Until 2026-11-30 the
// first face's number stood alone: caxif's Face82 lacked the 4,764 of its
// 26,529 mm2 that lie on Face67, and 38 of its faces had no group at all.
template <class History>
void number_subshapes(const TopoDS_Shape& input, const TopoDS_Shape& result, TopAbs_ShapeEnum kind,
                      History& history, std::vector<TopoDS_Shape>& shapes, std::vector<int>& numbers,
                      std::vector<std::vector<int>>* origins = nullptr,
                      std::map<int, std::vector<int>>* shared = nullptr) {
  TopTools_IndexedMapOfShape in, out;
  TopExp::MapShapes(input, kind, in);
  TopExp::MapShapes(result, kind, out);
  std::vector<int> number(out.Extent() + 1, 0);
  std::vector<std::vector<int>> from(out.Extent() + 1);
  for (int i = 1; i <= in.Extent(); ++i) {
    TopTools_ListOfShape images;
    if (history) images = history->Modified(in(i));
    if (images.IsEmpty() && !(history && history->IsDeleted(in(i)))) images.Append(in(i));
    for (const TopoDS_Shape& image : images) {
      const int k = out.FindIndex(image);
      if (k <= 0) continue;
      if (number[k] == 0) number[k] = i;
      if (from[k].empty() || from[k].back() != i) from[k].push_back(i);
    }
  }
  int next = in.Extent();
  for (int k = 1; k <= out.Extent(); ++k)
    if (number[k] == 0) number[k] = ++next;
  if (shared) *shared = number_shared_pieces(number, from, next);
  std::vector<std::vector<int>> found;
  for (int k = 1; k <= out.Extent(); ++k) {
    shapes.push_back(out(k));
    numbers.push_back(number[k]);
    found.push_back(from[k]);
  }
  // Ordered by number, so that Solid1/Face1 come first.
  std::vector<size_t> order(shapes.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return numbers[a] < numbers[b]; });
  std::vector<TopoDS_Shape> s2;
  std::vector<int> n2;
  std::vector<std::vector<int>> o2;
  for (size_t i : order) s2.push_back(shapes[i]), n2.push_back(numbers[i]), o2.push_back(found[i]);
  shapes.swap(s2);
  numbers.swap(n2);
  if (origins) origins->swap(o2);
}

// `shape` with each solid of negative volume reversed; compounds rebuilt
// around them child by child (TopoDS_Iterator composes the orientations and
// locations), so that the sub-shapes come in the same order.
TopoDS_Shape with_solids_turned_out(const TopoDS_Shape& shape, bool& turned) {
  if (shape.ShapeType() == TopAbs_SOLID) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(shape, props);
    if (!(props.Mass() < 0)) return shape;
    turned = true;
    return shape.Reversed();
  }
  if (shape.ShapeType() != TopAbs_COMPOUND && shape.ShapeType() != TopAbs_COMPSOLID) return shape;
  BRep_Builder builder;
  TopoDS_Compound compound;
  builder.MakeCompound(compound);
  for (TopoDS_Iterator it(shape); it.More(); it.Next()) builder.Add(compound, with_solids_turned_out(it.Value(), turned));
  return compound;
}

// `glue`: fuse the solids as touching only (see CadModel::glued).
std::unique_ptr<CadModel::Impl> build_model(TopoDS_Shape input, const std::string& name, std::string units,
                                            double& seconds_fuse, OccCancel& cancel, bool glue) {
  auto impl = std::make_unique<CadModel::Impl>();
  impl->name = name;
  impl->units = std::move(units);
  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(input, TopAbs_SOLID, solids);
  if (solids.Extent() == 0) {
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(input, TopAbs_FACE, faces);
    if (faces.Extent() == 0) throw InputError(name + ": the shape has no faces and no solids");
    input = solids_from_faces(input, name, faces.Extent(), cancel);
    TopExp::MapShapes(input, TopAbs_SOLID, solids);
  }
  for (int i = 1; i <= solids.Extent(); ++i) {
    const int open = free_edges(solids(i));
    if (open > 0)
      throw InputError(name + ": Solid" + std::to_string(i) + " is not closed (" + std::to_string(open) +
                       " edges bound only one face)");
  }
  // A solid turned inside out (FreeCAD's Shape.reversed(), some exporters)
  // encloses a negative volume: its faces point in, and its facets came out
  // with their sides swapped ("region tags contradict the surface: facet 0
  // says region 1 on its back side"). Turned back, in a copy of the
  // compound's structure, so that the numbering stays as it was.
  bool turned = false;
  const TopoDS_Shape out = with_solids_turned_out(input, turned);
  if (turned) {
    input = out;
    solids.Clear();
    TopExp::MapShapes(input, TopAbs_SOLID, solids);
  }

  const auto t0 = Clock::now();
  std::vector<TopoDS_Shape> solid_shapes, face_shapes;
  std::vector<int> face_numbers;
  if (solids.Extent() > 1) {
    // Touching solids share faces only after the general fuse.
    TopTools_ListOfShape arguments;
    for (int i = 1; i <= solids.Extent(); ++i) arguments.Append(solids(i));
    auto fuse = std::make_unique<BRepAlgoAPI_BuilderAlgo>();
    fuse->SetArguments(arguments);
    // OpenCASCADE's parallel mode (its own thread pool, a thread per core)
    // unless --threads 1: caxif_as1-oc-214.stp's 18 solids fuse in 2.5 s on
    // two cores instead of 4.2 s on one, into the same shape (the meshes of
    // caxif, the ring and the wing-fuselage byte for byte the same).
    fuse->SetRunParallel(thread_count() > 1);
    fuse->SetNonDestructive(true);
    // Glued first: the solids of an assembly touch, and do not cross. The
    // fuse then skips the intersections of faces, edges and vertices that
    // touching solids do not have (gmsh_simple_plane.brep's 27 solids in
    // 0.67 s instead of 2.69, caxif's 18 in 2.16 instead of 2.78, into the
    // same shapes). Where solids do cross, their faces are left whole and the
    // tessellation crosses itself; mesh_cad then fuses again in full
    // (CadModel::fused_in_full).
    if (glue) {
      fuse->SetGlue(BOPAlgo_GlueShift);
      // Kept for fused_in_full as read: tessellating the glued model writes
      // triangulations into the faces it shares with the input, and the
      // full fuse and its bounding box must not see them.
      impl->input = BRepBuilderAPI_Copy(input, Standard_True, Standard_True).Shape();
    }
    impl->fuse = glue ? "glued" : "in full";
    fuse->Build(cancel.range());
    cancel.check();  // before the errors: a stopped fuse reports one
    if (glue && (fuse->HasErrors() || !fuse->IsDone())) {
      // Whatever stopped the glued fuse, the full one decides.
      return build_model(input, name, impl->units, seconds_fuse, cancel, false);
    }
    if (fuse->HasErrors() || !fuse->IsDone()) {
      std::ostringstream report;
      fuse->DumpErrors(report);
      throw InputError(name + ": the general fuse of its " + std::to_string(solids.Extent()) +
                       " solids failed: " + report.str());
    }
    impl->shape = fuse->Shape();
    number_subshapes(input, impl->shape, TopAbs_SOLID, fuse, solid_shapes, impl->solid_number,
                     &impl->solid_origins);
    number_subshapes(input, impl->shape, TopAbs_FACE, fuse, face_shapes, face_numbers, nullptr, &impl->face_groups);
  } else {
    impl->shape = solids(1);
    std::unique_ptr<BRepAlgoAPI_BuilderAlgo> none;
    number_subshapes(input, impl->shape, TopAbs_SOLID, none, solid_shapes, impl->solid_number);
    number_subshapes(input, impl->shape, TopAbs_FACE, none, face_shapes, face_numbers);
  }
  seconds_fuse = std::chrono::duration<double>(Clock::now() - t0).count();
  for (const auto& s : solid_shapes) impl->solids.push_back(TopoDS::Solid(s));
  // Only faces of solids are meshed: free faces of a compound bound nothing.
  TopTools_IndexedMapOfShape solid_faces;
  for (const auto& s : impl->solids) TopExp::MapShapes(s, TopAbs_FACE, solid_faces);
  for (size_t i = 0; i < face_shapes.size(); ++i) {
    if (!solid_faces.Contains(face_shapes[i])) continue;
    impl->faces.push_back(TopoDS::Face(face_shapes[i]));
    impl->face_number.push_back(face_numbers[i]);
    impl->face_index.Add(face_shapes[i]);
  }
  for (const auto& s : impl->solids) TopExp::MapShapes(s, TopAbs_EDGE, impl->edge_index);
  Bnd_Box box;
  BRepBndLib::Add(impl->shape, box);
  impl->diagonal = box.IsVoid() ? 0.0 : std::sqrt(box.SquareExtent());
  if (!(impl->diagonal > 0)) throw InputError(name + ": the shape has no extent");
  return impl;
}

}  // namespace

CadModel CadModel::read(const std::string& path, const std::atomic<bool>* cancel_flag, Fuse fuse) {
  const auto t0 = Clock::now();
  OccCancel cancel(cancel_flag);
  try {
    std::string units;
    TopoDS_Shape shape = read_file(path, units, cancel);
    const double seconds_read = std::chrono::duration<double>(Clock::now() - t0).count();
    double seconds_fuse = 0;
    CadModel model(build_model(shape, path, units, seconds_fuse, cancel, fuse == Fuse::glued_first));
    model.seconds_read = seconds_read;
    model.seconds_fuse = seconds_fuse;
    return model;
  } catch (const Standard_Failure& e) {
    // A fault turned into an exception (OccSignalsWhileReading): an
    // OSD_Signal, or, from the IGES transfer, which catches that and throws
    // anew, a Standard_Failure saying "System Signal received".
    const std::string what = e.GetMessageString() ? e.GetMessageString() : "";
    if (dynamic_cast<const OSD_Signal*>(&e) || what.find("Signal") != std::string::npos)
      throw InputError(path + ": OpenCASCADE's reader faulted on this file (" + e.DynamicType()->Name() + ": " +
                       what + "): the file is broken, or holds entities the reader cannot handle");
    throw InputError(path + ": OpenCASCADE failed: " + what);
  }
}

CadModel CadModel::from_brep_string(const std::string& brep, const std::string& name,
                                    const std::atomic<bool>* cancel_flag, Fuse fuse) {
  OccCancel cancel(cancel_flag);
  try {
    std::istringstream in(brep);
    if (!has_brep_version_line(in))
      throw InputError(name + ": not a BREP shape (no line \"CASCADE Topology V1/V2/V3\", which starts the shapes)");
    in.clear();
    in.seekg(0);
    BRep_Builder builder;
    TopoDS_Shape shape;
    BRepTools::Read(shape, in, builder, cancel.range());
    cancel.check();
    if (shape.IsNull()) throw InputError(name + ": not a BREP shape");
    double seconds_fuse = 0;
    CadModel model(
        build_model(shape, name, "as given (BREP has no units)", seconds_fuse, cancel, fuse == Fuse::glued_first));
    model.seconds_fuse = seconds_fuse;
    return model;
  } catch (const Standard_Failure& e) {
    throw InputError(name + ": OpenCASCADE failed: " + e.GetMessageString());
  }
}

CadModel CadModel::fused_in_full(const std::atomic<bool>* cancel_flag) const {
  if (!glued()) throw std::logic_error("fused_in_full: the model was fused in full already");
  OccCancel cancel(cancel_flag);
  try {
    double seconds_fuse = 0;
    CadModel model(build_model(impl_->input, impl_->name, impl_->units, seconds_fuse, cancel, false));
    model.seconds_read = seconds_read;
    model.seconds_fuse = seconds_fuse;
    return model;
  } catch (const Standard_Failure& e) {
    throw InputError(impl_->name + ": OpenCASCADE failed: " + e.GetMessageString());
  }
}

bool CadModel::glued() const { return impl_->fuse == "glued"; }

CadModel::CadModel(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
CadModel::CadModel(CadModel&&) noexcept = default;
CadModel& CadModel::operator=(CadModel&&) noexcept = default;
CadModel::~CadModel() = default;

int CadModel::solid_count() const {
  return static_cast<int>(std::set<int>(impl_->solid_number.begin(), impl_->solid_number.end()).size());
}
int CadModel::face_count() const { return static_cast<int>(impl_->faces.size()); }
double CadModel::bbox_diagonal() const { return impl_->diagonal; }
std::string CadModel::units() const { return impl_->units; }
double CadModel::default_size() const { return impl_->diagonal / 25.0; }

int CadModel::interface_face_count() const {
  // Between two solid numbers: not between two pieces of one overlapping
  // solid (number_subshapes).
  std::vector<int> front, back;
  face_sides(*impl_, front, back);
  int shared = 0;
  for (size_t f = 0; f < front.size(); ++f) shared += front[f] > 0 && back[f] > 0 && front[f] != back[f];
  return shared;
}

std::string CadModel::fuse_kind() const { return impl_->fuse; }

}  // namespace vd::cad
