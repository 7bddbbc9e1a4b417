// The frames check: frames/positions.bin with topology.obj, or frames/frame_NNNN.obj one per
// frame of report.json, each holding every piece with the piece file's vertex count and triangles.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <set>

#include "check/check_internal.hpp"
#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fracref::check_detail {
namespace {

namespace fs = std::filesystem;
using Tri = std::array<std::uint32_t, 3>;

std::string frame_name(std::size_t t) {
  char buffer[40];
  std::snprintf(buffer, sizeof buffer, "frame_%04zu.obj", t);
  return buffer;
}

std::string group_name(std::size_t p) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "piece_%03zu", p);
  return buffer;
}

// Frame files in frames/: the expected ones present, and the names of any others.
void list_frames(const fs::path& dir, std::size_t count, std::vector<std::string>& missing, std::vector<std::string>& extra) {
  std::set<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("frame_", 0) == 0 && entry.path().extension() == ".obj") names.insert(name);
  }
  for (std::size_t t = 0; t < count; ++t)
    if (!names.erase(frame_name(t))) missing.push_back(frame_name(t));
  extra.assign(names.begin(), names.end());
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size() && i < 5; ++i) out += (i ? ", " : "") + names[i];
  if (names.size() > 5) out += ", ...";
  return out;
}

// The first thing wrong with group g of a frame, or "".
std::string check_group(const MeshSoup& m, std::uint32_t g, const std::vector<std::size_t>& faces, const PieceFile& piece,
                        const std::vector<Tri>& expected, std::uint32_t& next_vertex) {
  if (faces.size() != expected.size())
    return std::to_string(faces.size()) + " triangles, " + piece.name + " has " + std::to_string(expected.size());
  std::uint32_t lo = UINT32_MAX, hi = 0;
  for (std::size_t i : faces)
    for (std::uint32_t v : m.triangles[i]) lo = std::min(lo, v), hi = std::max(hi, v);
  const std::size_t count = faces.empty() ? 0 : hi - lo + 1;
  if (count != piece.mesh.positions.size())
    return std::to_string(count) + " vertices, " + piece.name + " has " + std::to_string(piece.mesh.positions.size());
  if (!faces.empty() && lo != next_vertex)
    return "vertices start at " + std::to_string(lo + 1) + ", expected " + std::to_string(next_vertex + 1) +
           " (each piece on its own consecutive vertices)";
  for (std::size_t k = 0; k < faces.size(); ++k) {
    const Tri& t = m.triangles[faces[k]];
    if (Tri{t[0] - lo, t[1] - lo, t[2] - lo} != expected[k])
      return "triangle " + std::to_string(k) + " differs from " + piece.name;
  }
  next_vertex += std::uint32_t(count);
  return "";
}

void check_frame(const fs::path& path, const std::string& name, const std::vector<PieceFile>& pieces,
                 const std::vector<std::vector<Tri>>& expected, std::vector<std::string>& failures) {
  const MeshSoup m = read_obj(path);
  std::vector<std::vector<std::size_t>> faces(m.groups.size());
  for (std::size_t i = 0; i < m.triangle_group.size(); ++i) faces[m.triangle_group[i]].push_back(i);
  std::uint32_t next_vertex = 0;
  for (std::size_t p = 0; p < pieces.size(); ++p) {
    if (p >= m.groups.size() || m.groups[p] != group_name(p)) {
      const bool anywhere = std::find(m.groups.begin(), m.groups.end(), group_name(p)) != m.groups.end();
      failures.push_back(name + ": " + group_name(p) + (anywhere ? " out of order" : " missing"));
      return;
    }
    if (!pieces[p].present) return;  // already reported by piece_files
    const std::string why = check_group(m, std::uint32_t(p), faces[p], pieces[p], expected[p], next_vertex);
    if (!why.empty()) {
      failures.push_back(name + ": " + group_name(p) + " has " + why);
      return;
    }
  }
  if (m.groups.size() > pieces.size()) failures.push_back(name + ": unexpected group " + m.groups[pieces.size()]);
  else if (next_vertex != m.positions.size())
    failures.push_back(name + ": " + std::to_string(m.positions.size()) + " vertices, the pieces use " + std::to_string(next_vertex));
}

}  // namespace

std::vector<std::array<std::uint32_t, 3>> obj_order(const PieceFile& f, int only_group) {
  std::vector<Tri> out;
  for (std::uint8_t group : {std::uint8_t(0), std::uint8_t(1)})
    for (std::size_t t = 0; t < f.mesh.triangles.size(); ++t)
      if (f.inside[t] == group && (only_group < 0 || only_group == group)) out.push_back(f.mesh.triangles[t]);
  return out;
}

