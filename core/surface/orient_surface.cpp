#include "surface/orient_surface.h"

#include <utility>

#include "surface/edge_map.h"

namespace vd {

int orient_consistently(Mesh& m) {
  const EdgeMap edges(m.triangles);
  std::vector<int> component(m.triangles.size(), -1);
  std::vector<bool> flip(m.triangles.size(), false);
  std::vector<int> stack;
  int components = 0;
  for (size_t seed = 0; seed < m.triangles.size(); ++seed) {
    if (component[seed] >= 0) continue;
    const int c = components++;
    component[seed] = c;
    stack.push_back(static_cast<int>(seed));
    std::vector<int> members;
    while (!stack.empty()) {
      const int f = stack.back();
      stack.pop_back();
      members.push_back(f);
      Triangle t = m.triangles[f];
      if (flip[f]) std::swap(t.v[1], t.v[2]);
      for (int i = 0; i < 3; ++i) {
        const int a = t.v[i], b = t.v[(i + 1) % 3];
        const auto& across = edges.facets(a, b);
        if (across.size() != 2) continue;
        const int g = across[0] == f ? across[1] : across[0];
        if (component[g] >= 0) continue;
        component[g] = c;
        // g must run the edge b -> a.
        flip[g] = has_directed_edge(m.triangles[g], a, b);
        stack.push_back(g);
      }
    }
    double volume = 0;
    const Vec3 o = m.points[m.triangles[seed].v[0]];
    for (int f : members) {
      Triangle t = m.triangles[f];
      if (flip[f]) std::swap(t.v[1], t.v[2]);
      volume += dot(cross(m.points[t.v[0]] - o, m.points[t.v[1]] - o), m.points[t.v[2]] - o);
    }
    if (volume < 0)
      for (int f : members) flip[f] = !flip[f];
  }
  int turned = 0;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    if (flip[f]) {
      std::swap(m.triangles[f].v[1], m.triangles[f].v[2]);
      // Edges 01, 12, 20 of the turned corners are 20, 12, 01 of the old:
      // second-order surfaces came out with nodes on other edges.
      if (m.triangle_mid.size() == m.triangles.size()) std::swap(m.triangle_mid[f][0], m.triangle_mid[f][2]);
      ++turned;
    }
  return turned;
}

}  // namespace vd
