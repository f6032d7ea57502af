// Abaqus / CalculiX input deck (.inp). Writes *NODE, one *ELEMENT block per
// region (C3D4 or C3D10, ELSET = the region's name), and per face id an
// element-based *SURFACE (tetrahedron faces S1..S4) plus an *NSET of its
// nodes: no *HEADING (a deck allows one, and ours is meant to be included),
// no 2D elements in a solid deck (CalculiX wants a section for every element).
// A mesh without tetrahedra is written as S3/STRI65 shells, one ELSET per face.
// Reads nodes, tetrahedra, triangle shells, ELSETs and element surfaces back,
// through *INCLUDE files too.
#include <algorithm>
#include <cerrno>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>

#include "formats.h"
#include "io_util.h"

namespace vd::io {
namespace {

using detail::Cursor;
using detail::FileBytes;

// C3D4 / C3D10 faces S1..S4 by corner (0-based).
const int kFaces[4][3] = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};

// Abaqus names: letters, digits and '_', starting with a letter.
std::string sanitized(const std::string& name) {
  std::string r;
  for (char c : name) r += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (r.empty() || !std::isalpha(static_cast<unsigned char>(r[0]))) r = "S" + r;
  return r;
}

// Set names CalculiX takes and Abaqus keeps apart: sanitized, at most 80
// characters with "_Nodes" added (CalculiX stops at "set name too long"),
// and unique regardless of case, Abaqus's names being case-blind: "Steel"
// and "steel", or "part A" and "part_A", were written as one set until
// 2026-11-30, and read back as one region.
class SetNames {
 public:
  std::string unique(const std::string& wanted) {
    constexpr size_t kLongest = 80 - 6;  // room for "_Nodes"
    const std::string base = sanitized(wanted).substr(0, kLongest);
    std::string name = base;
    for (int k = 2; !taken_.insert(detail::to_upper(name)).second; ++k) {
      const std::string suffix = "_" + std::to_string(k);
      name = base.substr(0, kLongest - suffix.size()) + suffix;
    }
    return name;
  }

 private:
  std::set<std::string> taken_;
};

// CalculiX reads each field of a data line through 20 characters: a longer
// number stops it ("ERROR reading *NODE"), and 4.8502286207676093E-05 is 22.
// The shortest exact text is written when it fits, else the most digits that do.
std::string_view abaqus_number(double v, char (&buf)[32]) {
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  for (int digits = 16; r.ptr - buf > 20 && digits > 0; --digits)
    r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, digits);
  return {buf, static_cast<size_t>(r.ptr - buf)};
}

void node_list(detail::Out& out, const std::vector<int>& ids) {
  for (size_t i = 0; i < ids.size(); ++i) out << ids[i] + 1 << ((i + 1) % 16 == 0 || i + 1 == ids.size() ? "\n" : ", ");
}

// Calls visit(tet, face, triangle) for every tetrahedron face that is a
// triangle of the mesh (face: Abaqus's S1..S4 as 0..3).
template <class Visit>
void for_each_tet_face_on_triangle(const Mesh& m, Visit visit) {
  using Key = std::array<int, 3>;
  auto key = [](Key k) {
    std::sort(k.begin(), k.end());
    return k;
  };
  std::vector<std::pair<Key, int>> index;
  index.reserve(m.triangles.size());
  for (size_t i = 0; i < m.triangles.size(); ++i) index.push_back({key(m.triangles[i].v), static_cast<int>(i)});
  std::sort(index.begin(), index.end());
  for (size_t ti = 0; ti < m.tets.size(); ++ti) {
    const Tetrahedron& t = m.tets[ti];
    for (int f = 0; f < 4; ++f) {
      const Key k = key({t.v[kFaces[f][0]], t.v[kFaces[f][1]], t.v[kFaces[f][2]]});
      for (auto it = std::lower_bound(index.begin(), index.end(), std::make_pair(k, -1));
           it != index.end() && it->first == k; ++it)
        visit(static_cast<int>(ti), f, static_cast<size_t>(it->second));
    }
  }
}

// For each triangle, the (tetrahedron, face) on its front side and on its
// back side ({-1, -1} where none).
struct SideOwners {
  std::pair<int, int> front{-1, -1}, back{-1, -1};
};
std::vector<SideOwners> triangle_side_owners(const Mesh& m) {
  std::vector<SideOwners> owner(m.triangles.size());
  for_each_tet_face_on_triangle(m, [&](int ti, int f, size_t i) {
    const Triangle& tri = m.triangles[i];
    // The corner off face f lies behind the triangle when it is on the
    // side its normal points away from.
    static constexpr int kOff[4] = {3, 2, 0, 1};
    const int apex = m.tets[static_cast<size_t>(ti)].v[kOff[f]];
    const double side = detail::tet_det(m, {tri.v[0], tri.v[1], tri.v[2], apex});
    (side < 0 ? owner[i].back : owner[i].front) = {ti, f};
  });
  return owner;
}

