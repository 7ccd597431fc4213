#include "mesh/msh_format.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <unordered_map>
#include <unordered_set>

namespace dsdem::mesh {

const MshElementType* msh_element_type(int type) {
  // Gmsh's numbering (GmshDefines.h), names as gmsh::model::mesh::getElementProperties gives them.
  static const MshElementType kTypes[] = {
      {"Line 2", 1, 2},           {"Triangle 3", 2, 3},        {"Quadrilateral 4", 2, 4},  {"Tetrahedron 4", 3, 4},
      {"Hexahedron 8", 3, 8},     {"Prism 6", 3, 6},           {"Pyramid 5", 3, 5},        {"Line 3", 1, 3},
      {"Triangle 6", 2, 6},       {"Quadrilateral 9", 2, 9},   {"Tetrahedron 10", 3, 10},  {"Hexahedron 27", 3, 27},
      {"Prism 18", 3, 18},        {"Pyramid 14", 3, 14},       {"Point", 0, 1},            {"Quadrilateral 8", 2, 8},
      {"Hexahedron 20", 3, 20},   {"Prism 15", 3, 15},         {"Pyramid 13", 3, 13},      {"Triangle 9", 2, 9},
      {"Triangle 10", 2, 10},     {"Triangle 12", 2, 12},      {"Triangle 15", 2, 15},     {"Triangle 15", 2, 15},
      {"Triangle 21", 2, 21},     {"Line 4", 1, 4},            {"Line 5", 1, 5},           {"Line 6", 1, 6},
      {"Tetrahedron 20", 3, 20},  {"Tetrahedron 35", 3, 35},   {"Tetrahedron 56", 3, 56}};
  if (type < 1 || type > static_cast<int>(std::size(kTypes))) return nullptr;
  return &kTypes[type - 1];
}

namespace {

const char* kDimName[] = {"point", "curve", "surface", "volume"};

// A line quoted in an error message: at most 60 characters, control bytes as '?'.
std::string shown(std::string_view line) {
  std::string s(line.substr(0, 60));
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 32) c = '?';
  return line.size() > 60 ? s + "..." : s;
}

bool blank(std::string_view line) { return line.find_first_not_of(" \t") == std::string_view::npos; }

void split(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    std::size_t j = i;
    while (j < line.size() && line[j] != ' ' && line[j] != '\t') ++j;
    if (j > i) out.push_back(line.substr(i, j - i));
    i = j;
  }
}

// The file's lines with their numbers; every error names PATH:LINE.
class Lines {
 public:
  Lines(std::string_view text, const std::string& path) : text_(text), path_(path) {}

  // Next line without its '\r\n' or '\n'; false at the end of the text.
  bool next(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const std::size_t end = std::min(text_.find('\n', pos_), text_.size());
    line = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_no_;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.find('\0') != std::string_view::npos)
      fail("not a Gmsh ASCII .msh file: NUL byte (binary data; save the mesh as ASCII, Mesh.Binary = 0)");
    return true;
  }
  long line_no() const { return line_no_; }
  // Bytes not read yet: caps every reservation made from a count in the file.
  std::size_t remaining() const { return pos_ >= text_.size() ? 0 : text_.size() - pos_; }
  // Whether the text still holds `s` (at the start of a line) after the current line.
  bool ahead(std::string_view s) const {
    for (std::size_t at = text_.find(s, std::min(pos_, text_.size())); at != std::string_view::npos; at = text_.find(s, at + 1))
      if (at == 0 || text_[at - 1] == '\n') return true;
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const { fail_at(line_no_, what); }
  [[noreturn]] void fail_at(long line, const std::string& what) const {
    throw std::runtime_error(fmt::format("{}:{}: {}", path_, line, what));
  }

 private:
  std::string_view text_;
  const std::string& path_;
  std::size_t pos_ = 0;
  long line_no_ = 0;
};

