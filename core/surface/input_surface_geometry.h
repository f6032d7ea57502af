// The input surface as the geometry of faceted input, for the sliver pass.
//
// On CAD input a surface vertex inside a curved face slides on the CAD face
// in the sliver pass (case C). Faceted input has no other geometry than its
// facets: a vertex inside a curved face slides on them instead, onto the
// nearest point of the input facets of its face. Before, only vertices of
// flat patches and straight creases could move, and on gmsh_lever.stl most
// tetrahedra left under 10 deg had a face on the fillets' needle strips.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "geometry/triangle_index.h"
#include "mesh/mesh.h"
#include "surface/surface_geometry.h"

namespace vd {

class InputSurfaceGeometry : public SurfaceGeometry {
 public:
  // The facets of `input` with their face ids as they will be in the mesh
  // (after the face patches are assigned). `faces_given`: some face ids are
  // the input's own, not patches split at sharp edges, and a face may go
  // round a corner.
  InputSurfaceGeometry(const Mesh& input, bool faces_given);
  // Splits stay on the chord (the paper's behaviour on faceted input).
  Vec3 place_on_surface(const std::vector<int>&, const Vec3& chord) const override { return chord; }
  std::optional<Vec3> project_onto_face(int face, const Vec3& p, const Vec3& near) const override;
  bool faces_may_be_sharp() const override { return faces_given_; }

 private:
  // By face id, until the face's index is built from them (the index keeps
  // its own copy).
  mutable std::map<int, std::vector<std::array<Vec3, 3>>> facets_;
  // Built at a face's first projection: most faces have no vertex that moves.
  mutable std::map<int, std::unique_ptr<TriangleIndex>> index_;
  bool faces_given_;
};

}  // namespace vd