// The region whose element sides a face group's *SURFACE names, by group:
// the solid inside its facets on the exterior, when they agree; for a
// group of interface facets only (a face glued whole to another solid's),
// of the two groups on the interface the lower-numbered one takes the
// lower-numbered region, as CAD numbers faces solid by solid (FreeCAD's
// Face<j> of Solid<k>). Until 2026-11-30 both groups named the sides in the
// region behind the facet, so one solid's face listed the other's elements.
std::map<int, int> group_regions(const Mesh& m, const std::map<int, std::vector<size_t>>& by_group) {
  std::map<int, int> region;
  for (const auto& [g, tris] : by_group) {
    int found = 0;
    for (size_t i : tris) {
      const Triangle& t = m.triangles[i];
      if ((t.front == 0) == (t.back == 0)) continue;
      const int r = std::max(t.front, t.back);
      found = found == 0 || found == r ? r : -1;
    }
    if (found > 0) region[g] = found;
  }
  // Groups of interface facets only: the other side of the facet from the
  // partner group's solid where that is known, else the numbering.
  const std::map<int, int> known = region;
  for (const auto& [g, tris] : by_group) {
    if (region.count(g) || tris.empty()) continue;
    const Triangle& t = m.triangles[tris.front()];
    const std::vector<int> groups = face_groups_of(m, t.face);
    if (groups.size() != 2 || t.front <= 0 || t.back <= 0 || t.front == t.back) continue;
    const int partner = groups[0] == g ? groups[1] : groups[0];
    const auto other = known.find(partner);
    if (other != known.end() && (other->second == t.front || other->second == t.back)) {
      region[g] = other->second == t.front ? t.back : t.front;
      continue;
    }
    const bool lower = g == std::min(groups[0], groups[1]);
    region[g] = lower ? std::min(t.front, t.back) : std::max(t.front, t.back);
  }
  return region;
}

// For each triangle: (tetrahedron, face 0..3) having it as a face, preferring
// the tetrahedron behind it (its back region); (-1, -1) when none.
std::vector<std::pair<int, int>> triangle_owners(const Mesh& m) {
  std::vector<std::pair<int, int>> owner(m.triangles.size(), {-1, -1});
  for_each_tet_face_on_triangle(m, [&](int ti, int f, size_t i) {
    auto& o = owner[i];
    if (o.first < 0 || m.tets[static_cast<size_t>(ti)].region == m.triangles[i].back) o = {ti, f};
  });
  return owner;
}

void write_abaqus(const Mesh& m, const std::string& path, const WriteOptions&) {
  detail::Out out(path);
  out << "** Mesh written by vdmesh: add *MATERIAL, *SOLID SECTION and *STEP.\n";
  out << "*NODE, NSET=NALL\n";
  for (size_t i = 0; i < m.points.size(); ++i) {
    const Vec3& p = m.points[i];
    char buf[32];
    out << i + 1 << ", " << abaqus_number(p.x, buf);
    out << ", " << abaqus_number(p.y, buf);
    out << ", " << abaqus_number(p.z, buf) << '\n';
  }
  std::map<int, std::vector<size_t>> by_face;
  for (size_t i = 0; i < m.triangles.size(); ++i) by_face[m.triangles[i].face].push_back(i);
  // The named groups of faces: a facet on two CAD faces is in both
  // (Mesh::face_groups); the shells' element blocks below stay one per face.
  std::map<int, std::vector<size_t>> by_group;
  for (const auto& [f, tris] : by_face)
    for (const int g : face_groups_of(m, f)) {
      std::vector<size_t>& into = by_group[g];
      into.insert(into.end(), tris.begin(), tris.end());
    }
  for (auto& [g, tris] : by_group) std::sort(tris.begin(), tris.end());
  std::map<int, std::vector<size_t>> by_region;
  for (size_t i = 0; i < m.tets.size(); ++i) by_region[m.tets[i].region].push_back(i);
  SetNames names;
  std::map<int, std::string> region_set, face_set_name;
  for (const auto& [r, tets] : by_region)
    region_set[r] = names.unique(r == kUnknownRegion ? "RegionUnknown" : detail::region_name(m, r));
  const auto& named_faces = m.tets.empty() ? by_face : by_group;
  for (const auto& [f, tris] : named_faces)
    face_set_name[f] = names.unique(f == kNoFace ? "FaceNone" : detail::face_name(m, f));
  auto face_set = [&](int f) { return face_set_name.at(f); };
  // Ids a set's name does not carry (Region<k>, Solid<k>, Face<k> do), for
  // the reader: a named region came back numbered by its lowest element.
  for (const auto& [r, name] : region_set)
    if (r > 0 && detail::id_from_name(name, "Region") != r && detail::id_from_name(name, "Solid") != r)
      out << "** vdmesh region " << r << ' ' << name << '\n';
  for (const auto& [f, name] : face_set_name)
    if (f >= 0 && detail::id_from_name(name, "Face") != f) out << "** vdmesh face " << f << ' ' << name << '\n';

  if (m.tets.empty()) {
    const bool quad = !m.triangle_mid.empty();
    for (const auto& [f, tris] : by_face) {
      out << "*ELEMENT, TYPE=" << (quad ? "STRI65" : "S3") << ", ELSET=" << face_set(f) << '\n';
      for (size_t i : tris) {
        // Shells alone: nothing says a triangle's sides.
        const Triangle& t = m.triangles[i];
        const std::array<int, 3> v = detail::corners_without_sides(t);
        out << i + 1 << ", " << v[0] + 1 << ", " << v[1] + 1 << ", " << v[2] + 1;
        if (quad)
          for (int x : detail::mid_nodes_without_sides(t, m.triangle_mid[i])) out << ", " << x + 1;
        out << '\n';
      }
    }
  } else {
    const bool quad = !m.tet_mid.empty();
    for (const auto& [r, tets] : by_region) {
      out << "*ELEMENT, TYPE=" << (quad ? "C3D10" : "C3D4") << ", ELSET=" << region_set.at(r) << '\n';
      for (size_t i : tets) {
        const Tetrahedron& t = m.tets[i];
        out << i + 1;
        for (int v : t.v) out << ", " << v + 1;
        if (quad)
          for (int v : m.tet_mid[i]) out << ", " << v + 1;
        out << '\n';
      }
    }
    // A node set per region too: *BOUNDARY or *INITIAL CONDITIONS on a solid
    // want its nodes, and CalculiX cannot take them from an element set.
    std::vector<int> seen(m.points.size(), 0);
    int stamp = 0;
    for (const auto& [r, tets] : by_region) {
      ++stamp;
      std::vector<int> nodes;
      for (size_t i : tets) {
        for (int v : m.tets[i].v)
          if (seen[v] != stamp) seen[v] = stamp, nodes.push_back(v);
        if (quad)
          for (int v : m.tet_mid[i])
            if (seen[v] != stamp) seen[v] = stamp, nodes.push_back(v);
      }
      std::sort(nodes.begin(), nodes.end());
      out << "*NSET, NSET=" << region_set.at(r) << "_Nodes\n";
      node_list(out, nodes);
    }
    const auto owner = triangle_owners(m);
    const auto sides = triangle_side_owners(m);
    const std::map<int, int> group_region = group_regions(m, by_group);
    for (const auto& [f, tris] : by_group) {
      // The side in the group's region where the facet has one there.
      const auto it = group_region.find(f);
      const auto side_of = [&](size_t i) {
        if (it != group_region.end()) {
          const Triangle& t = m.triangles[i];
          if (t.front == it->second && sides[i].front.first >= 0) return sides[i].front;
          if (t.back == it->second && sides[i].back.first >= 0) return sides[i].back;
        }
        return owner[i];
      };
      bool any = false;
      for (size_t i : tris) any |= side_of(i).first >= 0;
      if (!any) continue;
      out << "*SURFACE, NAME=" << face_set(f) << ", TYPE=ELEMENT\n";
      for (size_t i : tris) {
        const auto [tet, face] = side_of(i);
        if (tet >= 0) out << tet + 1 << ", S" << face + 1 << '\n';
      }
    }
  }
  for (const auto& [f, tris] : named_faces) {
    std::set<int> nodes;
    for (size_t i : tris) {
      nodes.insert(m.triangles[i].v.begin(), m.triangles[i].v.end());
      if (!m.triangle_mid.empty()) nodes.insert(m.triangle_mid[i].begin(), m.triangle_mid[i].end());
    }
    out << "*NSET, NSET=" << face_set(f) << "_Nodes\n";
    node_list(out, std::vector<int>(nodes.begin(), nodes.end()));
  }
  out.finish();
}