// One section's content: lines until $EndNAME, each split into tokens.
class Section {
 public:
  Section(Lines& lines, std::string name) : lines_(lines), name_(std::move(name)) {}

  // Tokens of the next non-blank content line; a '$' line or the end of the file here
  // means the section is cut short.
  const std::vector<std::string_view>& line() {
    std::string_view l;
    do {
      if (!lines_.next(l)) lines_.fail(fmt::format("${} is not closed (truncated file?)", name_));
    } while (blank(l));
    if (l[0] == '$') lines_.fail(fmt::format("${} is not closed before '{}'", name_, shown(l)));
    split(l, tokens_);
    return tokens_;
  }
  // Tokens of the next line, which must hold exactly n of them.
  const std::vector<std::string_view>& line(std::size_t n, const char* what) {
    line();
    if (tokens_.size() != n) fail(fmt::format("{} values on a line of {} (expected {}: {})", tokens_.size(), where(), n, what));
    return tokens_;
  }
  // The closing $EndNAME, after all entries the counts announced.
  void end() {
    std::string_view l;
    do {
      if (!lines_.next(l)) lines_.fail(fmt::format("${} is not closed (truncated file?)", name_));
    } while (blank(l));
    if (l == "$End" + name_) return;
    if (l[0] == '$') lines_.fail(fmt::format("${} is not closed before '{}'", name_, shown(l)));
    lines_.fail(fmt::format("'{}' in {} after all the entries its counts announce (expected $End{})", shown(l), where(),
                            name_));
  }

  std::int64_t integer(std::string_view tok, const char* what, std::int64_t lo, std::int64_t hi) {
    std::int64_t v = 0;
    const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || p != tok.data() + tok.size())
      fail(fmt::format("{} '{}' in {} is not an integer", what, shown(tok), where()));
    if (v < lo || v > hi) fail(fmt::format("{} {} in {} is out of range {}..{}", what, v, where(), lo, hi));
    return v;
  }
  double real(std::string_view tok, const char* what) {
    double v = 0;
    const auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || p != tok.data() + tok.size() || !std::isfinite(v))
      fail(fmt::format("{} '{}' in {} is not a finite number", what, shown(tok), where()));
    return v;
  }
  // A count of entries that each take at least min_bytes of the rest of the file.
  std::size_t count(std::string_view tok, const char* what, std::size_t min_bytes) {
    const auto n = static_cast<std::size_t>(integer(tok, what, 0, std::int64_t(1) << 53));
    if (n > lines_.remaining() / min_bytes) {
      if (!lines_.ahead("$End" + name_)) fail(fmt::format("${} is not closed (truncated file?)", name_));
      fail(fmt::format("{} {} in {} is more than the rest of the file can hold (truncated file?)", what, n, where()));
    }
    return n;
  }

  [[noreturn]] void fail(const std::string& what) { lines_.fail(what); }
  [[noreturn]] void fail_at(long line, const std::string& what) { lines_.fail_at(line, what); }
  long line_no() const { return lines_.line_no(); }
  std::string where() const { return "$" + name_; }

 private:
  Lines& lines_;
  std::string name_;
  std::vector<std::string_view> tokens_;
};

constexpr std::int64_t kIntMax = 2147483647;       // entity and physical tags are C ints in Gmsh
constexpr std::int64_t kTagMax = std::int64_t(1) << 62;  // node and element tags

class Parser {
 public:
  Parser(std::string_view text, const std::string& path) : lines_(text, path) { file_.path = path; }

