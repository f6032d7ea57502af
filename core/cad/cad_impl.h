// Inside core/cad only: the OpenCASCADE side of CadModel.
#pragma once

#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Solid.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <ShapeAnalysis_Surface.hxx>
#include <TopLoc_Location.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <Message_ProgressIndicator.hxx>
#include <Message_ProgressRange.hxx>

#include <array>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "cad/cad_model.h"
#include "geometry/predicates.h"
#include "mesh/cancel.h"

namespace vd::cad {

struct CadModel::Impl {
  std::string name;               // the file, for messages
  std::string units = "as given";
  TopoDS_Shape input;             // glued: a copy of the solids as read, for fused_in_full
  TopoDS_Shape shape;             // after the general fuse
  // "none" (one solid), "glued" (the fuse took the solids as only touching,
  // BOPAlgo_GlueShift), "in full".
  std::string fuse = "none";
  std::vector<TopoDS_Solid> solids;
  std::vector<int> solid_number;  // Solid<n> of solids[i]
  // The input solids solids[i] is a piece of (empty without a fuse); two
  // or more for the common piece of solids that overlap.
  std::vector<std::vector<int>> solid_origins;
  std::vector<TopoDS_Face> faces; // the faces of the solids
  std::vector<int> face_number;   // Face<n> of faces[i]
  // Numbers of faces that lie on two or more input faces -> those faces'
  // numbers (Mesh::face_groups).
  std::map<int, std::vector<int>> face_groups;
  TopTools_IndexedMapOfShape face_index;  // face -> 1 + index into faces
  TopTools_IndexedMapOfShape edge_index;  // every edge of the solids
  double diagonal = 0;
  // OpenCASCADE's integrals of solids[i] (volume, area), computed once: at
  // 1e-7 they were a fifth of gmsh_wing_fuselage.step's run, asked for by
  // every tessellation and again by the volume checks. Empty until asked;
  // filled without a lock: a model is read and meshed on one thread.
  mutable std::vector<std::array<double, 2>> solid_integrals;
  // OpenCASCADE's area of faces[i], likewise once: the report's check per
  // face, and summed over a solid's faces, the solid's area (integrated
  // apart, solids and faces were a sixth of gmsh_917_fusee.stp's run).
  mutable std::vector<double> face_areas;

  int index_of_face_number(int number) const;
};

// OpenCASCADE's long algorithms (STEP and IGES transfer, sewing, the general
// fuse, BRepMesh) ask their progress indicator whether to stop. This one
// answers from vdmesh's cancel flag, so that a fuse of a minute stops when
// the Python caller presses Ctrl-C. The algorithms return early, with their
// own errors set; the caller calls check() before looking at them.
class OccCancel {
 public:
  explicit OccCancel(const std::atomic<bool>* cancel) : cancel_(cancel), indicator_(new Indicator(cancel)) {}
  // A fresh range for one algorithm (the indicator is restarted).
  Message_ProgressRange range() { return indicator_->Start(); }
  void check() const { throw_if_cancelled(cancel_); }

 private:
  class Indicator : public Message_ProgressIndicator {
   public:
    explicit Indicator(const std::atomic<bool>* cancel) : cancel_(cancel) {}
    Standard_Boolean UserBreak() override { return cancel_requested(cancel_); }
    void Show(const Message_ProgressScope&, const Standard_Boolean) override {}