// ---------------------------------------------------------------------------
// reader

struct Keyword {
  std::string name;                           // upper case, without '*'
  std::map<std::string, std::string> options;  // upper-case keys
};

class InpReader {
 public:
  InpReader(const FileBytes& data, const std::string& path) {
    sources_.push_back(std::make_unique<Source>(nullptr, data, path));
    in_ = &sources_.back()->cursor;
    total_bytes_ = data.size();
  }
  Mesh read();

 private:
  Keyword keyword(std::string_view line);
  bool at_data_line();
  // The numbers of one data line, continued over lines ending with ','.
  std::vector<std::string_view> fields(size_t want);
  void nodes();
  void elements(const Keyword& k);
  void elset(const Keyword& k);
  void surface(const Keyword& k);
  void skip_data();
  void keyword_data(const Keyword& k);
  void instance();
  int parts_ = 0, instances_ = 0, includes_ = 0;
  size_t keyword_line_ = 0;  // the line of the keyword being read
  void include(const Keyword& k, size_t line);
  int node(std::string_view field);

  // Fails naming the first line of the data just read by fields().
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(in_->name() + ":" + std::to_string(data_line_) + ": " + what);
  }

  // The deck and the files it includes, the one being read last.
  struct Source {
    std::unique_ptr<FileBytes> owned;  // null for the deck itself
    Cursor cursor;
    Source(std::unique_ptr<FileBytes> file, const FileBytes& bytes, const std::string& path)
        : owned(std::move(file)), cursor(bytes, path) {
      cursor.set_comma_separates(true);
    }
  };
  std::vector<std::unique_ptr<Source>> sources_;
  Cursor* in_ = nullptr;
  size_t total_bytes_ = 0;
  size_t data_line_ = 0;
  Mesh m_;
  detail::IdIndex node_index_;
  // Tetrahedra go straight into the mesh; until the end their region field
  // holds their ELSET (an index into set_names_, -1 for none). Per-element
  // records with two set names each were 11 times the mesh on 1M tetrahedra.
  detail::TagList tet_ids_;
  detail::IdIndex tet_index_;
  std::vector<std::string> set_names_;
  std::map<std::string, int> set_index_;
  int set_of(const std::string& name);
  std::map<std::string, int> shell_face_;   // ELSET of shell elements -> face id
  struct Shell {
    int64_t id;
    Triangle t;
    TriMidNodes mid;
    std::string set;
  };
  std::vector<Shell> shells_;
  // *ELSET lists by upper-case name: element numbers, and the names of sets
  // they include (FreeCAD's decks list their element blocks' sets by name).
  struct ElementSet {
    std::vector<int64_t> ids;
    std::vector<std::string> sets;
  };
  std::map<std::string, ElementSet> elsets_;
  std::vector<std::string> elset_order_;       // upper-case names, as first written
  std::vector<std::string> section_sets_;      // *SOLID SECTION ELSETs, upper-case, in order
  void regions_from_sets();
  bool quad_shells_ = false;
  std::vector<std::pair<std::string, std::vector<std::pair<int64_t, int>>>> surfaces_;
  std::vector<std::pair<std::string, std::vector<std::pair<std::string, int>>>> surface_sets_;
  // The ids vdmesh's writer gives in comments ("** vdmesh region 1 Zeta"),
  // by upper-case set name: names that are no Region<k>, Solid<k>, Face<k>.
  std::map<std::string, int> region_id_of_name_, face_id_of_name_;
  void read_id_comment(std::string_view line);
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