  MshFile run() {
    std::string_view l;
    bool saw_format = false, saw_nodes = false, saw_elements = false, saw_names = false, saw_entities = false;
    while (lines_.next(l)) {
      if (lines_.line_no() == 1 && l != "$MeshFormat") lines_.fail("not a Gmsh ASCII .msh file: the first line must be $MeshFormat");
      if (blank(l)) continue;
      if (l.substr(0, 4) == "$End")
        lines_.fail(fmt::format("'{}' without a matching ${}", shown(l), shown(l.substr(4))));
      if (l[0] != '$') lines_.fail(fmt::format("'{}' outside every section ($Name ... $EndName)", shown(l)));
      const std::string name(l.substr(1));
      auto once = [&](bool& seen) {
        if (seen) lines_.fail(fmt::format("a second ${} section", name));
        seen = true;
      };
      if (name == "MeshFormat") {
        if (lines_.line_no() != 1) lines_.fail("a second $MeshFormat section");
        mesh_format();
        saw_format = true;
      } else if (name == "PhysicalNames") {
        once(saw_names);
        physical_names();
      } else if (name == "Entities" && file_.major_version == 4) {
        once(saw_entities);
        if (saw_nodes) lines_.fail("$Entities after $Nodes (nodes refer to entities)");
        entities();
      } else if (name == "Nodes") {
        once(saw_nodes);
        if (file_.major_version == 4) nodes41(); else nodes22();
      } else if (name == "Elements") {
        once(saw_elements);
        if (!saw_nodes) lines_.fail("$Elements before $Nodes (elements refer to nodes)");
        if (file_.major_version == 4) elements41(); else elements22();
      } else {
        skip(name);
      }
    }
    if (lines_.line_no() == 0) lines_.fail_at(1, "not a Gmsh ASCII .msh file: empty file");
    if (!saw_format) lines_.fail("not a Gmsh ASCII .msh file: no version line after $MeshFormat");
    if (!saw_nodes) lines_.fail("no $Nodes section (was it meshed?)");
    file_.last_line = lines_.line_no();
    if (file_.major_version == 2) {
      sort_elements22();
      assign_nodes22();
    }
    return std::move(file_);
  }

 private:
  void mesh_format() {
    std::string_view l;
    auto fail = [&](const std::string& what) { lines_.fail("not a Gmsh ASCII .msh file: " + what); };
    if (!lines_.next(l)) fail("no version line after $MeshFormat");
    std::vector<std::string_view> t;
    split(l, t);
    double version = 0;
    int file_type = -1, data_size = 0;
    auto num = [](std::string_view s, auto& v) {
      const auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
      return ec == std::errc() && p == s.data() + s.size();
    };
    if (t.size() != 3 || !num(t[0], version) || !num(t[1], file_type) || !num(t[2], data_size))
      fail("expected 'version file-type data-size' after $MeshFormat");
    if (version != 4.1 && version != 2.2)
      fail(fmt::format("unsupported .msh version {} (write 4.1 or 2.2)", version));
    if (file_type != 0) fail("binary .msh (save the mesh as ASCII, Mesh.Binary = 0)");
    if (data_size != sizeof(double)) fail(fmt::format("data size {} (expected {})", data_size, sizeof(double)));
    file_.major_version = version == 4.1 ? 4 : 2;
    Section s(lines_, "MeshFormat");
    s.end();
  }

  void physical_names() {
    Section s(lines_, "PhysicalNames");
    const std::size_t n = s.count(s.line(1, "the number of names")[0], "number of names", 6);
    for (std::size_t i = 0; i < n; ++i) {
      const auto& t = s.line();
      if (t.size() < 3) s.fail("a physical name needs 'dim tag \"name\"'");
      const std::int64_t dim = s.integer(t[0], "physical dimension", -kIntMax, kIntMax);
      const std::int64_t tag = s.integer(t[1], "physical tag", -kIntMax, kIntMax);
      // Gmsh 4.8 crashed on a dimension outside 0..3 (a fuzz find): refused here too.
      if (dim < 0 || dim > 3 || tag <= 0)
        s.fail(fmt::format("not a Gmsh ASCII .msh file: physical name with dimension {} and tag {} (dimension 0..3, tag > 0)", dim, tag));
      // The name runs from the first '"' to the next, as Gmsh reads it; spaces allowed.
      const char* b = t[2].data();
      const char* e = t.back().data() + t.back().size();
      const std::string_view rest(b, static_cast<std::size_t>(e - b));
      const std::size_t q1 = rest.find('"');
      const std::size_t q2 = q1 == std::string_view::npos ? q1 : rest.find('"', q1 + 1);
      if (q1 != 0 || q2 == std::string_view::npos || q2 + 1 != rest.size())
        s.fail(fmt::format("physical name '{}' is not one double-quoted string", shown(rest)));
      if (!file_.physical_names.emplace(std::pair{int(dim), int(tag)}, std::string(rest.substr(1, q2 - 1))).second)
        s.fail(fmt::format("a second name for physical group (dim {}, tag {})", dim, tag));
    }
    s.end();
  }

