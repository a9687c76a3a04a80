#include "io/obj_reader.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <utility>
#include <vector>

#include "core/util/error.h"
#include "io/text_file.h"

namespace clothbake::io {

namespace {

std::string line_field(int line) { return "line " + std::to_string(line); }

std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

std::vector<std::string_view> split_whitespace(std::string_view s) {
  std::vector<std::string_view> tokens;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > start) tokens.push_back(s.substr(start, i - start));
  }
  return tokens;
}

class ObjParser {
 public:
  explicit ObjParser(std::string path) : m_path(std::move(path)) {}

  [[noreturn]] void fail(int line, const std::string& message) const {
    throw InputError(line_field(line), message, m_path);
  }

  /// A finite coordinate; the whole token must be the number.
  float number(int line, std::string_view token, const char* what) const {
    double d = 0.0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), d);
    if (ec == std::errc::result_out_of_range)
      fail(line, "malformed number '" + std::string(token) + "' in " + what + " (out of range)");
    if (ec != std::errc() || end != token.data() + token.size())
      fail(line, "malformed number '" + std::string(token) + "' in " + what);
    if (!std::isfinite(d) || std::fabs(d) > 3.0e38)
      fail(line, "non-finite number '" + std::string(token) + "' in " + what);
    return static_cast<float>(d);
  }

  /// A 1-based (or negative, relative) OBJ index; returns it unresolved.
  long index(int line, std::string_view token, std::string_view corner) const {
    long i = 0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), i);
    if (ec != std::errc() || end != token.data() + token.size() || i == 0)
      fail(line, "malformed index '" + std::string(token) + "' in face corner '" +
                     std::string(corner) + "' (OBJ indices are non-zero integers)");
    return i;
  }

 private:
  std::string m_path;
};

// An index as read, kept with its line until all elements are known, so that
// positive indices may refer forward (as many readers allow).
struct RawCorner {
  long position, uv;
};
struct RawQuad {
  RawCorner corner[4];
  int line;
};

// Resolves an OBJ index against `count` elements (the count when the face was
// read, for negative indices; the final count for positive ones).
bool resolve(long index, long count_at_line, long count_total, int& out) {
  const long i = index < 0 ? count_at_line + index : index - 1;
  if (i < 0 || i >= count_total || (index < 0 && i >= count_at_line)) return false;
  out = static_cast<int>(i);
  return true;
}

}  // namespace

QuadMesh read_obj_quads(const std::string& path) {
  return obj_quads_from_text(read_text_file(path, "an OBJ file"), path);
}

