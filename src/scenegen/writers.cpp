// The demo's input files, in the formats of scenes/INPUTS.md, written atomically; small math.
#include <charconv>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <system_error>

#include "scenegen/scenegen_internal.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref::scenegen_detail {

void append_number(std::string& out, double value) {
  if (value == 0.0) value = 0.0;  // no "-0"
  char buf[40];
  const auto r = std::to_chars(buf, buf + sizeof buf, value);
  if (r.ec != std::errc()) throw RunError("scenegen: cannot format a number");
  out.append(buf, r.ptr);
}

namespace {

void append_point(std::string& out, const glm::dvec3& p) {
  append_number(out, p.x);
  out += ' ';
  append_number(out, p.y);
  out += ' ';
  append_number(out, p.z);
}

}  // namespace

void write_obj(const std::filesystem::path& path, const TriMesh& mesh, const std::string& comment) {
  std::string out = "# " + comment + "\n";
  for (const glm::dvec3& p : mesh.positions) {
    out += "v ";
    append_point(out, p);
    out += '\n';
  }
  for (const auto& t : mesh.triangles)
    out += "f " + std::to_string(t[0] + 1) + ' ' + std::to_string(t[1] + 1) + ' ' + std::to_string(t[2] + 1) + '\n';
  write_file_atomic(path, out);
}

void write_medit(const std::filesystem::path& path, const TetSet& set, const std::vector<int>& labels) {
  std::string out = "MeshVersionFormatted 2\nDimension 3\nVertices\n" + std::to_string(set.positions.size()) + '\n';
  for (const glm::dvec3& p : set.positions) {
    append_point(out, p);
    out += " 0\n";
  }
  out += "Tetrahedra\n" + std::to_string(set.tets.size()) + '\n';
  for (std::size_t t = 0; t < set.tets.size(); ++t) {
    const glm::uvec4& k = set.tets[t];
    out += std::to_string(k.x + 1) + ' ' + std::to_string(k.y + 1) + ' ' + std::to_string(k.z + 1) + ' ' +
           std::to_string(k.w + 1) + ' ' + std::to_string(labels[t]) + '\n';
  }
  out += "End\n";
  write_file_atomic(path, out);
}

void write_faces(const std::filesystem::path& path, const std::vector<glm::uvec3>& faces, const std::string& comment) {
  std::string out = "# " + comment + "\n";
  for (const glm::uvec3& f : faces)
    out += std::to_string(f.x) + ' ' + std::to_string(f.y) + ' ' + std::to_string(f.z) + '\n';
  write_file_atomic(path, out);
}

void write_frame(const std::filesystem::path& path, const std::vector<glm::dvec3>& points) {
  std::string out;
  out.reserve(points.size() * 48);
  for (const glm::dvec3& p : points) {
    append_point(out, p);
    out += '\n';
  }
  write_file_atomic(path, out);
}

void write_parent_map(const std::filesystem::path& path, const std::vector<std::uint32_t>& parent) {
  std::string out = "# v parent: vertex v of the last frame was split off vertex parent\n";
  for (std::size_t v = 0; v < parent.size(); ++v)
    if (parent[v] != v) out += std::to_string(v) + ' ' + std::to_string(parent[v]) + '\n';
  write_file_atomic(path, out);
}

void write_rigid(const std::filesystem::path& path, const std::vector<std::vector<RigidTransform>>& frames) {
  std::string out = "# frame piece  r00 r01 r02 t0  r10 r11 r12 t1  r20 r21 r22 t2\n";
  for (std::size_t f = 0; f < frames.size(); ++f)
    for (std::size_t p = 0; p < frames[f].size(); ++p) {
      out += std::to_string(f) + ' ' + std::to_string(p);
      const RigidTransform& x = frames[f][p];
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) {
          out += ' ';
          append_number(out, x.rotation[col][row]);
        }
        out += ' ';
        append_number(out, x.translation[row]);
      }
      out += '\n';
    }
  write_file_atomic(path, out);
}

glm::dvec3 Rng::direction() {
  const double z = uniform(-1.0, 1.0), phi = uniform(0.0, 2.0 * std::numbers::pi);
  const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

glm::dmat3 rotation(const glm::dvec3& axis, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  const glm::dvec3 a = axis;
  // Columns of the Rodrigues matrix.
  return glm::dmat3(glm::dvec3(t * a.x * a.x + c, t * a.x * a.y + s * a.z, t * a.x * a.z - s * a.y),
                    glm::dvec3(t * a.x * a.y - s * a.z, t * a.y * a.y + c, t * a.y * a.z + s * a.x),
                    glm::dvec3(t * a.x * a.z + s * a.y, t * a.y * a.z - s * a.x, t * a.z * a.z + c));
}

double smoothstep01(double x) {
  x = x < 0.0 ? 0.0 : (x > 1.0 ? 1.0 : x);
  return x * x * (3.0 - 2.0 * x);
}

}  // namespace fracref::scenegen_detail