  void entities() {
    Section s(lines_, "Entities");
    const auto& h = s.line(4, "numPoints numCurves numSurfaces numVolumes");
    std::size_t counts[4];
    for (int d = 0; d < 4; ++d) counts[d] = s.count(h[d], "number of entities", 10);
    for (int d = 0; d < 4; ++d) {
      for (std::size_t i = 0; i < counts[d]; ++i) {
        const auto& t = s.line();
        // point: tag x y z nphys phys...; others: tag box(6) nphys phys... nbound bound...
        const std::size_t nphys_at = d == 0 ? 4 : 7;
        if (t.size() <= nphys_at) s.fail(fmt::format("{} entity line has {} values (too few)", kDimName[d], t.size()));
        const int tag = static_cast<int>(s.integer(t[0], "entity tag", 1, kIntMax));
        for (std::size_t k = 1; k < nphys_at; ++k) s.real(t[k], "entity coordinate");
        const std::size_t nphys = static_cast<std::size_t>(s.integer(t[nphys_at], "number of physical tags", 0, kIntMax));
        const std::size_t nbound_at = nphys_at + 1 + nphys;
        const bool ok = d == 0 ? t.size() == nbound_at : t.size() > nbound_at;
        if (!ok) s.fail(fmt::format("{} entity {} has {} values (its counts need {}{})", kDimName[d], tag, t.size(),
                                    nbound_at + (d > 0), d > 0 ? " and its bounding entities" : ""));
        MshEntity e;
        for (std::size_t k = nphys_at + 1; k < nbound_at; ++k) {
          // A negative physical tag marks an entity used reversed; Gmsh takes its absolute value.
          std::int64_t p = s.integer(t[k], "physical tag", -kIntMax, kIntMax);
          if (p == 0) s.fail(fmt::format("physical tag 0 on {} entity {}", kDimName[d], tag));
          p = std::abs(p);
          if (std::find(e.physicals.begin(), e.physicals.end(), int(p)) == e.physicals.end()) e.physicals.push_back(int(p));
        }
        if (d > 0) {
          const std::size_t nb = static_cast<std::size_t>(s.integer(t[nbound_at], "number of bounding entities", 0, kIntMax));
          if (t.size() != nbound_at + 1 + nb)
            s.fail(fmt::format("{} entity {} has {} values (its counts need {})", kDimName[d], tag, t.size(), nbound_at + 1 + nb));
          for (std::size_t k = nbound_at + 1; k < t.size(); ++k) {
            const std::int64_t b = std::abs(s.integer(t[k], "bounding entity tag", -kIntMax, kIntMax));
            if (!file_.entities.count({d - 1, int(b)}))
              s.fail(fmt::format("{} entity {} is bounded by unknown {} entity {}", kDimName[d], tag, kDimName[d - 1], b));
          }
        }
        if (!file_.entities.emplace(std::pair{d, tag}, std::move(e)).second)
          s.fail(fmt::format("{} entity {} is defined twice", kDimName[d], tag));
      }
    }
    s.end();
  }

  MshEntity& entity(Section& s, std::int64_t dim, std::int64_t tag) {
    auto it = file_.entities.find({int(dim), int(tag)});
    if (it == file_.entities.end())
      s.fail(fmt::format("{} refers to unknown {} entity {} (not in $Entities)", s.where(), kDimName[dim], tag));
    return it->second;
  }