// About 135 lines, kept whole: a line-by-line parser with one case per OBJ
// statement, each refusing with the line number.
QuadMesh obj_quads_from_text(std::string_view all, const std::string& path) {
  const ObjParser parser(path);
  QuadMesh mesh;
  std::vector<RawQuad> raw;
  // Counts at the time each face was read, for negative indices.
  std::vector<std::pair<long, long>> counts_at_face;

  // Step 1: read statements line by line.
  int line = 0;
  for (size_t begin = 0; begin < all.size();) {
    // One line, as std::getline splits them: the last may lack its '\n'.
    const size_t newline = all.find('\n', begin);
    const size_t end = newline == std::string_view::npos ? all.size() : newline;
    std::string_view s = all.substr(begin, end - begin);
    begin = end + 1;
    ++line;
    if (const size_t hash = s.find('#'); hash != std::string_view::npos) s = s.substr(0, hash);
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    const std::vector<std::string_view> tok = split_whitespace(s);
    if (tok.empty()) continue;
    const std::string_view key = tok[0];

    if (key == "v") {
      if (tok.size() < 4) parser.fail(line, "'v' needs three coordinates x y z");
      Imath::V3f p;
      for (int c = 0; c < 3; ++c) p[c] = parser.number(line, tok[1 + c], "vertex position");
      for (size_t c = 4; c < tok.size(); ++c) (void)parser.number(line, tok[c], "vertex");
      mesh.positions_world.push_back(p);
    } else if (key == "vt") {
      if (tok.size() < 3) parser.fail(line, "'vt' needs two coordinates u v");
      Imath::V2f uv;
      for (int c = 0; c < 2; ++c) uv[c] = parser.number(line, tok[1 + c], "texture coordinate");
      for (size_t c = 3; c < tok.size(); ++c) (void)parser.number(line, tok[c], "vt");
      mesh.uvs.push_back(uv);
    } else if (key == "f") {
      const size_t corners = tok.size() - 1;
      if (corners != 4)
        parser.fail(line, "face has " + std::to_string(corners) +
                              " corners; clothbake needs quads (4 corners)");
      RawQuad q;
      q.line = line;
      for (int c = 0; c < 4; ++c) {
        const std::string_view corner = tok[1 + c];
        const size_t slash = corner.find('/');
        const std::string_view pos = corner.substr(0, slash);
        std::string_view uv;
        if (slash != std::string_view::npos) {
          uv = corner.substr(slash + 1);
          uv = uv.substr(0, uv.find('/'));
        }
        if (uv.empty())
          parser.fail(line, "face corner " + std::to_string(c + 1) + " ('" + std::string(corner) +
                                "') has no texture coordinate; clothbake needs UVs (the weave "
                                "follows them)");
        q.corner[c] = {parser.index(line, pos, corner), parser.index(line, uv, corner)};
      }
      raw.push_back(q);
      counts_at_face.emplace_back(static_cast<long>(mesh.positions_world.size()),
                                  static_cast<long>(mesh.uvs.size()));
    } else if (key == "vn" || key == "o" || key == "g" || key == "s" || key == "usemtl" ||
               key == "mtllib") {
      // Normals come from the quads themselves; groups and materials do not matter.
    } else {
      parser.fail(line, "unsupported OBJ statement '" + std::string(key) +
                            "' (clothbake reads v, vt, f and ignores vn, o, g, s, usemtl, "
                            "mtllib)");
    }
  }
  if (raw.empty())
    throw InputError("", "the mesh has no faces; clothbake needs at least one quad", path);

  // Step 2: resolve indices now that every element is known.
  const long n_pos = static_cast<long>(mesh.positions_world.size());
  const long n_uv = static_cast<long>(mesh.uvs.size());
  mesh.quads.reserve(raw.size());
  for (size_t f = 0; f < raw.size(); ++f) {
    QuadMesh::Quad quad;
    for (int c = 0; c < 4; ++c) {
      const RawCorner& rc = raw[f].corner[c];
      if (!resolve(rc.position, counts_at_face[f].first, n_pos, quad.position[c]))
        parser.fail(raw[f].line, "vertex index " + std::to_string(rc.position) + " of corner " +
                                     std::to_string(c + 1) + " is out of range (" +
                                     std::to_string(n_pos) + " vertices)");
      if (!resolve(rc.uv, counts_at_face[f].second, n_uv, quad.uv[c]))
        parser.fail(raw[f].line, "texture coordinate index " + std::to_string(rc.uv) +
                                     " of corner " + std::to_string(c + 1) + " is out of range (" +
                                     std::to_string(n_uv) + " texture coordinates)");
    }
    mesh.quads.push_back(quad);
  }

  // Step 3: refuse degenerate quads, relative to the mesh's own scale. The
  // diagonals' cross product is twice the area of a planar quad and the
  // area of the projection for a twisted one.
  Imath::V3d lo(1e300), hi(-1e300);
  for (const Imath::V3f& p : mesh.positions_world)
    for (int c = 0; c < 3; ++c) {
      lo[c] = std::min(lo[c], double(p[c]));
      hi[c] = std::max(hi[c], double(p[c]));
    }
  Imath::V2d uv_lo(1e300), uv_hi(-1e300);
  for (const Imath::V2f& t : mesh.uvs)
    for (int c = 0; c < 2; ++c) {
      uv_lo[c] = std::min(uv_lo[c], double(t[c]));
      uv_hi[c] = std::max(uv_hi[c], double(t[c]));
    }
  const double diag2 = (hi - lo).length2();
  const double uv_diag2 = n_uv > 0 ? (uv_hi - uv_lo).length2() : 0.0;
  for (size_t f = 0; f < mesh.quads.size(); ++f) {
    const QuadMesh::Quad& q = mesh.quads[f];
    Imath::V3d p[4];
    Imath::V2d t[4];
    for (int c = 0; c < 4; ++c) {
      const Imath::V3f& pf = mesh.positions_world[q.position[c]];
      p[c] = Imath::V3d(pf.x, pf.y, pf.z);
      t[c] = Imath::V2d(mesh.uvs[q.uv[c]].x, mesh.uvs[q.uv[c]].y);
    }
    const double area = 0.5 * ((p[2] - p[0]).cross(p[3] - p[1])).length();
    if (area == 0.0 || area < 1e-12 * diag2)
      parser.fail(raw[f].line, "quad has zero area (" + format_number(area) +
                                   " square units); clothbake cannot map a texture onto it");
    // A collapsed edge leaves a triangle: its patch has a singular side.
    for (int c = 0; c < 4; ++c)
      for (int d = c + 1; d < 4; ++d)
        if (p[c] == p[d])
          parser.fail(raw[f].line, "corners " + std::to_string(c + 1) + " and " +
                                       std::to_string(d + 1) +
                                       " are the same point; a quad needs four distinct corners");
    const Imath::V2d a = t[2] - t[0], b = t[3] - t[1];
    const double uv_area = 0.5 * std::fabs(a.x * b.y - a.y * b.x);
    if (uv_area == 0.0 || uv_area < 1e-12 * uv_diag2)
      parser.fail(raw[f].line,
                  "quad's texture coordinates have zero area; the weave cannot be mapped onto it");
  }
  return mesh;
}

}  // namespace clothbake::io
