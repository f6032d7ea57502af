#include "pipeline/missing_facets.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "mesh/number_text.h"

namespace vd {

namespace {

std::string point_text(const Vec3& p) {
  return "(" + number_text(p.x, "%.4g") + ", " + number_text(p.y, "%.4g") + ", " + number_text(p.z, "%.4g") + ")";
}

}  // namespace

std::string where_facets_are_missing(const Mesh& m, const std::vector<int>& missing) {
  if (missing.empty()) return {};
  // Places: the missing facets' centres binned on a grid of a fiftieth of
  // the surface's extent; a bin and its 26 neighbours make a place, the
  // fullest first, and a place takes its facets out of later ones.
  Vec3 lo = m.points[m.triangles[missing[0]].v[0]], hi = lo;
  for (const Triangle& t : m.triangles)
    for (int v : t.v)
      for (int i = 0; i < 3; ++i) lo[i] = std::min(lo[i], m.points[v][i]), hi[i] = std::max(hi[i], m.points[v][i]);
  const double cell = std::max(norm(hi - lo) / 50.0, 1e-300);
  struct Bin {
    int count = 0;
    Vec3 sum{0, 0, 0};
  };
  std::map<std::array<long, 3>, Bin> bins;  // ordered: ties go the same way every run
  for (int f : missing) {
    const Triangle& t = m.triangles[f];
    const Vec3 c = (1.0 / 3.0) * (m.points[t.v[0]] + m.points[t.v[1]] + m.points[t.v[2]]);
    Bin& b = bins[{long(std::floor((c.x - lo.x) / cell)), long(std::floor((c.y - lo.y) / cell)),
                   long(std::floor((c.z - lo.z) / cell))}];
    ++b.count;
    b.sum = b.sum + c;
  }
  std::ostringstream s;
  s << "most of them near";
  for (int place = 0; place < 3 && !bins.empty(); ++place) {
    auto fullest = std::max_element(bins.begin(), bins.end(),
                                    [](const auto& a, const auto& b) { return a.second.count < b.second.count; });
    const auto key = fullest->first;
    Bin total;
    for (long dz = -1; dz <= 1; ++dz)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dx = -1; dx <= 1; ++dx) {
          auto it = bins.find({key[0] + dx, key[1] + dy, key[2] + dz});
          if (it == bins.end()) continue;
          total.count += it->second.count;
          total.sum = total.sum + it->second.sum;
          bins.erase(it);
        }
    // A place of under a tenth of the facets is not worth naming after the first.
    if (place > 0 && total.count * 10 < static_cast<int>(missing.size())) break;
    s << (place ? " and " : " ") << point_text((1.0 / total.count) * total.sum) << " (" << total.count << ")";
  }
  std::unordered_map<int, int> per_face;
  for (int f : missing) ++per_face[m.triangles[f].face];
  std::vector<std::pair<int, int>> faces(per_face.begin(), per_face.end());  // (face, count)
  std::sort(faces.begin(), faces.end(), [](const auto& a, const auto& b) {
    return a.second != b.second ? a.second > b.second : a.first < b.first;
  });
  s << "; faces";
  for (size_t i = 0; i < faces.size() && i < 6; ++i) {
    const auto name = m.face_names.find(faces[i].first);
    s << (i ? ", " : " ")
      << (name != m.face_names.end() ? name->second : faces[i].first == kNoFace ? std::string("untagged")
                                                                                 : std::to_string(faces[i].first))
      << " (" << faces[i].second << ")";
  }
  if (faces.size() > 6) s << " and " << faces.size() - 6 << " more";
  return s.str();
}

}  // namespace vd