  // One node's tag, checked against the header's range and the tags seen so far.
  void add_node_tag(Section& s, std::string_view tok, std::int64_t lo, std::int64_t hi) {
    const std::int64_t tag = s.integer(tok, "node tag", lo, hi);
    if (!node_index_.emplace(tag, file_.node_tags.size()).second) s.fail(fmt::format("node {} is defined twice", tag));
    file_.node_tags.push_back(tag);
  }
  void add_node_xyz(Section& s, std::string_view tx, std::string_view ty, std::string_view tz) {
    const double x = s.real(tx, "node coordinate"), y = s.real(ty, "node coordinate"), z = s.real(tz, "node coordinate");
    if (z != 0.0 && file_.first_off_plane.line == 0)
      file_.first_off_plane = {lines_.line_no(), file_.node_tags[file_.node_xyz.size()], z};
    file_.node_xyz.push_back({x, y, z});
  }

  void nodes41() {
    Section s(lines_, "Nodes");
    const auto& h = s.line(4, "numEntityBlocks numNodes minNodeTag maxNodeTag");
    const long header_line = s.line_no();
    const std::size_t blocks = s.count(h[0], "number of node blocks", 8);
    const std::size_t total = s.count(h[1], "number of nodes", 8);
    const std::int64_t lo = s.integer(h[2], "minimum node tag", 0, kTagMax);
    const std::int64_t hi = s.integer(h[3], "maximum node tag", 0, kTagMax);
    if (total > 0 && (lo < 1 || hi < lo || static_cast<std::uint64_t>(hi - lo) + 1 < total))
      s.fail(fmt::format("node tags {}..{} cannot hold {} nodes", lo, hi, total));
    file_.node_tags.reserve(total);
    file_.node_xyz.reserve(total);
    node_index_.reserve(total);
    for (std::size_t b = 0; b < blocks; ++b) {
      const auto& bh = s.line(4, "entityDim entityTag parametric numNodesInBlock");
      const std::int64_t dim = s.integer(bh[0], "entity dimension", 0, 3);
      const std::int64_t tag = s.integer(bh[1], "entity tag", 1, kIntMax);
      const bool parametric = s.integer(bh[2], "parametric flag", 0, 1) == 1;
      const std::size_t n = s.count(bh[3], "number of nodes in block", 8);
      MshEntity& e = entity(s, dim, tag);
      const std::size_t first = file_.node_tags.size();
      if (n > total - first) s.fail(fmt::format("node blocks hold more than the {} nodes the header counts", total));
      for (std::size_t i = 0; i < n; ++i) add_node_tag(s, s.line(1, "a node tag")[0], lo, hi);
      const std::size_t nxyz = 3 + (parametric && (dim == 1 || dim == 2) ? dim : 0);
      for (std::size_t i = 0; i < n; ++i) {
        const auto& t = s.line(nxyz, parametric ? "x y z and the parametric coordinates" : "x y z");
        for (std::size_t k = 3; k < nxyz; ++k) s.real(t[k], "parametric coordinate");
        add_node_xyz(s, t[0], t[1], t[2]);
        e.nodes.push_back(first + i);
      }
    }
    if (file_.node_tags.size() != total)
      s.fail_at(header_line, fmt::format("node blocks hold {} nodes; the header counts {}", file_.node_tags.size(), total));
    s.end();
  }

  void nodes22() {
    Section s(lines_, "Nodes");
    const std::size_t total = s.count(s.line(1, "the number of nodes")[0], "number of nodes", 8);
    file_.node_tags.reserve(total);
    file_.node_xyz.reserve(total);
    node_index_.reserve(total);
    for (std::size_t i = 0; i < total; ++i) {
      const auto& t = s.line(4, "tag x y z");
      add_node_tag(s, t[0], 1, kTagMax);
      add_node_xyz(s, t[1], t[2], t[3]);
    }
    s.end();
  }

