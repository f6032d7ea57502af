// Reads Gmsh MSH 2.2 and 4.1, ASCII and binary. Keeps triangles (2, 9) and
// tetrahedra (4, 11), skips points and lines, and refuses other surface and
// volume elements (shape_lost); skips other sections.
// Elements come out in the order of their tags, so files written by vdmesh
// (grouped by entity, tagged in the original order) read back in order.
#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <map>
#include <set>
#include <unordered_map>

#include "gmsh.h"
#include "io_util.h"
#include "mesh/disjoint_sets.h"
#include "surface/edge_map.h"
#include "surface/orient_surface.h"

namespace vd::io::detail {

int msh_nodes_per_element(int type) {
  static const int table[] = {-1, 2,  3, 4,  4,  8,  6,  5,  3,  6,  9,  10, 27, 18, 14, 1,
                              8,  20, 15, 13, 9, 10, 12, 15, 15, 21, 4,  5,  6,  20, 35, 56};
  return type >= 1 && type < static_cast<int>(sizeof table / sizeof table[0]) ? table[type] : -1;
}

namespace {

// Shapes vdmesh has no place for: skipped, they were lost without a word
// (tetrahedra and prisms read as the tetrahedra alone, order 3 as no
// element, exit 0, until 2026-11-30). Points and lines are no part of a
// solid's mesh and are skipped.
const char* shape_lost(int type) {
  switch (type) {
    case 3: case 10: case 16: return "quadrangle";
    case 5: case 12: case 17: return "hexahedron";
    case 6: case 13: case 18: return "prism";
    case 7: case 14: case 19: return "pyramid";
    case 20: case 21: case 22: case 23: case 24: case 25: return "triangle of order 3 or more";
    case 29: case 30: case 31: return "tetrahedron of order 3 or more";
    default: return nullptr;
  }
}

struct Entity {
  std::vector<int> physicals;
  std::vector<int> bounding;  // signed surface tags of a volume
};

// A 2.2 tetrahedron's region field, until finish(), when it has no
// physical group: kEntityCode - its entity.
constexpr int kEntityCode = -2;

// The number of an element in a physical group, or in an entity only. Where
// some elements of a kind have physical groups, those without are numbered
// after the largest group: a box shell (entity 3) around a sphere in
// physical group 3 became one region with it. Tag 0 (meshio writes no
// other without cell data) is no tag: region 0 is the exterior.
long long group_number(int physical, int entity, int largest_physical) {
  if (physical > 0) return physical;
  if (entity <= 0) return -1;  // kUnknownRegion, kNoFace
  return static_cast<long long>(largest_physical) + entity;
}

// Of the physical groups a tetrahedron is in, the one that holds the fewest
// tetrahedra (`size`), the lowest numbered of those: a volume in "all" and
// in "left" is in the region "left", in MSH 4.1 and 2.2 alike. Gmsh lists
// an entity's groups in its own order (the left box "11 100", the right
// one "100 22"), and the first listed was taken until 2026-11-30: "right"
// vanished and "all" held the right box alone, exit 0.
template <typename Size>
int most_specific_group(const std::vector<int>& groups, Size size) {
  int best = 0;
  for (const int g : groups)
    if (best == 0 || size(g) < size(best) || (size(g) == size(best) && g < best)) best = g;
  return best;
}

int parent_or_self(const std::map<int, int>& parent, int entity) {
  const auto it = parent.find(entity);
  return it == parent.end() ? entity : it->second;
}

// For the triangles `own` of m that bound one volume: whether each one's
// normal points out of it. They are turned to agree across their edges and
// each connected piece to enclose a positive volume (orient_consistently);
// a volume is one solid, so the piece enclosing the most is its outer
// boundary and the others are its cavities, whose normals point into them.
std::vector<char> turned_out_of_the_volume(const Mesh& m, const std::vector<size_t>& own) {
  Mesh piece;
  std::unordered_map<int, int> local;
  for (size_t i : own) {
    Triangle t = m.triangles[i];
    for (int& v : t.v) {
      const auto [it, added] = local.emplace(v, static_cast<int>(piece.points.size()));
      if (added) piece.points.push_back(m.points[static_cast<size_t>(v)]);
      v = it->second;
    }
    t.front = t.back = kUnknownRegion;
    piece.triangles.push_back(t);
  }
  const std::vector<Triangle> before = piece.triangles;
  orient_consistently(piece);
  // The connected pieces (across edges of two triangles, as
  // orient_consistently joins them) and the volume each encloses, taken
  // about a vertex of its own (far from the origin, a sum about the origin
  // cancels badly).
  DisjointSets sets(piece.triangles.size());
  std::unordered_map<std::uint64_t, std::vector<int>> on_edge;
  for (size_t k = 0; k < piece.triangles.size(); ++k)
    for (int e = 0; e < 3; ++e)
      on_edge[edge_key(piece.triangles[k].v[e], piece.triangles[k].v[(e + 1) % 3])].push_back(static_cast<int>(k));
  for (const auto& [key, list] : on_edge)
    if (list.size() == 2) sets.join(list[0], list[1]);
  std::map<int, double> enclosed;
  std::map<int, std::array<Vec3, 2>> box;  // lowest and highest corner
  for (size_t k = 0; k < piece.triangles.size(); ++k) {
    const int root = sets.find(static_cast<int>(k));
    const Vec3& o = piece.points[static_cast<size_t>(piece.triangles[static_cast<size_t>(root)].v[0])];
    const auto& v = piece.triangles[k].v;
    const Vec3 &a = piece.points[static_cast<size_t>(v[0])], &b = piece.points[static_cast<size_t>(v[1])],
               &c = piece.points[static_cast<size_t>(v[2])];
    enclosed[root] += dot(a - o, cross(b - o, c - o)) / 6.0;
    auto [it, added] = box.try_emplace(root, std::array<Vec3, 2>{a, a});
    for (const Vec3& p : {a, b, c})
      for (int d = 0; d < 3; ++d) {
        it->second[0][d] = std::min(it->second[0][d], p[d]);
        it->second[1][d] = std::max(it->second[1][d], p[d]);
      }
  }
  int outer = -1;
  for (const auto& [root, volume] : enclosed)
    if (outer < 0 || volume > enclosed[outer]) outer = root;
  // The others are cavities only inside it: a volume of two lumps, or an
  // island in a cavity, is not one solid's boundary, and its sides are left
  // to the surface (empty: unknown).
  for (const auto& [root, corners] : box) {
    if (root == outer) continue;
    for (int d = 0; d < 3; ++d)
      if (!(corners[0][d] > box[outer][0][d] && corners[1][d] < box[outer][1][d])) return {};
  }
  std::vector<char> out(own.size());
  for (size_t k = 0; k < own.size(); ++k) {
    const bool kept = has_directed_edge(before[k], piece.triangles[k].v[0], piece.triangles[k].v[1]);
    out[k] = kept == (sets.find(static_cast<int>(k)) == outer);
  }
  return out;
}

struct Element {
  uint64_t tag;
  int entity;
  int physical;   // 2.2 only; 0 when none
  int more = -1;  // 2.2: its further physical groups, an index into more_physicals_
};

class MshReader {
 public:
  MshReader(const FileBytes& data, const std::string& path) : in_(data, path) {}
  Mesh read();