Keyword InpReader::keyword(std::string_view line) {
  Keyword k;
  line.remove_prefix(1);
  size_t at = 0;
  bool first = true;
  while (at <= line.size()) {
    const size_t comma = std::min(line.find(',', at), line.size());
    const std::string_view part = trim(line.substr(at, comma - at));
    if (first) {
      k.name = detail::to_upper(part);
      first = false;
    } else if (!part.empty()) {
      const size_t eq = part.find('=');
      if (eq == std::string_view::npos) k.options[detail::to_upper(part)] = "";
      else k.options[detail::to_upper(trim(part.substr(0, eq)))] = std::string(trim(part.substr(eq + 1)));
    }
    at = comma + 1;
  }
  return k;
}

// True when the next non-comment line is data (not a keyword, not the end).
bool InpReader::at_data_line() {
  for (;;) {
    if (in_->at_end()) return false;
    const std::string_view rest = in_->data().substr(in_->pos());
    if (rest.compare(0, 2, "**") == 0) {
      if (rest.compare(0, 10, "** vdmesh ") == 0) read_id_comment(rest.substr(0, std::min(rest.find('\n'), rest.size())));
      in_->skip_line();
      continue;
    }
    return rest[0] != '*';
  }
}

void InpReader::read_id_comment(std::string_view line) {
  line = trim(line.substr(10));
  const bool region = line.compare(0, 7, "region ") == 0, face = line.compare(0, 5, "face ") == 0;
  if (!region && !face) return;
  line = trim(line.substr(region ? 7 : 5));
  const size_t space = line.find(' ');
  if (space == std::string_view::npos) return;
  int64_t id = 0;
  // Within what a name Region<k> or Face<k> can say (9 digits), so that the
  // numbers after them cannot overflow.
  if (!Cursor::parse_int(line.substr(0, space), id) || id < (region ? 1 : 0) || id > 999999999) return;
  const std::string name = detail::to_upper(trim(line.substr(space + 1)));
  if (!name.empty()) (region ? region_id_of_name_ : face_id_of_name_).emplace(name, static_cast<int>(id));
}

std::vector<std::string_view> InpReader::fields(size_t want) {
  data_line_ = in_->line();
  std::vector<std::string_view> f;
  for (;;) {
    for (std::string_view t = in_->token_in_line(); !t.empty(); t = in_->token_in_line()) f.push_back(t);
    // A line ending in a comma continues on the next one.
    const std::string_view data = in_->data();
    size_t back = in_->pos();
    while (back > 0 && (data[back - 1] == ' ' || data[back - 1] == '\t' || data[back - 1] == '\r')) --back;
    const bool continued = back > 0 && data[back - 1] == ',' && f.size() < want;
    in_->skip_line();
    if (!continued || !at_data_line()) break;
  }
  return f;
}

int InpReader::node(std::string_view field) {
  int64_t id;
  if (!Cursor::parse_int(field, id)) fail("expected a node number, found '" + std::string(field.substr(0, 40)) + "'");
  const int index = node_index_.find(id);
  if (index < 0) fail("node " + std::to_string(id) + " does not exist");
  return index;
}

int InpReader::set_of(const std::string& name) {
  if (name.empty()) return -1;
  // Abaqus set names are not case-sensitive: Steel and STEEL are one set,
  // named as first written.
  const auto [it, added] = set_index_.emplace(detail::to_upper(name), static_cast<int>(set_names_.size()));
  if (added) set_names_.push_back(name);
  return it->second;
}

void InpReader::skip_data() {
  while (at_data_line()) in_->skip_line();
}

void InpReader::nodes() {
  while (at_data_line()) {
    const size_t line = in_->line();
    const auto f = fields(4);
    if (f.empty()) continue;
    int64_t id;
    if (!Cursor::parse_int(f[0], id)) fail("expected a node number, found '" + std::string(f[0].substr(0, 40)) + "'");
    Vec3 p;
    for (int k = 0; k < 3; ++k) {
      double v = 0;
      if (static_cast<size_t>(k + 1) < f.size() && !Cursor::parse_real(f[static_cast<size_t>(k + 1)], v))
        throw InputError(in_->name() + ":" + std::to_string(line) + ": bad coordinate '" +
                         std::string(f[static_cast<size_t>(k + 1)].substr(0, 40)) + "'");
      p[k] = v;
    }
    if (!node_index_.add(id, static_cast<int>(m_.points.size())))
      throw InputError(in_->name() + ":" + std::to_string(line) + ": node " + std::to_string(id) + " appears twice");
    m_.points.push_back(p);
  }
}

