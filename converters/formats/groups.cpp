#include "groups.h"

#include <set>

#include "io_util.h"

namespace vd::io::detail {

std::vector<int> face_ids_for_groups(const std::vector<std::string>& names, Mesh& m) {
  std::vector<int> ids;
  std::set<int> seen;
  for (const std::string& n : names) {
    const int k = id_from_name(n, "Face");
    if (k < 1 || !seen.insert(k).second) {
      ids.clear();
      break;
    }
    ids.push_back(k);
  }
  if (ids.size() != names.size()) {
    ids.clear();
    for (size_t i = 0; i < names.size(); ++i) ids.push_back(static_cast<int>(i) + 1);
  }
  for (size_t i = 0; i < names.size(); ++i)
    if (!names[i].empty()) m.face_names[ids[i]] = names[i];
  return ids;
}

}  // namespace vd::io::detail