  std::size_t node_of(Section& s, std::string_view tok) {
    const std::int64_t tag = s.integer(tok, "node tag", 1, kTagMax);
    auto it = node_index_.find(tag);
    if (it == node_index_.end()) s.fail(fmt::format("element refers to unknown node {}", tag));
    return it->second;
  }

  // The element's tag, checked for repeats; appends it with its nodes (tokens from `first`).
  void add_element(Section& s, std::int64_t tag, int type, const std::vector<std::string_view>& t, std::size_t first,
                   MshEntity& e) {
    if (!element_tags_.insert(tag).second) s.fail(fmt::format("element {} is defined twice", tag));
    MshElement el{tag, type, file_.element_nodes.size(), s.line_no()};
    for (std::size_t k = first; k < t.size(); ++k) file_.element_nodes.push_back(node_of(s, t[k]));
    e.elements[type].push_back(file_.elements.size());
    file_.elements.push_back(el);
  }

  const MshElementType& element_type(Section& s, std::string_view tok) {
    const std::int64_t type = s.integer(tok, "element type", 1, kIntMax);
    const MshElementType* et = msh_element_type(static_cast<int>(type));
    if (!et) s.fail(fmt::format("element type {} is not a Gmsh element type dsdem knows", type));
    return *et;
  }