namespace {

constexpr std::size_t kHeader = 32;  // magic, version, frames, pieces, vertices, fps

std::uint32_t u32_of(const std::string& b, std::size_t at) {
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | std::uint8_t(b[at + std::size_t(k)]);
  return v;
}

// positions.bin's header against report.json and the piece files; the first thing wrong, or "".
std::string check_positions_header(const std::string& h, std::uint64_t file_size, const std::vector<PieceFile>& pieces, std::size_t frames) {
  if (h.size() < kHeader || h.compare(0, 8, "FRFRAMES") != 0) return "not a fracref positions file (magic FRFRAMES)";
  if (u32_of(h, 8) != 1) return "version " + std::to_string(u32_of(h, 8)) + ", expected 1";
  if (u32_of(h, 12) != frames) return std::to_string(u32_of(h, 12)) + " frames, report.json has " + std::to_string(frames);
  if (u32_of(h, 16) != pieces.size()) return std::to_string(u32_of(h, 16)) + " pieces, report.json has " + std::to_string(pieces.size());
  const double fps = std::bit_cast<double>(std::uint64_t(u32_of(h, 24)) | std::uint64_t(u32_of(h, 28)) << 32);
  if (!(fps > 0.0) || !std::isfinite(fps)) return "fps is not a positive number";
  std::uint64_t offset = 0;
  for (std::size_t p = 0; p <= pieces.size(); ++p) {
    if (h.size() < kHeader + 4 * (p + 1) || u32_of(h, kHeader + 4 * p) != offset)
      return "piece offset " + std::to_string(p) + " is not " + std::to_string(offset) + " (the vertices of the pieces before it)";
    if (p < pieces.size()) offset += pieces[p].mesh.positions.size();
  }
  if (u32_of(h, 20) != offset) return std::to_string(u32_of(h, 20)) + " vertices, the pieces have " + std::to_string(offset);
  const std::uint64_t want = kHeader + 4 * (pieces.size() + 1) + std::uint64_t(frames) * offset * 12;
  if (file_size != want) return std::to_string(file_size) + " bytes, expected " + std::to_string(want);
  return "";
}

std::vector<glm::dvec3> read_positions(const fs::path& file, std::size_t pieces, std::size_t vertices, std::size_t t) {
  std::ifstream in(file, std::ios::binary);
  std::string bytes(12 * vertices, '\0');
  in.seekg(std::streamoff(kHeader + 4 * (pieces + 1) + 12 * vertices * t));
  in.read(bytes.data(), std::streamsize(bytes.size()));
  if (!in) throw InputError(file.string() + ": frame " + std::to_string(t) + " cannot be read");
  std::vector<glm::dvec3> out(vertices);
  for (std::size_t i = 0; i < 3 * vertices; ++i) out[i / 3][int(i % 3)] = double(std::bit_cast<float>(u32_of(bytes, 4 * i)));
  return out;
}

FrameReader check_positions(const fs::path& out, const std::vector<PieceFile>& pieces, std::size_t frames, CheckReport& report) {
  std::vector<std::string> failures;
  std::vector<std::vector<Tri>> expected;
  for (const PieceFile& p : pieces) expected.push_back(p.present ? obj_order(p) : std::vector<Tri>{});
  if (!fs::exists(out / "frames" / "topology.obj")) failures.push_back("frames/topology.obj: missing (positions.bin needs it)");
  else check_frame(out / "frames" / "topology.obj", "frames/topology.obj", pieces, expected, failures);
  const fs::path file = out / "frames" / "positions.bin";
  std::ifstream in(file, std::ios::binary);
  std::string header(kHeader + 4 * (pieces.size() + 1), '\0');
  in.read(header.data(), std::streamsize(header.size()));
  header.resize(std::size_t(in.gcount()));
  const std::string why = check_positions_header(header, fs::file_size(file), pieces, frames);
  if (!why.empty()) failures.push_back("frames/positions.bin: " + why);
  std::size_t vertices = 0;
  for (const PieceFile& p : pieces) vertices += p.mesh.positions.size();
  for (std::size_t t = 0; t < frames && failures.empty(); ++t)
    for (const glm::dvec3& x : read_positions(file, pieces.size(), vertices, t))
      if (!std::isfinite(x.x) || !std::isfinite(x.y) || !std::isfinite(x.z)) {
        failures.push_back("frames/positions.bin: frame " + std::to_string(t) + " has a position that is not finite");
        break;
      }
  record(report, "frames", failures, "topology.obj and " + std::to_string(frames) + " frames of positions.bin read");
  if (!failures.empty()) return {};
  const std::size_t count = pieces.size();
  return [file, count, vertices](std::size_t t) { return read_positions(file, count, vertices, t); };
}

FrameReader check_obj_frames(const fs::path& out, const std::vector<PieceFile>& pieces, std::size_t frames, CheckReport& report) {
  std::vector<std::string> failures, missing, extra;
  list_frames(out / "frames", frames, missing, extra);
  if (!missing.empty())
    failures.push_back("frames: " + std::to_string(missing.size()) + " of report.json's " + std::to_string(frames) +
                       " frames missing: " + listed(missing));
  if (!extra.empty())
    failures.push_back("frames: " + std::to_string(extra.size()) + " frame files beyond report.json's " +
                       std::to_string(frames) + ": " + listed(extra));
  std::vector<std::vector<Tri>> expected;
  for (const PieceFile& p : pieces) expected.push_back(p.present ? obj_order(p) : std::vector<Tri>{});
  std::size_t checked = 0;
  for (std::size_t t = 0; t < frames; ++t) {
    if (std::find(missing.begin(), missing.end(), frame_name(t)) != missing.end()) continue;
    check_frame(out / "frames" / frame_name(t), "frames/" + frame_name(t), pieces, expected, failures);
    ++checked;
  }
  record(report, "frames", failures, std::to_string(checked) + " of " + std::to_string(frames) + " frames read");
  if (!failures.empty()) return {};
  const fs::path dir = out / "frames";
  return [dir](std::size_t t) { return read_obj(dir / frame_name(t)).positions; };
}

}  // namespace

FrameReader check_frames(const fs::path& out, const std::vector<PieceFile>& pieces, std::size_t frames, CheckReport& report) {
  if (fs::exists(out / "frames" / "positions.bin")) return check_positions(out, pieces, frames, report);
  return check_obj_frames(out, pieces, frames, report);
}

}  // namespace fracref::check_detail
