#include <charconv>
#include <cmath>
#include <string>

#include "io/mesh_writers.hpp"
#include "io/text_scan.hpp"
#include "util/error.hpp"

namespace fracref::io_detail {

void check_soup_for_writing(const MeshSoup& soup, const std::string& file) {
  const std::string prefix = file + ": cannot write: ";
  for (std::size_t i = 0; i < soup.positions.size(); ++i) {
    const glm::dvec3& p = soup.positions[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw RunError(prefix + "vertex " + std::to_string(i) + " has a non-finite coordinate");
  }
  for (std::size_t t = 0; t < soup.triangles.size(); ++t)
    for (std::uint32_t v : soup.triangles[t])
      if (v >= soup.positions.size())
        throw RunError(prefix + "triangle " + std::to_string(t) + " references vertex " + std::to_string(v) +
                       " of " + std::to_string(soup.positions.size()));
  if (soup.triangle_group.empty()) return;
  if (soup.triangle_group.size() != soup.triangles.size())
    throw RunError(prefix + "triangle_group has " + std::to_string(soup.triangle_group.size()) +
                   " entries for " + std::to_string(soup.triangles.size()) + " triangles");
  for (std::uint32_t g : soup.triangle_group)
    if (g >= soup.groups.size())
      throw RunError(prefix + "triangle group " + std::to_string(g) + " of " + std::to_string(soup.groups.size()));
}

void append_double(std::string& out, double value) {
  char buffer[64];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value, std::chars_format::general, 17);
  out.append(buffer, result.ptr);
}

namespace {

void append_uint(std::string& out, std::uint64_t value) {
  char buffer[24];
  auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_xyz(std::string& out, const glm::dvec3& p) {
  append_double(out, p.x);
  out += ' ';
  append_double(out, p.y);
  out += ' ';
  append_double(out, p.z);
  out += '\n';
}

// A name the OBJ reader gives back unchanged: not empty, no comment start, no line break, no
// blank at either end.
void check_group_name(const std::string& name, const std::string& file) {
  bool ok = !name.empty() && trim(name) == name && name.find_first_of("#\r\n") == std::string::npos;
  if (!ok) throw RunError(file + ": cannot write: group name " + quote_token(name) + " would not read back from OBJ");
}

}  // namespace

std::string obj_bytes(const MeshSoup& soup, const std::string& file) {
  bool grouped = !soup.triangle_group.empty();
  if (grouped)
    for (const std::string& name : soup.groups) check_group_name(name, file);
  std::string out = "# fracref mesh: " + std::to_string(soup.positions.size()) + " vertices, " +
                    std::to_string(soup.triangles.size()) + " triangles\n";
  for (const glm::dvec3& p : soup.positions) {
    out += "v ";
    append_xyz(out, p);
  }
  for (std::size_t t = 0; t < soup.triangles.size(); ++t) {
    if (grouped && (t == 0 || soup.triangle_group[t] != soup.triangle_group[t - 1]))
      out += "g " + soup.groups[soup.triangle_group[t]] + "\n";
    out += 'f';
    for (std::uint32_t v : soup.triangles[t]) {
      out += ' ';
      append_uint(out, std::uint64_t(v) + 1);
    }
    out += '\n';
  }
  return out;
}

std::string off_bytes(const MeshSoup& soup) {
  std::string out = "OFF\n" + std::to_string(soup.positions.size()) + " " +
                    std::to_string(soup.triangles.size()) + " 0\n";
  for (const glm::dvec3& p : soup.positions) append_xyz(out, p);
  for (const auto& t : soup.triangles) {
    out += '3';
    for (std::uint32_t v : t) {
      out += ' ';
      append_uint(out, v);
    }
    out += '\n';
  }
  return out;
}

}  // namespace fracref::io_detail