void InpReader::elements(const Keyword& k) {
  const auto type_it = k.options.find("TYPE");
  const std::string type = type_it == k.options.end() ? "" : detail::to_upper(type_it->second);
  int nodes = 0;
  bool tet = false;
  // Stress (C3D4, C3D10 and their H, M, T... variants) and heat transfer
  // (DC3D4, DC3D10) tetrahedra; DC3D4 was skipped until 2026-11-30.
  const std::string solid = type.rfind("DC3D", 0) == 0 ? type.substr(1) : type;
  if (solid.rfind("C3D4", 0) == 0) nodes = 4, tet = true;
  else if (solid.rfind("C3D10", 0) == 0) nodes = 10, tet = true;
  else if (solid.rfind("C3D", 0) == 0)
    throw InputError(in_->name() + ":" + std::to_string(keyword_line_) + ": *ELEMENT, TYPE=" + type +
                     ": vdmesh reads tetrahedra (C3D4, C3D10) of the solid elements only, and would lose these");
  else if (type == "S3" || type == "S3R" || type == "CPS3" || type == "CPE3" || type == "M3D3" || type == "R3D3" ||
           type == "STRI3" || type == "SFM3D3")
    nodes = 3;
  else if (type == "STRI65" || type == "S6" || type == "CPS6" || type == "CPE6" || type == "M3D6" || type == "SFM3D6")
    nodes = 6;
  if (nodes == 0) return skip_data();
  const auto set_it = k.options.find("ELSET");
  const std::string set = set_it == k.options.end() ? "" : set_it->second;
  const int set_index = tet ? set_of(set) : -1;
  while (at_data_line()) {
    const auto f = fields(static_cast<size_t>(nodes) + 1);
    if (f.size() != static_cast<size_t>(nodes) + 1)
      fail(type + " element with " + std::to_string(f.size() ? f.size() - 1 : 0) + " nodes, expected " +
               std::to_string(nodes));
    int64_t id;
    if (!Cursor::parse_int(f[0], id)) fail("expected an element number, found '" + std::string(f[0].substr(0, 40)) + "'");
    int v[10];
    for (int j = 0; j < nodes; ++j) v[j] = node(f[static_cast<size_t>(j) + 1]);
    if (tet) {
      if (id < 0) fail("element number " + std::to_string(id) + " is negative");
      if (!tet_index_.add(id, static_cast<int>(m_.tets.size()))) fail("element " + std::to_string(id) + " appears twice");
      if (!m_.tets.empty() && (nodes == 10) != !m_.tet_mid.empty()) fail("C3D4 and C3D10 elements are mixed");
      Tetrahedron t;
      t.v = {v[0], v[1], v[2], v[3]};
      t.region = set_index;
      m_.tets.push_back(t);
      if (nodes == 10) m_.tet_mid.push_back({v[4], v[5], v[6], v[7], v[8], v[9]});
      tet_ids_.push_back(static_cast<uint64_t>(id));
    } else {
      Shell s{id, {}, {}, set};
      s.t.v = {v[0], v[1], v[2]};
      if (nodes == 6) s.mid = {v[3], v[4], v[5]}, quad_shells_ = true;
      shells_.push_back(s);
    }
  }
}

void InpReader::elset(const Keyword& k) {
  const auto it = k.options.find("ELSET");
  if (it == k.options.end()) fail("*ELSET without ELSET=");
  const bool generate = k.options.count("GENERATE") > 0;
  const std::string key = detail::to_upper(it->second);
  if (!elsets_.count(key)) elset_order_.push_back(key);
  set_of(it->second);  // named as first written, like the blocks' sets
  ElementSet& set = elsets_[key];
  std::vector<int64_t>& ids = set.ids;
  while (at_data_line()) {
    const auto f = fields(0);
    std::vector<int64_t> nums;
    for (std::string_view t : f) {
      int64_t v;
      if (Cursor::parse_int(t, v)) nums.push_back(v);
      else if (!generate && !t.empty()) set.sets.push_back(detail::to_upper(t));
    }
    if (generate) {
      if (nums.size() < 2) fail("GENERATE needs first, last[, step]");
      const int64_t step = nums.size() > 2 ? nums[2] : 1;
      if (step <= 0 || nums[1] < nums[0]) fail("bad GENERATE range");
      const uint64_t span = static_cast<uint64_t>(nums[1]) - static_cast<uint64_t>(nums[0]);
      const uint64_t count = span / static_cast<uint64_t>(step) + 1;
      if (count > 4 * static_cast<uint64_t>(total_bytes_)) fail("GENERATE range larger than the file could use");
      for (uint64_t i = 0; i < count; ++i)
        ids.push_back(static_cast<int64_t>(static_cast<uint64_t>(nums[0]) + i * static_cast<uint64_t>(step)));
    } else {
      ids.insert(ids.end(), nums.begin(), nums.end());
    }
  }
}

void InpReader::surface(const Keyword& k) {
  const auto type = k.options.find("TYPE");
  if (type != k.options.end() && detail::to_upper(type->second) != "ELEMENT") return skip_data();
  const auto name = k.options.find("NAME");
  std::vector<std::pair<std::string, int>> entries;
  while (at_data_line()) {
    const auto f = fields(2);
    if (f.size() < 2) fail("a surface line needs an element (or set) and a face");
    const std::string face = detail::to_upper(f[1]);
    if (face.size() != 2 || face[0] != 'S' || face[1] < '1' || face[1] > '4')
      fail("tetrahedron faces are S1..S4, not '" + face.substr(0, 40) + "'");
    entries.push_back({std::string(f[0]), face[1] - '1'});
  }
  surface_sets_.push_back({name == k.options.end() ? "" : name->second, std::move(entries)});
}