   private:
    const std::atomic<bool>* cancel_;
  };
  const std::atomic<bool>* cancel_;
  Handle(Indicator) indicator_;
};

inline Vec3 to_vec(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }

// The corner (0, 1, 2) of facet t at vertex v; -1 when v is not a corner.
inline int corner_of(const Triangle& t, int v) {
  for (int i = 0; i < 3; ++i)
    if (t.v[i] == v) return i;
  return -1;
}

// Twice the area of triangle v, along its normal (right-hand rule).
inline Vec3 area_vector(const Mesh& m, const std::array<int, 3>& v) {
  return cross(m.points[v[1]] - m.points[v[0]], m.points[v[2]] - m.points[v[0]]);
}

// Orientation of (a, b, c) in a face's (u, v), exactly: +1 counter-clockwise,
// -1 clockwise, 0 collinear. The fold guards multiply two of them.
inline int orient2d(const gp_Pnt2d& a, const gp_Pnt2d& b, const gp_Pnt2d& c) {
  return orientation_2d(a.X(), a.Y(), b.X(), b.Y(), c.X(), c.Y());
}

// Nearest points on a face's surface, in world coordinates (the face's
// placement applied both ways); build one per face and keep it.
class FaceProjector {
 public:
  explicit FaceProjector(const TopoDS_Face& face);
  bool valid() const { return !analyser_.IsNull(); }
  // (u, v) of the surface point nearest `p`; on a periodic surface moved by
  // whole periods to lie nearest `near` when given (the caller's side of a seam).
  gp_Pnt2d uv(const Vec3& p, double tolerance, const gp_Pnt2d* near = nullptr) const;
  // The same by Newton's method from `start` (a few evaluations instead of
  // the global search), on the side of a seam nearest `start`; the global
  // search where Newton fails or ends farther than `max_gap` from p.
  gp_Pnt2d uv_from(const gp_Pnt2d& start, const Vec3& p, double tolerance, double max_gap) const;
  // uv moved by whole periods to lie nearest `near`.
  gp_Pnt2d near_period(gp_Pnt2d uv, const gp_Pnt2d& near) const;
  Vec3 point(const gp_Pnt2d& uv) const;

