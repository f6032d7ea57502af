// Triangulation of one planar facet of a PLC (TetGen .poly/.smesh): polygons
// in a plane, some nested in others; a nested polygon bounds a hole when a
// hole point lies in it, else it only splits the facet.
#pragma once

#include <array>
#include <vector>

#include "mesh/mesh.h"

namespace vd::io::detail {

// Triangles (point indices) covering the facet, each turned like the facet's
// first polygon. Polygons with fewer than 3 vertices (segments, points in the
// facet) are ignored. Never fails: a polygon ear clipping cannot finish is
// completed as a fan.
std::vector<std::array<int, 3>> triangulate_facet(const std::vector<Vec3>& points,
                                                  const std::vector<std::vector<int>>& polygons,
                                                  const std::vector<Vec3>& holes);

// One polygon of a surface file (OFF, OBJ): a fan when the polygon is
// convex in its plane, as every such file's quads are, else the facet
// triangulation above. A fan over a non-convex polygon folds: an L-shaped
// cap came out with area 4 for 3, and the solid was refused as
// self-intersecting, until 2026-11-30.
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Vec3>& points, const std::vector<int>& polygon);
// The fan from the polygon's first vertex.
std::vector<std::array<int, 3>> fan(const std::vector<int>& polygon);
// A triangle strip's triangles (VTK's TRIANGLE_STRIPS, PLY's tristrips):
// triangle j is (j, j+1, j+2), every other one turned so that all face as
// the first; repeated vertices (strips joined by degenerate triangles) give
// no triangle.
std::vector<std::array<int, 3>> strip_triangles(const int* strip, size_t count);

}  // namespace vd::io::detail