// Each tetrahedron's region, as an index into set_names_ in its region
// field: the first *SOLID SECTION whose set holds it (a deck's materials:
// CalculiX's, FreeCAD's and Abaqus/CAE's list their regions' elements in
// *ELSETs apart from the element blocks, and two materials were read as
// one region until 2026-11-29); without sections, the *ELSETs of
// tetrahedra only, when each tetrahedron is in one of them (Gmsh's physical
// groups); else its element block's ELSET. A set Region<k> listing a
// tetrahedron wins over all (vdmesh's own numbering). Sections naming no
// set vdmesh knows (a shell block's, a set defined nowhere) are passed over:
// they ended in "internal error: map::at".
void InpReader::regions_from_sets() {
  std::map<std::string, std::vector<int>> block;  // element block set -> tetrahedra (positions)
  for (size_t i = 0; i < m_.tets.size(); ++i)
    if (m_.tets[i].region >= 0) block[detail::to_upper(set_names_[static_cast<size_t>(m_.tets[i].region)])].push_back(static_cast<int>(i));
  // A set's tetrahedra (sorted, once each) and how many of its elements are
  // not tetrahedra, each set resolved once: a chain of 4,000 sets naming
  // the next took 2.4 s resolved anew for each. A set met again while it is
  // being resolved (a cycle) adds nothing.
  struct Members {
    std::vector<int> tets;
    size_t others = 0;
  };
  std::map<std::string, Members> resolved;
  // Depth first without recursion: a chain of 4,000 sets overflowed the
  // stack under AddressSanitizer.
  const auto members = [&](const std::string& name) -> const Members& {
    if (const auto done = resolved.find(name); done != resolved.end()) return done->second;
    std::set<std::string> open{name};
    std::vector<std::pair<std::string, size_t>> stack{{name, 0}};  // a set, its next inner set
    while (!stack.empty()) {
      const std::string set = stack.back().first;
      const auto e = elsets_.find(set);
      if (e != elsets_.end() && stack.back().second < e->second.sets.size()) {
        const std::string inner = e->second.sets[stack.back().second++];
        if (!resolved.count(inner) && open.insert(inner).second) stack.push_back({inner, 0});
        continue;
      }
      Members out;
      if (const auto b = block.find(set); b != block.end()) out.tets = b->second;
      if (e != elsets_.end()) {
        for (const int64_t id : e->second.ids) {
          const int t = tet_index_.find(id);
          if (t >= 0) out.tets.push_back(t);
          else ++out.others;
        }
        for (const std::string& inner : e->second.sets) {
          const auto m = resolved.find(inner);
          if (m == resolved.end()) continue;  // still open: a cycle adds nothing
          out.tets.insert(out.tets.end(), m->second.tets.begin(), m->second.tets.end());
          out.others += m->second.others;
        }
      }
      std::sort(out.tets.begin(), out.tets.end());
      out.tets.erase(std::unique(out.tets.begin(), out.tets.end()), out.tets.end());
      resolved[set] = std::move(out);
      open.erase(set);
      stack.pop_back();
    }
    return resolved.at(name);
  };
  // A set that holds every tetrahedron says nothing of regions the element
  // blocks give (the usual EALL of a deck, or one material for all): they
  // stand. Where a block has no set (Abaqus/CAE's parts), it does name them.
  const bool blocks_named = std::all_of(m_.tets.begin(), m_.tets.end(), [](const Tetrahedron& t) { return t.region >= 0; });
  const auto telling = [&](const std::string& name) {
    const auto it = set_index_.find(name);
    if (it == set_index_.end()) return false;  // named by a section, defined nowhere
    const Members& m = members(name);
    return !m.tets.empty() && (m.tets.size() < m_.tets.size() || !blocks_named);
  };
  std::vector<std::string> region_sets;
  for (const std::string& name : section_sets_)
    if (telling(name)) region_sets.push_back(name);
  if (region_sets.empty()) {
    std::vector<int> times(m_.tets.size(), 0);
    for (const std::string& name : elset_order_) {
      if (block.count(name) || !telling(name) || members(name).others > 0) continue;
      region_sets.push_back(name);
      for (const int t : members(name).tets) ++times[static_cast<size_t>(t)];
    }
    if (!std::all_of(times.begin(), times.end(), [](int n) { return n == 1; })) region_sets.clear();
  }
  std::vector<int> region(m_.tets.size(), -2);  // -2: no region set holds it
  for (const std::string& name : region_sets) {
    const int index = set_index_.at(name);
    for (const int t : members(name).tets)
      if (region[static_cast<size_t>(t)] == -2) region[static_cast<size_t>(t)] = index;
  }
  for (size_t i = 0; i < m_.tets.size(); ++i)
    if (region[i] != -2) m_.tets[i].region = region[i];
  for (const std::string& name : elset_order_)
    if (detail::id_from_name(name, "REGION") >= 0)
      for (const int t : members(name).tets) m_.tets[static_cast<size_t>(t)].region = set_index_.at(name);
}

// The data lines of keyword `k`, read when it is met and again when its data
// goes on in (or after) an included file: decks often say "*NODE" and then
// "*INCLUDE, INPUT=nodes.inp" holding the lines alone.
void InpReader::keyword_data(const Keyword& k) {
  if (k.name == "NODE") nodes();
  else if (k.name == "ELEMENT") elements(k);
  else if (k.name == "ELSET") elset(k);
  else if (k.name == "SURFACE") surface(k);
  else if (k.name == "INSTANCE") instance();
  else skip_data();
}

// Abaqus/CAE's decks: one *Part and one *Instance of it read as a flat deck
// (the part's numbers are the deck's); more parts, more instances, or an
// instance moved by its data lines are refused: each part numbers its nodes
// from 1 ("node 1 appears twice"), and a translation was dropped without a
// word (exit 0) until 2026-11-30.
void InpReader::instance() {
  while (at_data_line()) {
    for (const std::string_view f : fields(7)) {
      double v;
      if (Cursor::parse_real(f, v) && v != 0)
        fail("an *INSTANCE moved by a translation or rotation: vdmesh reads flat decks (Abaqus/CAE: Model > Edit "
             "Attributes > Do not use parts and assemblies in input files)");
    }
  }
}

