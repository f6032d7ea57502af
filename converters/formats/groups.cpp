#include "groups.h"

#include <map>
#include <set>

#include "io_util.h"

namespace vd::io::detail {

std::vector<int> face_ids_for_groups(const std::vector<std::string>& names, Mesh& m) {
  // Groups of one name are one face: vdmesh's ASCII STL starts a solid each
  // time the face changes in facet order (11 faces were read back as 195),
  // and OBJ may name a group again. Unnamed groups stay apart.
  std::map<std::string, int> index;
  std::vector<std::string> unique;
  std::vector<int> group(names.size());
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].empty()) {
      group[i] = static_cast<int>(unique.size());
      unique.emplace_back();
      continue;
    }
    const auto [it, added] = index.emplace(names[i], static_cast<int>(unique.size()));
    if (added) unique.push_back(names[i]);
    group[i] = it->second;
  }
  std::vector<int> id;
  std::set<int> seen;
  for (const std::string& n : unique) {
    const int k = id_from_name(n, "Face");
    if (k < 1 || !seen.insert(k).second) {
      id.clear();
      break;
    }
    id.push_back(k);
  }
  if (id.size() != unique.size()) {
    id.clear();
    for (size_t u = 0; u < unique.size(); ++u) id.push_back(static_cast<int>(u) + 1);
  }
  for (size_t u = 0; u < unique.size(); ++u)
    if (!unique[u].empty()) m.face_names[id[u]] = unique[u];
  std::vector<int> ids(names.size());
  for (size_t i = 0; i < names.size(); ++i) ids[i] = id[static_cast<size_t>(group[i])];
  return ids;
}

}  // namespace vd::io::detail