 private:
  gp_Pnt local(const Vec3& p) const;
  Handle(ShapeAnalysis_Surface) analyser_;
  TopLoc_Location location_;
};

// A tessellation under refinement: the surface plus, per facet corner, its
// parameters on the facet's CAD face, and for mesh edges that lie on CAD
// edges the curve parameters of their ends. New vertices are evaluated on the
// CAD geometry from these parameters, never projected from the chord.
struct CadEdgeSpan {
  int edge = -1;        // 1-based index in Impl::edge_index
  double t_lo = 0;      // parameter at the vertex with the smaller id
  double t_hi = 0;      // parameter at the vertex with the larger id
};

struct CadSurface {
  Mesh mesh;
  std::vector<int> facet_face;                  // index into Impl::faces
  std::vector<std::array<gp_Pnt2d, 3>> uv;      // per facet corner
  std::unordered_map<std::uint64_t, CadEdgeSpan> edge_spans;  // key: edge_key(a, b)
  // Vertices at degenerate edges (sphere poles, cone apexes): their (u, v)
  // is a whole segment, so mid-points of their edges are projected instead.
  std::unordered_set<int> singular;
};

inline std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Two faces' triangulations do not share an edge's nodes: BRepMesh meshed
// the edge anew for one of them (an internal error of the chord height
// levels, cad_tessellate.cpp).
struct EdgeMismatchError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// cad_tessellate.cpp: OpenCASCADE's mesher, welded through the shared edge
// discretisation, tagged and oriented. `face_deflection`, `face_angle_rad`:
// the chord height and the angular deflection of each face (index into
// Impl::faces).
CadSurface tessellate_faces(const CadModel::Impl& cad, const std::vector<double>& face_deflection,
                            const std::vector<double>& face_angle_rad, TessellationStats& stats,
                            const std::atomic<bool>* cancel = nullptr);
// Which solid (its number) lies in front of and behind each face, 0 for none.
void face_sides(const CadModel::Impl& cad, std::vector<int>& front, std::vector<int>& back);
// cad_collapse.cpp: edges shorter than `max_length` collapsed where the
// geometry allows (inner nodes onto a neighbour, edge nodes along their CAD
// edge); the removed vertices are dropped. Returns the number collapsed.
int collapse_short_edges(CadSurface& s, double max_length);
// Would triangle (x, y, z) have two edges on one CAD edge? It would lie in
// the sliver between the curve and its chord, and where the next face meets
// this one at a zero angle (a knife edge), in that face's plane: such a flip
// made occt_MODERN_Exhaust_1.brep's surface overlap itself.
bool hugs_border(const CadSurface& s, int x, int y, int z);
// An inner vertex a hair from a border and the border node it goes onto:
// one split under it (`split`), or the end of the border piece it faces.
struct BorderSnap {
  int vertex, node;
  bool split;
};
// Each snap's vertex collapsed onto its node where the geometry allows (a
// split node is collapsed away again where not). Returns the count moved;
// the positions of the vertices not moved go to `refused`.
int snap_onto_border(CadSurface& s, const std::vector<BorderSnap>& snaps, std::vector<Vec3>* refused = nullptr);
// Edges shorter than `ratio` times the longest edge of each of their facets
// collapsed, an inner end onto the other, on faces not marked in
// `skip_faces`. Returns the number collapsed.
int collapse_needle_edges(CadSurface& s, double ratio, const std::vector<char>& skip_faces);
// Inner vertices of three facets of one face with a corner over 170 deg
// (nearly on the edge of their neighbours' triangle) removed, the three
// facets made that triangle, when the vertex is within the face's chord
// height of it. Returns the number removed.
int remove_flat_inner_vertices(CadSurface& s, const std::vector<double>& face_deflection);
// Drops the facets marked in `dead_facets` (none when empty) and every vertex
// no facet uses (drop_unused_points), renumbering the rest with their
// parameters. Returns the number of vertices dropped.
int compact_surface(CadSurface& s, const std::vector<char>& dead_facets = {});
// cad_remesh.cpp: the facets a face of this area gets with edges of length
// `longest` (equilateral triangles).
double new_facets(double area, double longest);
// cad_refine.cpp: edge splits to the size on the CAD geometry, then flips.
// With options.remesh, then the inside of the faces meshed anew
// (remesh_faces). `face_size`, `face_deflection`: the size and the chord
// height per face (by face index).
void refine_to_size(const CadModel::Impl& cad, CadSurface& s, const TessellationOptions& options,
                    const std::vector<double>& face_size, const std::vector<double>& face_deflection,
                    TessellationStats& stats);
// cad_remesh.cpp: the faces meshed anew inside their border nodes by
// Delaunay refinement in a chart of their (u, v) that keeps angles (exactly
// on planes, cylinders, cones, spheres and tori; elsewhere kept only when
// rounder); faces at a singular vertex their chart cannot place, and faces
// that would get over the plan's `growth_limit` times their facets (and are
// not among its `past_limit`), are left. Returns
// the faces remeshed, and marks them (by face index) in `remeshed` if given.
struct RemeshPlan;
int remesh_faces(const CadModel::Impl& cad, CadSurface& s, const std::vector<double>& face_deflection,
                 const std::vector<double>& face_size, const RemeshPlan& plan, std::vector<char>* remeshed = nullptr);
// Before it: how many times its facets a face may get, from what the whole
// surface would get; and where each border piece (edge_key of its ends)
// must be cut for the faces' meshes to be round (Ruppert's segment splits):
// at the nodes CGAL's planning run put on it, cut before remesh_faces. Cut
// instead in halves until it had as many pieces (until 2026-11-26), the two
// sides of a 0 deg corner got nodes at other distances from it, and the
// face kept triangles of 179.8 deg between them (occt_MODERN_Exhaust_1.brep,
// whose recovery then ran away there).
struct RemeshPlan {
  double growth_limit = 0;
  // By face index: faces past growth_limit that the surface's budget still
  // takes (plan_remeshing).
  std::vector<char> past_limit;
  // Per border piece: where the mesher put its nodes, as fractions of the
  // piece's length from its end with the lower vertex id.
  std::map<std::uint64_t, std::vector<double>> border_nodes;
  // A face's sharp corner (its angle under 20 deg) and the two border
  // pieces that leave it, with their lengths: their first nodes are put as
  // far from it (plan_remeshing).
  struct SharpCorner {
    int corner;
    std::array<std::uint64_t, 2> pieces;
    std::array<double, 2> lengths;
  };
  std::vector<SharpCorner> sharp_corners;
};
RemeshPlan plan_remeshing(const CadModel::Impl& cad, CadSurface& s, const std::vector<double>& face_deflection,
                          const std::vector<double>& face_size);

}  // namespace vd::cad