// Files are named relative to the including file's folder: decks are run
// from their own folder (CalculiX and Abaqus look in the working folder),
// and `vdmesh convert sub/deck.inp` should find what the deck's run would.
void InpReader::include(const Keyword& k, size_t line) {
  const std::string where = in_->name() + ":" + std::to_string(line) + ": ";
  const auto it = k.options.find("INPUT");
  std::string file = it == k.options.end() ? "" : it->second;
  if (file.size() >= 2 && (file.front() == '"' || file.front() == '\'') && file.back() == file.front())
    file = file.substr(1, file.size() - 2);
  if (file.empty()) throw InputError(where + "*INCLUDE without INPUT=");
  // Deeper than any deck nests its files: a file including itself, or two each other.
  constexpr size_t kDeepest = 32;
  if (sources_.size() > kDeepest)
    throw InputError(where + "*INCLUDE nested more than " + std::to_string(kDeepest) +
                     " files deep (a file that includes itself?)");
  // And no more files in all: two files each including the next twice
  // would be read 2^32 times within that depth.
  constexpr int kMostIncludes = 1000;
  if (++includes_ > kMostIncludes)
    throw InputError(where + "more than " + std::to_string(kMostIncludes) + " *INCLUDEs read (files including each "
                     "other over and over?)");
  std::filesystem::path path(file);
  if (path.is_relative()) path = std::filesystem::path(in_->name()).parent_path() / path;
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) {
    const bool exists = std::filesystem::exists(path, error);
    throw FileError(where + "*INCLUDE, INPUT=" + file + ": " + path.string() +
                        (exists ? " is not a regular file" : " does not exist"),
                    path.string(), exists ? EISDIR : ENOENT);
  }
  auto bytes = std::make_unique<FileBytes>(path.string());
  const FileBytes& view = *bytes;
  total_bytes_ += view.size();
  sources_.push_back(std::make_unique<Source>(std::move(bytes), view, path.string()));
  in_ = &sources_.back()->cursor;
}