  void elements41() {
    Section s(lines_, "Elements");
    const auto& h = s.line(4, "numEntityBlocks numElements minElementTag maxElementTag");
    const long header_line = s.line_no();
    const std::size_t blocks = s.count(h[0], "number of element blocks", 8);
    const std::size_t total = s.count(h[1], "number of elements", 4);
    const std::int64_t lo = s.integer(h[2], "minimum element tag", 0, kTagMax);
    const std::int64_t hi = s.integer(h[3], "maximum element tag", 0, kTagMax);
    if (total > 0 && (lo < 1 || hi < lo || static_cast<std::uint64_t>(hi - lo) + 1 < total))
      s.fail(fmt::format("element tags {}..{} cannot hold {} elements", lo, hi, total));
    file_.elements.reserve(total);
    element_tags_.reserve(total);
    std::size_t seen = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      const auto& bh = s.line(4, "entityDim entityTag elementType numElementsInBlock");
      const std::int64_t dim = s.integer(bh[0], "entity dimension", 0, 3);
      const std::int64_t tag = s.integer(bh[1], "entity tag", 1, kIntMax);
      const int type = static_cast<int>(s.integer(bh[2], "element type", 1, kIntMax));
      const std::size_t n = s.count(bh[3], "number of elements in block", 4);
      const MshElementType& et = element_type(s, bh[2]);
      if (et.dim != dim)
        s.fail(fmt::format("'{}' elements (type {}) in a block of {} entity {}", et.name, type, kDimName[dim], tag));
      MshEntity& e = entity(s, dim, tag);
      if (n > total - seen) s.fail(fmt::format("element blocks hold more than the {} elements the header counts", total));
      seen += n;
      for (std::size_t i = 0; i < n; ++i) {
        const auto& t = s.line(1 + et.num_nodes, "the element tag and its nodes");
        add_element(s, s.integer(t[0], "element tag", lo, hi), type, t, 1, e);
      }
    }
    if (seen != total) s.fail_at(header_line, fmt::format("element blocks hold {} elements; the header counts {}", seen, total));
    s.end();
  }

  void elements22() {
    Section s(lines_, "Elements");
    const std::size_t total = s.count(s.line(1, "the number of elements")[0], "number of elements", 8);
    file_.elements.reserve(total);
    element_tags_.reserve(total);
    for (std::size_t i = 0; i < total; ++i) {
      const auto& t = s.line();
      if (t.size() < 5) s.fail("an element line needs 'tag type numTags physical elementary ... nodes'");
      const std::int64_t tag = s.integer(t[0], "element tag", 1, kTagMax);
      const MshElementType& et = element_type(s, t[1]);
      const int type = static_cast<int>(s.integer(t[1], "element type", 1, kIntMax));
      const std::size_t ntags = static_cast<std::size_t>(s.integer(t[2], "number of element tags", 2, 1000));
      if (t.size() != 3 + ntags + et.num_nodes)
        s.fail(fmt::format("element {} has {} values ('{}' with {} tags needs {})", tag, t.size(), et.name, ntags,
                           3 + ntags + et.num_nodes));
      // 2.2: the first tag is the physical group (0: none), the second the elementary entity.
      const int physical = static_cast<int>(s.integer(t[3], "physical tag", 0, kIntMax));
      const int elementary = static_cast<int>(s.integer(t[4], "elementary entity tag", 1, kIntMax));
      for (std::size_t k = 5; k < 3 + ntags; ++k) s.integer(t[k], "element tag", -kTagMax, kTagMax);
      MshEntity& e = file_.entities[{et.dim, elementary}];
      if (physical > 0 && std::find(e.physicals.begin(), e.physicals.end(), physical) == e.physicals.end())
        e.physicals.push_back(physical);
      add_element(s, tag, type, t, 3 + ntags, e);
    }
    s.end();
  }

  // Gmsh's 2.2 reader lists an entity's elements by increasing tag, whatever the file's order.
  void sort_elements22() {
    for (auto& [key, e] : file_.entities)
      for (auto& [type, elems] : e.elements)
        std::sort(elems.begin(), elems.end(),
                  [&](std::size_t a, std::size_t b) { return file_.elements[a].tag < file_.elements[b].tag; });
  }

  // 2.2 keeps no node-to-entity link: Gmsh gives each node used by an element to the
  // lowest-dimension entity using it (the smallest tag among equals), drops unused
  // nodes, and lists an entity's nodes by increasing tag. Done the same way here.
  void assign_nodes22() {
    constexpr std::size_t kNone = static_cast<std::size_t>(-1);
    std::vector<std::pair<int, int>> keys;
    for (const auto& [key, e] : file_.entities) keys.push_back(key);
    std::vector<std::size_t> owner(file_.node_tags.size(), kNone);
    for (std::size_t k = 0; k < keys.size(); ++k) {
      for (const auto& [type, elems] : file_.entities[keys[k]].elements) {
        const int nn = msh_element_type(type)->num_nodes;
        for (std::size_t ei : elems)
          for (int j = 0; j < nn; ++j) {
            std::size_t& o = owner[file_.element_nodes[file_.elements[ei].first_node + j]];
            if (o == kNone) o = k;  // keys are in (dim, tag) order: the first is the lowest
          }
      }
    }
    std::vector<std::size_t> by_tag(file_.node_tags.size());
    for (std::size_t i = 0; i < by_tag.size(); ++i) by_tag[i] = i;
    std::sort(by_tag.begin(), by_tag.end(), [&](std::size_t a, std::size_t b) { return file_.node_tags[a] < file_.node_tags[b]; });
    for (std::size_t i : by_tag)
      if (owner[i] != kNone) file_.entities[keys[owner[i]]].nodes.push_back(i);
  }

  void skip(const std::string& name) {
    // Sections dsdem does not use ($Periodic, $NodeData, ...): skipped up to their end.
    std::string_view l;
    while (true) {
      if (!lines_.next(l)) lines_.fail(fmt::format("${} is not closed (truncated file?)", name));
      if (l == "$End" + name) return;
      if (!l.empty() && l[0] == '$') lines_.fail(fmt::format("${} is not closed before '{}'", name, shown(l)));
    }
  }

  Lines lines_;
  MshFile file_;
  std::unordered_map<std::int64_t, std::size_t> node_index_;
  std::unordered_set<std::int64_t> element_tags_;
};

}  // namespace

MshFile parse_msh(std::string_view text, const std::string& path) { return Parser(text, path).run(); }

}  // namespace dsdem::mesh