 private:
  void read_format();
  void read_physical_names();
  struct EntityRecord {
    int tag = 0, parent_dim = -1, parent = 0;
    Entity entity;
  };
  EntityRecord read_entity(int dim, bool partitioned);
  void read_entities();
  void read_partitioned_entities();
  void read_nodes22(bool parametric);
  void read_nodes41();
  void read_elements22();
  void read_elements10();
  void read_elements41();
  void read_block41_binary(int type, int entity, uint64_t count, int k);
  bool plan_tet_places41(uint64_t blocks, uint64_t min_tag, uint64_t max_tag);
  void skip_section(std::string_view name);
  void expect_end(std::string_view name);
  void expect_token(std::string_view end);
  void add_node(uint64_t tag, Vec3 p);
  void add_element(int type, uint64_t tag, const uint64_t* nodes, int entity, int physical);
  void refuse_lost(int type, uint64_t tag);
  uint64_t size_value(const char* what);  // size_t in binary 4.1
  int int_value(const char* what);        // int in binary
  double real_value(const char* what);
  void finish();
  void choose_tet_groups22();
  int volume_group(const Entity& volume) const;

  Cursor in_;
  Mesh m_;
  double version_ = 0;
  bool binary_ = false;
  IdIndex nodes_;
  std::map<int, Entity> surfaces_, volumes_;
  bool have_entities_ = false;
  // A partitioned file's elements lie in partitioned entities: each stands
  // for its parent entity (with its physical groups), and a surface whose
  // parent is a volume is a cut between two partitions, no boundary.
  std::map<int, int> surface_parent_, volume_parent_;
  std::set<int> partition_cuts_;
  std::vector<Element> tri_info_;
  std::vector<std::vector<int>> more_physicals_;
  // 2.2: each tetrahedron's further physical groups (index into m_.tets,
  // group). Every group's count of tetrahedra, to choose among them
  // (most_specific_group): counted while reading in 2.2, from the
  // entities' in finish() in 4.1.
  std::vector<std::pair<size_t, int>> tet_more_physicals_;
  std::map<int, uint64_t> tets_in_group_;
  uint64_t tets_in(int group) const {
    const auto it = tets_in_group_.find(group);
    return it == tets_in_group_.end() ? 0 : it->second;
  }
  TagList tet_tags_;  // the tetrahedra's entities wait in their region field
  // Binary 4.1 whose tetrahedron tags are lo..lo+n-1, each once (what vdmesh
  // and Gmsh write): each tetrahedron goes straight to index tag - lo, so
  // nothing is sorted afterwards (the in-place sort was 37% of the read).
  bool place_by_tag_ = false;
  uint64_t place_lo_ = 0;
  struct {
    int type = 0, entity = 0, physical = 0;
    uint64_t nodes[10] = {};
  } last_;  // the element before, in a 2.2 file
};

uint64_t MshReader::size_value(const char* what) {
  if (!binary_) return in_.count(what);
  return in_.get<uint64_t>(what);
}

int MshReader::int_value(const char* what) {
  if (!binary_) return in_.int32(what);
  return in_.get<int32_t>(what);
}

double MshReader::real_value(const char* what) {
  if (!binary_) return in_.real(what);
  const double v = in_.get<double>(what);
  if (!std::isfinite(v)) in_.fail(std::string(what) + " is not a finite number");
  return v;
}

void MshReader::expect_end(std::string_view name) { expect_token("$End" + std::string(name.substr(1))); }

void MshReader::expect_token(std::string_view end) {
  const std::string want(end);
  const std::string_view t = in_.token(want.c_str());
  if (t != end) in_.fail("expected " + want + ", found '" + std::string(t.substr(0, 40)) + "'");
}

void MshReader::skip_section(std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  const size_t at = in_.data().find(end, in_.pos());
  if (at == std::string_view::npos) in_.fail("section " + std::string(name) + " has no " + end);
  // Walk to it line by line so errors after it still name the right line.
  while (in_.pos() < at && !in_.at_end()) in_.skip_line();
  in_.seek(at + end.size());
}

void MshReader::read_format() {
  const std::string_view v = in_.token("the MSH version");
  if (!Cursor::parse_real(v, version_)) in_.fail("bad MSH version '" + std::string(v.substr(0, 20)) + "'");
  const int file_type = in_.int32("the file type");
  const int data_size = in_.int32("the data size");
  if (!(version_ >= 2 && version_ < 3) && version_ != 4.1)
    in_.fail("MSH version " + std::string(v) + " is not supported (2.2 and 4.1 are)");
  if (file_type != 0 && file_type != 1) in_.fail("file type must be 0 (ASCII) or 1 (binary)");
  binary_ = file_type == 1;
  if (binary_) {
    if (data_size != 8) in_.fail("binary data size must be 8, not " + std::to_string(data_size));
    in_.skip_line();
    if (in_.get<int32_t>("the endianness check") != 1) in_.fail("big-endian binary MSH is not supported");
  }
  expect_end("$MeshFormat");
}

void MshReader::read_physical_names() {
  const uint64_t n = in_.count("the number of physical names", in_.remaining());
  for (uint64_t i = 0; i < n; ++i) {
    const int dim = in_.int32("a physical dimension");
    const int tag = in_.int32("a physical tag");
    std::string_view name = in_.rest_of_line();
    while (!name.empty() && (name.front() == ' ' || name.front() == '\t')) name.remove_prefix(1);
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
    if (dim == 3) m_.region_names[tag] = std::string(name);
    if (dim == 2) m_.face_names[tag] = std::string(name);
  }
  expect_end("$PhysicalNames");
}

// One entity of $Entities, or of $PartitionedEntities (`partitioned`): its
// tag, then there its parent's dimension and tag and its partitions, then
// its box, physical groups and bounding entities (kept for volumes).
MshReader::EntityRecord MshReader::read_entity(int dim, bool partitioned) {
  EntityRecord r;
  r.tag = int_value("an entity tag");
  if (partitioned) {
    r.parent_dim = int_value("a parent dimension");
    r.parent = int_value("a parent tag");
    const uint64_t partitions = size_value("a partition count");
    if (partitions > in_.remaining()) in_.fail("too many partitions");
    for (uint64_t k = 0; k < partitions; ++k) int_value("a partition tag");
  }
  for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) real_value("an entity bounding box");
  const uint64_t nphys = size_value("a physical tag count");
  if (nphys > in_.remaining()) in_.fail("too many physical tags");
  for (uint64_t k = 0; k < nphys; ++k) r.entity.physicals.push_back(int_value("a physical tag"));
  if (dim > 0) {
    const uint64_t nb = size_value("a bounding entity count");
    if (nb > in_.remaining()) in_.fail("too many bounding entities");
    for (uint64_t k = 0; k < nb; ++k) {
      const int b = int_value("a bounding entity tag");
      if (dim == 3) r.entity.bounding.push_back(b);
    }
  }
  return r;
}

void MshReader::read_entities() {
  if (version_ < 4) in_.fail("$Entities in a version 2 file");
  have_entities_ = true;
  uint64_t count[4];
  for (uint64_t& c : count) c = size_value("an entity count");
  for (int dim = 0; dim < 4; ++dim)
    for (uint64_t i = 0; i < count[dim]; ++i) {
      EntityRecord r = read_entity(dim, false);
      if (dim == 2) surfaces_[r.tag] = std::move(r.entity);
      if (dim == 3) volumes_[r.tag] = std::move(r.entity);
    }
  expect_end("$Entities");
}

// $PartitionedEntities (Gmsh -part N): read past until 2026-11-30, which
// made each partition's piece of a volume a region of its own and the cuts
// between partitions faces (two volumes read as 4 regions, 20 faces and 33
// triangles too many).
void MshReader::read_partitioned_entities() {
  if (version_ < 4) in_.fail("$PartitionedEntities in a version 2 file");
  size_value("the number of partitions");
  const uint64_t ghosts = size_value("the number of ghost entities");
  if (ghosts > in_.remaining()) in_.fail("too many ghost entities");
  for (uint64_t i = 0; i < ghosts; ++i) {
    int_value("a ghost entity tag");
    int_value("a ghost entity partition");
  }
  uint64_t count[4];
  for (uint64_t& c : count) c = size_value("an entity count");
  for (int dim = 0; dim < 4; ++dim)
    for (uint64_t i = 0; i < count[dim]; ++i) {
      EntityRecord r = read_entity(dim, true);
      if (dim == 2 && r.parent_dim == 3) partition_cuts_.insert(r.tag);
      if (dim == 2 && r.parent_dim == 2) surface_parent_[r.tag] = r.parent;
      if (dim == 3) volume_parent_[r.tag] = r.parent;
      if (dim == 2) surfaces_[r.tag] = std::move(r.entity);
      if (dim == 3) volumes_[r.tag] = std::move(r.entity);
    }
  expect_end("$PartitionedEntities");
}

void MshReader::add_node(uint64_t tag, Vec3 p) {
  if (tag > uint64_t{INT64_MAX}) in_.fail("node tag " + std::to_string(tag) + " is too large");
  if (!nodes_.add(static_cast<int64_t>(tag), static_cast<int>(m_.points.size())))
    in_.fail("node " + std::to_string(tag) + " appears twice");
  m_.points.push_back(p);
}

// $Nodes, or `parametric`: $ParametricNodes (Mesh.SaveParametric), each node
// then with its entity's dimension and tag, and one parameter per dimension
// on curves and surfaces (skipped until 2026-11-30, and every element then
// "refers to node 15, which does not exist").
void MshReader::read_nodes22(bool parametric) {
  const uint64_t n = in_.count("the number of nodes");
  nodes_.expect(n, in_.remaining());
  m_.points.reserve(capped(n, in_.remaining(), binary_ ? 28 : 8));
  if (binary_) in_.skip_line();
  for (uint64_t i = 0; i < n; ++i) {
    const uint64_t tag = binary_ ? static_cast<uint64_t>(static_cast<uint32_t>(in_.get<int32_t>("a node tag")))
                                 : in_.count("a node tag");
    Vec3 p;
    p.x = real_value("a node x");
    p.y = real_value("a node y");
    p.z = real_value("a node z");
    if (parametric) {
      const int dim = int_value("an entity dimension");
      int_value("an entity tag");
      if (dim < 0 || dim > 3) in_.fail("entity dimension " + std::to_string(dim));
      for (int k = 0; k < (dim == 1 || dim == 2 ? dim : 0); ++k) real_value("a parametric coordinate");
    }
    add_node(tag, p);
  }
  if (version_ < 2)
    expect_token("$ENDNOD");
  else
    expect_end(parametric ? "$ParametricNodes" : "$Nodes");
}

void MshReader::read_nodes41() {
  const uint64_t blocks = size_value("the number of node blocks");
  const uint64_t n = size_value("the number of nodes");
  size_value("the smallest node tag");
  size_value("the largest node tag");
  nodes_.expect(n, in_.remaining());
  m_.points.reserve(capped(n, in_.remaining(), binary_ ? 32 : 8));
  std::vector<uint64_t> tags;
  for (uint64_t b = 0; b < blocks; ++b) {
    const int dim = int_value("an entity dimension");
    int_value("an entity tag");
    const int parametric = int_value("the parametric flag");
    const uint64_t count = size_value("the number of nodes in a block");
    if (count > in_.remaining()) in_.fail("node block larger than the file");
    if (dim < 0 || dim > 3) in_.fail("entity dimension " + std::to_string(dim));
    const int extra = parametric ? dim : 0;
    tags.resize(count);
    for (uint64_t& t : tags) t = size_value("a node tag");
    for (uint64_t t : tags) {
      Vec3 p;
      p.x = real_value("a node x");
      p.y = real_value("a node y");
      p.z = real_value("a node z");
      for (int k = 0; k < extra; ++k) real_value("a parametric coordinate");
      add_node(t, p);
    }
  }
  if (m_.points.size() != n) in_.fail("the node blocks hold " + std::to_string(m_.points.size()) +
                                      " nodes, the header says " + std::to_string(n));
  expect_end("$Nodes");
}

void MshReader::refuse_lost(int type, uint64_t tag) {
  if (const char* shape = shape_lost(type))
    in_.fail("element " + std::to_string(tag) + " is a " + shape + " (type " + std::to_string(type) +
             "): vdmesh reads triangles and tetrahedra of order 1 or 2 only, and would lose it");
}

void MshReader::add_element(int type, uint64_t tag, const uint64_t* nodes, int entity, int physical) {
  const bool tri = type == kMshTriangle || type == kMshTriangle6;
  const bool tet = type == kMshTet || type == kMshTet10;
  if (!tri && !tet) return refuse_lost(type, tag);
  const int k = msh_nodes_per_element(type);
  // Gmsh's 2.2 writer repeats an element right after itself, under the next
  // number, for each further physical group of its entity: one element is
  // kept, in the group most_specific_group chooses (a tetrahedron in two
  // groups was two, a third region doubling the volume, until 2026-11-30).
  if (version_ < 4) {
    const bool repeat = type == last_.type && entity == last_.entity && physical != last_.physical &&
                        std::equal(nodes, nodes + k, last_.nodes);
    last_.type = type;
    last_.entity = entity;
    last_.physical = physical;
    std::copy(nodes, nodes + k, last_.nodes);
    if (tet && physical > 0) ++tets_in_group_[physical];
    if (repeat) {
      // A triangle in two physical surfaces lies on both faces
      // (Mesh::face_groups; vdmesh writes a CAD interface so).
      if (tri && !tri_info_.empty()) {
        Element& e = tri_info_.back();
        if (e.more < 0) e.more = static_cast<int>(more_physicals_.size()), more_physicals_.emplace_back();
        more_physicals_[static_cast<size_t>(e.more)].push_back(physical);
      }
      // A tetrahedron has one region: chosen among its groups in finish().
      if (tet && !m_.tets.empty()) tet_more_physicals_.push_back({m_.tets.size() - 1, physical});
      return;
    }
  }
  int idx[10];
  for (int j = 0; j < k; ++j) {
    idx[j] = nodes[j] > uint64_t{INT64_MAX} ? -1 : nodes_.find(static_cast<int64_t>(nodes[j]));
    if (idx[j] < 0) in_.fail("element " + std::to_string(tag) + " refers to node " + std::to_string(nodes[j]) +
                             ", which does not exist");
  }
  if (tri) {
    Triangle t;
    t.v = {idx[0], idx[1], idx[2]};
    m_.triangles.push_back(t);
    if (type == kMshTriangle6) m_.triangle_mid.push_back({idx[3], idx[4], idx[5]});
    tri_info_.push_back({tag, entity, physical});
  } else {
    Tetrahedron t;
    t.v = {idx[0], idx[1], idx[2], idx[3]};
    // 2.2 knows the tag now, a physical group as it is and an entity as
    // kEntityCode - entity (numbered in finish()); 4.1's physical group
    // comes from the entity.
    if (version_ < 4 && physical <= 0 && entity > INT_MAX + kEntityCode)
      in_.fail("element " + std::to_string(tag) + " has entity tag " + std::to_string(entity) + ", too large");
    t.region = version_ >= 4 ? entity : physical > 0 ? physical : kEntityCode - std::max(entity, 0);
    TetMidNodes mid{};
    if (type == kMshTet10) {
      mid = {idx[4], idx[5], idx[6], idx[7], idx[8], idx[9]};
      swap_tet10_gmsh(mid);
    }
    if (place_by_tag_) {
      const size_t at = static_cast<size_t>(tag - place_lo_);
      m_.tets[at] = t;
      if (type == kMshTet10) m_.tet_mid[at] = mid;
      return;
    }
    m_.tets.push_back(t);
    if (type == kMshTet10) m_.tet_mid.push_back(mid);
    tet_tags_.push_back(tag);
  }
}

void MshReader::read_elements22() {
  const uint64_t n = in_.count("the number of elements");
  uint64_t nodes[64];
  if (!binary_) {
    for (uint64_t i = 0; i < n; ++i) {
      const uint64_t tag = in_.count("an element tag");
      const int type = in_.int32("an element type");
      const int k = msh_nodes_per_element(type);
      if (k < 0) in_.fail("unknown element type " + std::to_string(type));
      const uint64_t ntags = in_.count("the number of element tags", 64);
      int tags[2] = {0, 0};
      for (uint64_t j = 0; j < ntags; ++j) {
        const int t = in_.int32("an element tag");
        if (j < 2) tags[j] = t;
      }
      for (int j = 0; j < k; ++j) nodes[j] = in_.count("an element node");
      add_element(type, tag, nodes, tags[1], tags[0]);
    }
  } else {
    in_.skip_line();
    uint64_t done = 0;
    while (done < n) {
      const int type = in_.get<int32_t>("an element type");
      const int32_t count = in_.get<int32_t>("an element count");
      const int32_t ntags = in_.get<int32_t>("a tag count");
      const int k = msh_nodes_per_element(type);
      if (k < 0) in_.fail("unknown element type " + std::to_string(type));
      if (count <= 0 || static_cast<uint64_t>(count) > n - done) in_.fail("bad element block size");
      if (ntags < 0 || ntags > 64) in_.fail("bad element tag count");
      for (int32_t e = 0; e < count; ++e) {
        const uint32_t tag = static_cast<uint32_t>(in_.get<int32_t>("an element tag"));
        int tags[2] = {0, 0};
        for (int j = 0; j < ntags; ++j) {
          const int t = in_.get<int32_t>("an element tag");
          if (j < 2) tags[j] = t;
        }
        for (int j = 0; j < k; ++j) nodes[j] = static_cast<uint32_t>(in_.get<int32_t>("an element node"));
        add_element(type, tag, nodes, tags[1], tags[0]);
      }
      done += static_cast<uint64_t>(count);
    }
  }
  expect_end("$Elements");
}

// MSH 1.0 (Gmsh before 2.0, 2006): each element as `tag type physical
// elementary node-count nodes...`, ASCII only.
void MshReader::read_elements10() {
  const uint64_t n = in_.count("the number of elements");
  uint64_t nodes[64];
  for (uint64_t i = 0; i < n; ++i) {
    const uint64_t tag = in_.count("an element tag");
    const int type = in_.int32("an element type");
    const int physical = in_.int32("a physical region");
    const int elementary = in_.int32("an elementary region");
    const uint64_t count = in_.count("the number of nodes", 64);
    const int k = msh_nodes_per_element(type);
    if (k < 0) in_.fail("unknown element type " + std::to_string(type));
    if (count != static_cast<uint64_t>(k))
      in_.fail("element " + std::to_string(tag) + " of type " + std::to_string(type) + " has " + std::to_string(k) +
               " nodes, not " + std::to_string(count));
    for (int j = 0; j < k; ++j) nodes[j] = in_.count("an element node");
    add_element(type, tag, nodes, elementary, physical);
  }
  expect_token("$ENDELM");
}

// Looks ahead through the binary element blocks (headers and tag columns
// only) for tetrahedron tags that form one range with each tag once, and
// sizes the tetrahedra to be placed by tag. Anything else (a short file,
// first- and second-order tetrahedra mixed, gaps, repeats) leaves the plan
// off, and the ordinary read reports or sorts it.
bool MshReader::plan_tet_places41(uint64_t blocks, uint64_t min_tag, uint64_t max_tag) {
  // Each element takes at least 16 bytes: the header's tag range cannot ask
  // for a larger table than the file could fill.
  if (max_tag < min_tag || max_tag - min_tag >= in_.remaining() / 16) return false;
  const std::string_view d = in_.data();
  const size_t start = in_.pos();
  size_t p = start;
  auto u64_at = [&](size_t at) {
    uint64_t v;
    std::memcpy(&v, d.data() + at, sizeof v);
    return v;
  };
  std::vector<bool> seen(static_cast<size_t>(max_tag - min_tag + 1), false);
  uint64_t n_tets = 0, lo = UINT64_MAX, hi = 0;
  bool first_order = false, second_order = false, once = true;
  // The look-ahead maps the pages it reads: it lets them go every 1 MiB, as
  // the cursor does, so the peak does not hold the element section twice.
  size_t dropped = start;
  auto let_go = [&](size_t upto) {
    if (upto >= dropped + (size_t{1} << 20)) {
      in_.drop(dropped, upto);
      dropped = upto;
    }
  };
  for (uint64_t b = 0; b < blocks && once; ++b) {
    int32_t head[3];
    if (d.size() - p < sizeof head + 8) return false;
    std::memcpy(head, d.data() + p, sizeof head);
    const uint64_t count = u64_at(p + sizeof head);
    p += sizeof head + 8;
    const int k = msh_nodes_per_element(head[2]);
    if (k < 0) return false;
    const size_t stride = 8 * static_cast<size_t>(1 + k);
    if (count > (d.size() - p) / stride) return false;
    if (head[2] == kMshTet || head[2] == kMshTet10) {
      (head[2] == kMshTet ? first_order : second_order) = true;
      for (uint64_t e = 0; e < count && once; ++e) {
        const uint64_t t = u64_at(p + e * stride);
        if (t < min_tag || t > max_tag) return false;
        once = !seen[static_cast<size_t>(t - min_tag)];
        seen[static_cast<size_t>(t - min_tag)] = true;
        lo = std::min(lo, t);
        hi = std::max(hi, t);
        if ((e & 0x3fff) == 0) let_go(p + e * stride);
      }
      n_tets += count;
    }
    p += count * stride;
  }
  in_.drop(start, p);
  if (!once || n_tets == 0 || n_tets > static_cast<uint64_t>(INT32_MAX) || (first_order && second_order) ||
      hi - lo + 1 != n_tets)
    return false;
  m_.tets.assign(n_tets, Tetrahedron{});
  if (second_order) m_.tet_mid.assign(n_tets, TetMidNodes{});
  place_by_tag_ = true;
  place_lo_ = lo;
  return true;
}

// A binary 4.1 block straight from the file: one bounds check per block, and
// the cursor moves every chunk so the pages behind it are let go.
void MshReader::read_block41_binary(int type, int entity, uint64_t count, int k) {
  const size_t stride = 8 * static_cast<size_t>(1 + k);
  if (count > in_.remaining() / stride) in_.fail("element block larger than the file");
  const bool kept = type == kMshTriangle || type == kMshTriangle6 || type == kMshTet || type == kMshTet10;
  if (count > 0) refuse_lost(type, [&] {
    uint64_t tag;
    std::memcpy(&tag, in_.data().data() + in_.pos(), sizeof tag);
    return tag;
  }());
  if (!kept) return in_.skip_bytes(count * stride, "an element block");
  constexpr uint64_t kChunk = 8192;
  uint64_t rec[11];
  for (uint64_t done = 0; done < count;) {
    const uint64_t n = std::min(kChunk, count - done);
    const char* p = in_.data().data() + in_.pos();
    for (uint64_t e = 0; e < n; ++e) {
      std::memcpy(rec, p + e * stride, stride);
      add_element(type, rec[0], rec + 1, entity, 0);
    }
    in_.skip_bytes(n * stride, "an element block");
    done += n;
  }
}

void MshReader::read_elements41() {
  const uint64_t blocks = size_value("the number of element blocks");
  const uint64_t n = size_value("the number of elements");
  const uint64_t min_tag = size_value("the smallest element tag");
  const uint64_t max_tag = size_value("the largest element tag");
  if (!binary_ || !plan_tet_places41(blocks, min_tag, max_tag)) {
    m_.tets.reserve(capped(n, in_.remaining(), binary_ ? 40 : 10));
    tet_tags_.reserve(m_.tets.capacity());
  }
  uint64_t nodes[64];
  uint64_t total = 0;
  for (uint64_t b = 0; b < blocks; ++b) {
    const int dim = int_value("an entity dimension");
    const int entity = int_value("an entity tag");
    const int type = int_value("an element type");
    const uint64_t count = size_value("the number of elements in a block");
    const int k = msh_nodes_per_element(type);
    if (k < 0) in_.fail("unknown element type " + std::to_string(type));
    if (dim < 0 || dim > 3) in_.fail("entity dimension " + std::to_string(dim));
    if (count > in_.remaining()) in_.fail("element block larger than the file");
    if (binary_) {
      read_block41_binary(type, entity, count, k);
    } else {
      for (uint64_t e = 0; e < count; ++e) {
        const uint64_t tag = size_value("an element tag");
        for (int j = 0; j < k; ++j) nodes[j] = size_value("an element node");
        add_element(type, tag, nodes, entity, 0);
      }
    }
    total += count;
  }
  if (total != n) in_.fail("the element blocks hold " + std::to_string(total) + " elements, the header says " +
                           std::to_string(n));
  expect_end("$Elements");
}

// 2.2: a tetrahedron in several physical groups takes the one of fewest
// tetrahedra (most_specific_group); its region field holds its first group
// until here.
void MshReader::choose_tet_groups22() {
  auto size = [this](int g) { return tets_in(g); };
  for (size_t k = 0; k < tet_more_physicals_.size();) {
    const size_t tet = tet_more_physicals_[k].first;
    std::vector<int> groups{m_.tets[tet].region};
    for (; k < tet_more_physicals_.size() && tet_more_physicals_[k].first == tet; ++k)
      groups.push_back(tet_more_physicals_[k].second);
    m_.tets[tet].region = most_specific_group(groups, size);
  }
  tet_more_physicals_ = {};
}

// 4.1: a volume's region among its physical groups (most_specific_group);
// 0 for none.
int MshReader::volume_group(const Entity& volume) const {
  if (volume.physicals.size() < 2) return volume.physicals.empty() ? 0 : volume.physicals.front();
  return most_specific_group(volume.physicals, [this](int g) { return tets_in(g); });
}

void MshReader::finish() {
  choose_tet_groups22();
  if (version_ >= 4) {
    // Tetrahedra hold their entity until numbered below.
    std::map<int, uint64_t> tets_in_entity;
    for (const Tetrahedron& t : m_.tets) ++tets_in_entity[t.region];
    for (const auto& [tag, v] : volumes_)
      for (const int g : v.physicals) tets_in_group_[g] += tets_in_entity[tag];
  }
  // Elements in tag order (stable, so untagged duplicates keep file order).
  const bool tri_mids = m_.triangle_mid.size() == m_.triangles.size();
  sort_in_place(
      tri_info_.size(), [&](size_t i) { return tri_info_[i].tag; },
      [&](size_t i, size_t j) {
        std::swap(tri_info_[i], tri_info_[j]);
        std::swap(m_.triangles[i], m_.triangles[j]);
        if (tri_mids) std::swap(m_.triangle_mid[i], m_.triangle_mid[j]);
      });
  if (!place_by_tag_) sort_tets_by_number(tet_tags_, m_.tets, m_.tet_mid);
  tet_tags_ = {};
  // An element's number: its physical group, else its geometrical entity
  // (group_number), which must fit an int.
  const auto numbered = [&](long long n) {
    if (n > INT_MAX) in_.fail("an entity numbered after physical group tags gets " + std::to_string(n) + ", too large");
    return static_cast<int>(n);
  };
  auto physical_of = [&](int entity, const std::map<int, Entity>& entities) {
    auto it = entities.find(entity);
    return it != entities.end() && !it->second.physicals.empty() ? it->second.physicals.front() : 0;
  };
  {
    // Blocks share entities: look each one up once per run.
    auto physical_and_entity = [&](const Tetrahedron& t) {
      if (version_ < 4) return t.region > 0 ? std::pair{t.region, 0} : std::pair{0, kEntityCode - t.region};
      const auto it = volumes_.find(t.region);
      return std::pair{it == volumes_.end() ? 0 : volume_group(it->second), parent_or_self(volume_parent_, t.region)};
    };
    int largest = 0;
    int last_region = 0, last_number = 0;
    bool have_last = false;
    for (const Tetrahedron& t : m_.tets) {
      if (have_last && t.region == last_region) continue;
      largest = std::max(largest, physical_and_entity(t).first);
      last_region = t.region;
      have_last = true;
    }
    have_last = false;
    for (Tetrahedron& t : m_.tets) {
      if (!have_last || t.region != last_region) {
        last_region = t.region;
        const auto [physical, entity] = physical_and_entity(t);
        last_number = numbered(group_number(physical, entity, largest));
        have_last = true;
      }
      t.region = last_number;
    }
  }
  {
    if (!partition_cuts_.empty()) {
      size_t kept = 0;
      for (size_t i = 0; i < m_.triangles.size(); ++i) {
        if (partition_cuts_.count(tri_info_[i].entity)) continue;
        m_.triangles[kept] = m_.triangles[i];
        if (tri_mids) m_.triangle_mid[kept] = m_.triangle_mid[i];
        tri_info_[kept++] = tri_info_[i];
      }
      m_.triangles.resize(kept);
      if (tri_mids) m_.triangle_mid.resize(kept);
      tri_info_.resize(kept);
    }
    auto physical = [&](const Element& e) { return version_ < 4 ? e.physical : physical_of(e.entity, surfaces_); };
    // Every physical surface of a triangle: 2.2's repeats, 4.1's entity's list.
    const std::vector<int> none;
    auto all_physicals = [&](const Element& e) -> const std::vector<int>& {
      if (version_ < 4) return e.more >= 0 ? more_physicals_[static_cast<size_t>(e.more)] : none;
      const auto it = surfaces_.find(e.entity);
      return it != surfaces_.end() && it->second.physicals.size() > 1 ? it->second.physicals : none;
    };
    int largest = 0;
    for (const Element& e : tri_info_) {
      largest = std::max(largest, physical(e));
      for (const int p : all_physicals(e)) largest = std::max(largest, p);
    }
    std::vector<int> ids(m_.triangles.size());
    std::vector<std::vector<int>> groups(m_.triangles.size());
    int last_id = 0;
    for (size_t i = 0; i < m_.triangles.size(); ++i) {
      const Element& e = tri_info_[i];
      const int entity = parent_or_self(surface_parent_, e.entity);
      ids[i] = numbered(group_number(physical(e), entity, largest));
      last_id = std::max(last_id, ids[i]);
      for (const int p : all_physicals(e)) {
        if (groups[i].empty()) groups[i].push_back(ids[i]);
        const int g = numbered(group_number(p, entity, largest));
        if (std::find(groups[i].begin(), groups[i].end(), g) == groups[i].end()) groups[i].push_back(g);
        last_id = std::max(last_id, g);
      }
    }
    // Past every named group too, those without elements among them (an
    // empty "Outlet" group's tag was given to a shared piece).
    for (const auto& [id, name] : m_.face_names) last_id = std::max(last_id, id);
    if (!more_physicals_.empty() || version_ >= 4) m_.face_groups = number_shared_pieces(ids, groups, last_id);
    for (size_t i = 0; i < m_.triangles.size(); ++i) m_.triangles[i].face = ids[i];
  }
  if (!m_.tets.empty()) {
    require_valid(m_, in_.name());
    sides_from_tets(m_);
    return;
  }
  // A surface mesh. Gmsh turns each surface's triangles like the surface's
  // own parametrization, not out of a solid: where the sides are not
  // known, the facets are turned to agree with their neighbours and to
  // enclose positive volumes (orient_surface.h), as for TetGen's PLCs (a box
  // of Gmsh's built-in kernel was refused: "inconsistent orientation").
  if (!have_entities_) {
    orient_consistently(m_);
    return;
  }
  // The volumes that list a surface as their boundary give its sides. Not
  // by the list's signs (+s: the surface's normal points out of the volume),
  // which are not to be trusted: Gmsh's OpenCASCADE kernel writes every one
  // as +, a wall between two boxes or a sphere in a box in both, and its own
  // kernel's disagree with the triangles' turn on some surfaces. By the
  // triangles themselves: each volume's are turned to point out of it
  // (turned_out_of_the_volume). Until 2026-11-30 the signs were read, their sides did
  // not close, and the regions were found from the surface: physical
  // volumes 11 "Left" and 22 "Right" came out as regions 1 and 2, beside
  // names for 11 and 22 (a surface tester's two boxes).
  int largest = 0;
  for (const auto& [vtag, v] : volumes_)
    largest = std::max(largest, volume_group(v));
  bool contradicted = false;  // two volumes on one side of a triangle
  std::vector<char> listed(m_.triangles.size(), 0);
  std::map<int, std::vector<size_t>> on_surface;  // entity -> its triangles
  for (size_t i = 0; i < m_.triangles.size(); ++i) on_surface[tri_info_[i].entity].push_back(i);
  // A triangle bounds two volumes at most: past that the file contradicts
  // itself, and its volumes could make this quadratic in its size.
  size_t looked_at = 0;
  for (const auto& [vtag, v] : volumes_) {
    if (contradicted) break;
    const int region = numbered(group_number(volume_group(v), vtag, largest));
    std::set<int> bounding;
    for (int s : v.bounding)
      if (s != INT_MIN) bounding.insert(std::abs(s));  // (INT_MIN has no absolute value)
    std::vector<size_t> own;
    for (int b : bounding) {
      const auto it = on_surface.find(b);
      if (it != on_surface.end()) own.insert(own.end(), it->second.begin(), it->second.end());
    }
    looked_at += own.size();
    if (looked_at > 2 * m_.triangles.size()) {
      contradicted = true;
      break;
    }
    std::sort(own.begin(), own.end());
    const std::vector<char> out_of_it = turned_out_of_the_volume(m_, own);
    if (out_of_it.size() != own.size()) {
      contradicted = true;
      break;
    }
    for (size_t k = 0; k < own.size(); ++k) {
      Triangle& t = m_.triangles[own[k]];
      if (!listed[own[k]]) t.front = t.back = 0, listed[own[k]] = 1;
      int& side = out_of_it[k] ? t.back : t.front;
      contradicted |= side != 0 && side != region;
      side = region;
    }
  }
  // Sides that do not close each region are dropped, and the regions are
  // found from the surface as for 2.2 ("region tags contradict the surface"
  // before). A triangle no volume lists (a surface-only model: Gmsh writes
  // $Entities in 4.1 all the same) leaves the sides unknown too.
  const bool all_known = std::all_of(listed.begin(), listed.end(), [](char c) { return c != 0; });
  if (contradicted || !all_known || !sides_close_regions(m_)) {
    for (Triangle& t : m_.triangles) t.front = t.back = kUnknownRegion;
    orient_consistently(m_);
  }
}

Mesh MshReader::read() {
  bool have_format = false;
  while (!in_.at_end()) {
    const std::string_view section = in_.token("a section");
    if (section.empty() || section[0] != '$') in_.fail("expected a $Section, found '" +
                                                       std::string(section.substr(0, 40)) + "'");
    // MSH 1.0 has no $MeshFormat: it starts with its nodes.
    if (!have_format && section == "$NOD") version_ = 1.0, have_format = true;
    if (!have_format && section != "$MeshFormat") in_.fail("the file does not start with $MeshFormat (nor $NOD, MSH 1.0)");
    // Binary 4.1 sections start right after the line of their name.
    if (binary_ && version_ >= 4 &&
        (section == "$Entities" || section == "$PartitionedEntities" || section == "$Nodes" || section == "$Elements"))
      in_.skip_line();
    const bool msh1 = have_format && version_ < 2;
    if (msh1 && (section == "$NOD" || section == "$ELM")) {
      if (section == "$NOD" ? !m_.points.empty() : (!m_.triangles.empty() || !m_.tets.empty()))
        in_.fail("a second " + std::string(section) + " section");
      section == "$NOD" ? read_nodes22(false) : read_elements10();
    } else if (msh1 && section == "$MeshFormat") {
      in_.fail("$MeshFormat after the nodes of an MSH 1.0 file");
    } else if (section == "$MeshFormat") {
      read_format();
      have_format = true;
    } else if (section == "$PhysicalNames") {
      read_physical_names();
    } else if (section == "$Entities") {
      read_entities();
    } else if (section == "$PartitionedEntities") {
      read_partitioned_entities();
    } else if (section == "$Nodes") {
      if (!m_.points.empty()) in_.fail("a second $Nodes section");
      version_ < 4 ? read_nodes22(false) : read_nodes41();
    } else if (section == "$ParametricNodes" && version_ < 4) {
      if (!m_.points.empty()) in_.fail("a second $Nodes section");
      read_nodes22(true);
    } else if (section == "$Elements") {
      if (!m_.triangles.empty() || !m_.tets.empty()) in_.fail("a second $Elements section");
      version_ < 4 ? read_elements22() : read_elements41();
    } else {
      skip_section(section);
    }
  }
  if (!have_format) in_.fail("empty file, expected $MeshFormat");
  finish();
  return std::move(m_);
}

}  // namespace

Mesh read_gmsh(const std::string& path) {
  const detail::FileBytes data(path);
  return MshReader(data, path).read();
}

}  // namespace vd::io::detail
