// Vertices that open the flat "caps" the sliver pass cannot reach.
//
// Where the surface folds by a few degrees (a faceted sphere, a tessellated
// cylinder), the Delaunay tetrahedralization may fill the fold with a flat
// tetrahedron whose four vertices are surface vertices and two of whose faces
// are the facets beside the fold edge. Case A would remove it by flipping the
// fold edge, which cuts the fold off the surface; flips inside the region do
// not reach a tetrahedron held by two facets; its surface vertices do not
// move off a curved face. A vertex inside the region, in the cap's
// circumsphere, destroys it in the Delaunay sense: the two facets then meet
// that vertex instead, and the sliver pass may move it (it is an interior
// vertex). TetGen's refinement reaches the same tetrahedra by inserting
// circumcentres.
#pragma once

#include <vector>

#include "delaunay/delaunay_tetrahedralization.h"
#include "mesh/mesh.h"

namespace vd {

class SurfaceGeometry;

// For every tetrahedron of m with a dihedral angle under sliver_angle_deg and
// two faces on the surface whose normals differ by more than ridge_angle_deg
// (case A would refuse it), a point on the cap's side (that of its fourth
// vertex from each facet, so that caps on a surface inside one region are
// reached too), inward of the middle of the fold edge,
// 0.35 of its length deep, or of the cap's centroid, or less deep (0.2, 0.1,
// 0.05, 0.02, 0.01, 0.005), the first that lies in the cap's circumsphere,
// else the cap's centroid; kept when it is in the
// cap's region (located in dt, whose vertices are m.points), not closer to a
// vertex of the tetrahedron it falls in than `clearance` times the fold edge
// (kCapPointClearance on faceted input, kCapPointClearanceCad on CAD), nor
// to another cap point than a tenth of it.
// One point per fold edge. Also the centroid of each tetrahedron under 1 deg
// of four surface vertices, no face on the surface, two of whose vertices
// are on opposite sides of a wall (the normals into the region there point
// more than 120 deg apart) or whose centroid is 0.15 of its longest edge
// from the planes of the facets at its vertices (across a groove). Pre: dt's
// tetrahedra carry their region labels (build_region_tetrahedra leaves them
// so).
struct CapPoint {
  Vec3 point;
  // For a cap whose fold is a side of a sharp border corner (which
  // split_cap_folds leaves): points under the middles of the cap's other
  // surface edges, for when `point` would take a facet.
  std::vector<Vec3> fallbacks;
  // The fold edge, split when the point is refused; for a centroid, the
  // tetrahedron's longest edge on the surface (-1 when none is).
  std::array<int, 2> fold{-1, -1};
  // The cap's smallest dihedral angle. When the fold lies inside a face, a
  // point whose new tetrahedra would be nearly flat and no fairer than the
  // cap is refused too (its fold is split then).
  double cap_angle_deg = 0;
  bool fold_inside_a_face = false;
};
//
// The clearance: a shallow point under a flat cap makes a short edge, and the
// sliver pass then fights the slivers around it; on gmsh_lever.stl's strip
// of needle facets nearly all the tetrahedra under 10 deg away from small
// input angles were at such points. On faceted input, 0.3 (0.1 until
// 2026-12-02): the lever's seeds 1 to 12 went from 22.8 such tetrahedra on
// average (15 to 32) to 7.8 (1 to 15), all 12 under 0.1 %, and from 1,035
// tetrahedra under 10 deg to 801; at 0.25, 0.35, 0.4 and 0.5 (seeds 1 to
// 6) 14.3, 13.8, 10.0 and 7.5, the larger ones with smallest angles down to
// 1.1 deg where 0.3 kept 2.4. On CAD input the caps left without a point
// stay: at 0.3 the U-joint fell from 0.21 to 0.001 deg and the Exhaust from
// 2.41 to 0.03; with the crowded points refused so that their folds are
// split on the faces, the U-joint still fell to 0.001; at 0.3 for caps of 1
// deg and more only, 10 files of the corpus had 794 tetrahedra under 10 deg
// against 741, with four smallest angles up and four down.
constexpr double kCapPointClearance = 0.3;
constexpr double kCapPointClearanceCad = 0.1;
std::vector<CapPoint> cap_breaking_points(const Mesh& m, const DelaunayTetrahedralization& dt,
                                          double sliver_angle_deg, double ridge_angle_deg, double clearance);

// Inserts each point into dt and m.points, one by one, unless it would make a
// surface facet stop being a face of dt (a point near a concave fold can), or
// its new tetrahedra would be nearly flat and no fairer than the cap over a
// fold inside a face (`refuse_unfair`): that is asked of dt's conflict zone
// first. The surface stays as it is, so
// no recovery (with its flips across folds) is needed, and the new tetrahedra
// take the label of their region (dt.labelled_cells() gives them). A point
// refused gives way to the fallback that keeps every facet and whose new
// tetrahedra have the largest smallest dihedral angle. Returns how many went
// in; the fold edges of the caps refused go to `refused_folds`.
// `refuse_unfair`: the refusal of nearly flat points over a fold inside a
// face (CAD input, whose fold splits go onto the face; on faceted input it
// split more of gmsh_lever.stl's folds, 1,663 -> 1,729 tetrahedra under 10
// deg, and changed no smallest angle of the other shared surfaces).
int insert_cap_vertices(Mesh& m, DelaunayTetrahedralization& dt, const std::vector<CapPoint>& points,
                        std::vector<std::array<int, 2>>* refused_folds = nullptr, long* from_fallbacks = nullptr,
                        bool refuse_unfair = false);

// For the caps no point can open without taking a facet (on a surface with
// one region on both sides, the facets' Delaunay apexes on the far side sit
// just beyond them): each fold edge split at its mid-point, in every facet
// that shares it, as TetGen splits an encroached facet. The mid-point lies on
// both facets, so the surface keeps its shape; two nearly right triangles
// over a cocircular quad become four isosceles ones around its centre.
// On CAD input (`geometry`) the mid-point goes onto the true surface where
// a recovery split would (place_split_point), and stays on the chord where
// recovery's would for a solid's volume (`volume_limit`, VolumeKeeper).
// Returns the number of edges split; the new points are appended to
// m.points (and m.point_size, when set). The caller inserts them and recovers. A fold that is a side of a
// face's sharp corner between two border edges stays (counted in
// `left_at_sharp_corners`): splitting it only makes the corner smaller.
int split_cap_folds(Mesh& m, const std::vector<std::array<int, 2>>& folds, const SurfaceGeometry* geometry = nullptr,
                    long* left_at_sharp_corners = nullptr, double volume_limit = 0);

}  // namespace vd