Mesh InpReader::read() {
  std::optional<Keyword> open;  // the last keyword met
  bool crossed = false;         // a file began or ended since then
  for (;;) {
    if (in_->at_end()) {
      if (sources_.size() == 1) break;
      sources_.pop_back();
      in_ = &sources_.back()->cursor;
      crossed = true;
      continue;
    }
    if (at_data_line()) {
      if (!crossed || !open)
        throw InputError(in_->name() + ":" + std::to_string(in_->line()) + ": data line outside a keyword");
      crossed = false;
      keyword_data(*open);
      continue;
    }
    if (in_->at_end()) continue;  // the file ended in comments
    const size_t line = in_->line();
    const std::string_view t = trim(in_->rest_of_line());
    const Keyword k = keyword(t);
    if (k.name == "INCLUDE") {
      include(k, line);
      crossed = true;
      continue;
    }
    if ((k.name == "PART" && ++parts_ > 1) || (k.name == "INSTANCE" && ++instances_ > 1))
      throw InputError(in_->name() + ":" + std::to_string(line) + ": a second *" + k.name +
                       ": vdmesh reads flat decks and Abaqus/CAE decks of one part placed once (Abaqus/CAE: Model > "
                       "Edit Attributes > Do not use parts and assemblies in input files)");
    open = k;
    crossed = false;
    keyword_line_ = line;
    if (k.name == "SOLID SECTION" && k.options.count("ELSET")) section_sets_.push_back(detail::to_upper(k.options.at("ELSET")));
    keyword_data(k);
  }
  regions_from_sets();
  const bool mids = !m_.tet_mid.empty();
  detail::sort_tets_by_number(tet_ids_, m_.tets, m_.tet_mid);
  for (size_t i = 0; i < m_.tets.size(); ++i) tet_index_.set(static_cast<int64_t>(tet_ids_[i]), static_cast<int>(i));
  tet_ids_ = {};
  std::vector<int> region_of_set(set_names_.size(), 0);  // 0: not numbered yet
  int next_region = 1;
  std::set<int> claimed;
  // The ids vdmesh's writer gave in comments first: they say what a name
  // cannot (Zeta) or says otherwise (a region 1 named Region2).
  for (size_t k = 0; k < set_names_.size(); ++k) {
    const auto given = region_id_of_name_.find(detail::to_upper(set_names_[k]));
    if (given == region_id_of_name_.end() || !claimed.insert(given->second).second) continue;
    region_of_set[k] = given->second;
    next_region = std::max(next_region, given->second + 1);
    if (detail::id_from_name(set_names_[k], "Region") != given->second) m_.region_names[given->second] = set_names_[k];
  }
  for (size_t k = 0; k < set_names_.size(); ++k) {
    const int r = detail::id_from_name(set_names_[k], "Region");
    if (r >= 0 && region_of_set[k] == 0 && claimed.insert(r).second)
      region_of_set[k] = r, next_region = std::max(next_region, r + 1);
  }
  // Solid<k>, vdmesh's name for CAD solid k, keeps its number and its name
  // (numbered by the lowest element before 2026-11-30: Solid2 came back as
  // region 1), unless a Region<k> set has it.
  for (size_t k = 0; k < set_names_.size(); ++k) {
    const int r = detail::id_from_name(set_names_[k], "Solid");
    if (r < 1 || region_of_set[k] != 0 || !claimed.insert(r).second) continue;
    region_of_set[k] = r;
    next_region = std::max(next_region, r + 1);
    m_.region_names[r] = set_names_[k];
  }
  for (Tetrahedron& t : m_.tets) {
    if (t.region < 0) continue;  // no ELSET: unknown
    const size_t k = static_cast<size_t>(t.region);
    if (region_of_set[k] == 0 && detail::id_from_name(set_names_[k], "Region") < 0) {
      region_of_set[k] = next_region;
      m_.region_names[next_region++] = set_names_[k];
    }
    t.region = set_names_[k] == "RegionUnknown" ? kUnknownRegion : region_of_set[k];
  }
  // Face ids from names "Face<k>", others numbered after them.
  std::map<std::string, int> face_of_name;
  std::set<int> face_ids_taken;
  int next_face = 1;
  auto face_id = [&](const std::string& name) {
    auto it = face_of_name.find(name);
    if (it != face_of_name.end()) return it->second;
    // The writer's comment first (Zeta, or a face 5 named Face7), then the
    // name's own number, then the next free one.
    const auto given = face_id_of_name_.find(detail::to_upper(name));
    int k = given != face_id_of_name_.end() && !face_ids_taken.count(given->second) ? given->second
                                                                                     : detail::id_from_name(name, "Face");
    if (k < 1) k = next_face;
    if (!name.empty() && detail::id_from_name(name, "Face") != k) m_.face_names[k] = name;
    face_ids_taken.insert(k);
    next_face = std::max(next_face, k + 1);
    return face_of_name[name] = k;
  };
  // Names with a comment's id, then names "Face<k>", claim their ids before
  // other names are numbered.
  for (const auto& [name, entries] : surface_sets_)
    if (face_id_of_name_.count(detail::to_upper(name))) face_id(name);
  for (const Shell& s : shells_)
    if (face_id_of_name_.count(detail::to_upper(s.set))) face_id(s.set);
  for (const auto& [name, entries] : surface_sets_)
    if (detail::id_from_name(name, "Face") >= 1) face_id(name);
  for (const Shell& s : shells_)
    if (detail::id_from_name(s.set, "Face") >= 1) face_id(s.set);
  // A triangle in several surfaces is one facet on several faces, whichever
  // tetrahedron each names it by (vdmesh writes an interface of two CAD
  // faces into both; a deck may give each solid's face by its own
  // elements). It was read as a facet per surface, duplicates the mesher
  // refuses.
  std::map<std::array<int, 3>, size_t> facet_of_side;  // sorted corners -> facet
  std::vector<std::vector<int>> facet_faces;           // of facets on several faces: every face, in order
  for (const auto& [name, entries] : surface_sets_) {
    const int face = face_id(name);
    auto add = [&](int64_t eid, int f) {
      const int at = tet_index_.find(eid);
      if (at < 0) return false;
      const int* corners = kFaces[f];
      std::array<int, 3> key{};
      for (int k = 0; k < 3; ++k) key[k] = m_.tets[static_cast<size_t>(at)].v[corners[k]];
      std::sort(key.begin(), key.end());
      const auto [known, added] = facet_of_side.emplace(key, m_.triangles.size());
      if (!added) {
        const size_t i = known->second;
        if (facet_faces.size() <= i) facet_faces.resize(m_.triangles.size());
        std::vector<int>& faces = facet_faces[i];
        if (faces.empty()) faces.push_back(m_.triangles[i].face);
        if (std::find(faces.begin(), faces.end(), face) == faces.end()) faces.push_back(face);
        return true;
      }
      const Tetrahedron& t = m_.tets[static_cast<size_t>(at)];
      const int* c = kFaces[f];
      // Abaqus faces point into a positive tetrahedron: turn them outward.
      const bool positive = detail::tet_det(m_, t.v) >= 0;
      const int a = c[0], b = positive ? c[2] : c[1], d = positive ? c[1] : c[2];
      Triangle tri;
      tri.v = {t.v[a], t.v[b], t.v[d]};
      tri.face = face;
      m_.triangles.push_back(tri);
      if (mids) {
        const TetMidNodes& mid = m_.tet_mid[static_cast<size_t>(at)];
        auto edge = [&](int x, int y) {
          static const int e[4][4] = {{-1, 0, 2, 3}, {0, -1, 1, 4}, {2, 1, -1, 5}, {3, 4, 5, -1}};
          return mid[static_cast<size_t>(e[x][y])];
        };
        m_.triangle_mid.push_back({edge(a, b), edge(b, d), edge(d, a)});
      }
      return true;
    };
    for (const auto& [target, f] : entries) {
      int64_t eid;
      if (Cursor::parse_int(target, eid)) {
        if (!add(eid, f)) throw InputError(in_->name() + ": surface " + name + " names element " + std::to_string(eid) +
                                           ", which is not a tetrahedron");
      } else {
        auto it = elsets_.find(detail::to_upper(target));
        if (it != elsets_.end())
          for (int64_t id : it->second.ids) add(id, f);
      }
    }
  }
  if (!facet_faces.empty()) {
    facet_faces.resize(m_.triangles.size());
    std::vector<int> ids;
    for (const Triangle& t : m_.triangles) ids.push_back(t.face);
    m_.face_groups = number_shared_pieces(ids, facet_faces, next_face - 1);
    for (size_t i = 0; i < ids.size(); ++i) m_.triangles[i].face = ids[i];
  }
  // Shell elements are the boundary of a mesh without tetrahedra, and beside
  // tetrahedra when no *SURFACE gives it (Gmsh writes its physical surfaces
  // as CPS3 blocks; they were dropped until 2026-11-29), of the same order.
  if (m_.tets.empty() || (surface_sets_.empty() && quad_shells_ == mids)) {
    std::stable_sort(shells_.begin(), shells_.end(), [](const Shell& a, const Shell& b) { return a.id < b.id; });
    for (const Shell& s : shells_) {
      Triangle t = s.t;
      t.face = s.set.empty() ? kNoFace : face_id(s.set);
      if (s.set == "FaceNone") t.face = kNoFace;
      m_.triangles.push_back(t);
      if (quad_shells_) m_.triangle_mid.push_back(s.mid);
    }
  }
  detail::require_valid(m_, in_->name());
  detail::sides_from_tets(m_);
  return std::move(m_);
}

Mesh read_abaqus(const std::string& path) {
  const detail::FileBytes data(path);
  return InpReader(data, path).read();
}

}  // namespace

Format make_abaqus_format() { return {"abaqus", {".inp"}, true, read_abaqus, write_abaqus, {}}; }

}  // namespace vd::io
