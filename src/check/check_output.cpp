// check_output: report.json, the piece files, the piece and partition checks, shared vertices.
#include "check/check_output.hpp"

#include <algorithm>
#include <bit>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include "check/check_internal.hpp"
#include "io/mesh_io.hpp"
#include "util/error.hpp"

namespace fracref {
namespace check_detail {

void record(CheckReport& report, const std::string& name, const std::vector<std::string>& failures,
            const std::string& detail) {
  report.checks.push_back({name, failures.empty() ? CheckStatus::kPassed : CheckStatus::kFailed, detail});
  report.failures.insert(report.failures.end(), failures.begin(), failures.end());
}

void record_skipped(CheckReport& report, const std::string& name, const std::string& why) {
  report.checks.push_back({name, CheckStatus::kSkipped, why});
}

}  // namespace check_detail

namespace {

using namespace check_detail;
namespace fs = std::filesystem;
using Json = nlohmann::json;

std::string piece_stem(std::size_t p) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "piece_%03zu", p);
  return buffer;
}

std::size_t count_key(const Json& j, const char* key, const std::string& file) {
  if (!j.contains(key)) throw InputError(file + ": key '" + key + "' missing (not a fracref report)");
  const Json& v = j[key];
  if (!v.is_number_integer() || v.get<std::int64_t>() < 0)
    throw InputError(file + ": key '" + key + "' is not a non-negative integer");
  return v.get<std::size_t>();
}

Json read_report(const fs::path& out) {
  if (!fs::is_directory(out)) throw InputError(out.string() + ": no such folder");
  const fs::path path = out / "report.json";
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string() + ": missing or unreadable (not a fracref output folder)");
  std::stringstream text;
  text << in.rdbuf();
  Json j;
  try {
    j = Json::parse(text.str());
  } catch (const Json::parse_error& e) {
    throw InputError(path.string() + ": byte " + std::to_string(e.byte) + ": malformed JSON");
  }
  if (!j.is_object()) throw InputError(path.string() + ": not a JSON object");
  return j;
}

// Per polygon of an OBJ already accepted by read_obj, whether it lies under `usemtl inside`.
std::vector<std::uint8_t> obj_polygon_inside(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> out;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string head, name;
    words >> head;
    if (head == "usemtl") inside = (words >> name) && name == "inside";
    if (head == "f") out.push_back(inside ? 1 : 0);
  }
  return out;
}

PieceFile read_piece(const fs::path& out, std::size_t p) {
  PieceFile f;
  const fs::path ply = out / "pieces" / (piece_stem(p) + ".ply"), obj = out / "pieces" / (piece_stem(p) + ".obj");
  f.name = "pieces/" + piece_stem(p) + ".ply";
  if (fs::exists(ply)) {
    f.mesh = read_ply(ply);
    auto column = std::find_if(f.mesh.face_properties.begin(), f.mesh.face_properties.end(),
                               [](const PropertyColumn& c) { return c.name == "inside"; });
    if (column == f.mesh.face_properties.end())
      throw InputError(ply.string() + ": no face property 'inside' (not a fracref piece)");
    for (double v : column->values) {
      if (v != 0.0 && v != 1.0) throw InputError(ply.string() + ": face property 'inside' is not 0 or 1");
      f.inside.push_back(std::uint8_t(v));
    }
  } else if (fs::exists(obj)) {
    f.name = "pieces/" + piece_stem(p) + ".obj";
    f.mesh = read_obj(obj);
    const std::vector<std::uint8_t> polygon = obj_polygon_inside(obj);
    for (std::uint32_t poly : f.mesh.triangle_polygon) f.inside.push_back(poly < polygon.size() ? polygon[poly] : 0);
  } else {
    return f;
  }
  f.present = true;
  return f;
}

// piece_* meshes in pieces/ beyond the report's piece count.
std::vector<std::string> extra_piece_files(const fs::path& out, std::size_t count) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(out / "pieces", ec)) {
    const std::string stem = entry.path().stem().string(), ext = entry.path().extension().string();
    if (stem.rfind("piece_", 0) != 0 || (ext != ".ply" && ext != ".obj")) continue;
    const std::string digits = stem.substr(6);
    const bool numbered = !digits.empty() && std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
    if (!numbered || digits.size() > 9 || std::stoull(digits) >= count || piece_stem(std::stoull(digits)) != stem)
      names.push_back("pieces/" + entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<PieceFile> check_piece_files(const fs::path& out, const Json& report_json, std::size_t count, CheckReport& report) {
  std::vector<PieceFile> files;
  std::vector<std::string> failures;
  std::size_t triangles = 0;
  for (std::size_t p = 0; p < count; ++p) {
    files.push_back(read_piece(out, p));
    const PieceFile& f = files.back();
    if (!f.present) {
      failures.push_back(f.name + ": missing");
      continue;
    }
    triangles += f.mesh.triangles.size();
    const Json* meshes = report_json.contains("piece_meshes") ? &report_json["piece_meshes"] : nullptr;
    if (meshes && meshes->is_array() && p < meshes->size() && (*meshes)[p].contains("triangles") &&
        (*meshes)[p]["triangles"] != Json(f.mesh.triangles.size()))
      failures.push_back(f.name + ": " + std::to_string(f.mesh.triangles.size()) + " triangles, report.json says " +
                         (*meshes)[p]["triangles"].dump());
  }
  for (const std::string& name : extra_piece_files(out, count))
    failures.push_back(name + ": not one of the report's " + std::to_string(count) + " pieces");
  record(report, "piece_files", failures, std::to_string(count) + " pieces, " + std::to_string(triangles) + " triangles");
  return files;
}

// The files as one PieceSet (vertices kept apart per piece), for check_pieces.
PieceSet as_piece_set(const std::vector<PieceFile>& files) {
  PieceSet set;
  for (const PieceFile& f : files) {
    const std::uint32_t base = std::uint32_t(set.positions.size());
    set.positions.insert(set.positions.end(), f.mesh.positions.begin(), f.mesh.positions.end());
    PieceSet::Piece piece;
    for (const auto& t : f.mesh.triangles) piece.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
    piece.inside = f.inside;
    set.pieces.push_back(std::move(piece));
  }
  return set;
}

void check_meshes(const fs::path& out, const std::vector<PieceFile>& files, const CheckOptions& options, CheckReport& report) {
  if (std::none_of(files.begin(), files.end(), [](const PieceFile& f) { return f.present && !f.mesh.triangles.empty(); })) {
    record(report, "piece_meshes", {"pieces: no piece file with triangles to check"}, "");
    record_skipped(report, "partition", "no piece to check");
    return;
  }
  const fs::path exterior_path = out / "exterior.ply";
  const bool have_exterior = fs::exists(exterior_path);
  PieceSet set = as_piece_set(files);
  MeshSoup exterior;
  PieceCheckOptions po = options.pieces;
  if (have_exterior) {
    exterior = read_mesh(exterior_path);
  } else {  // still check each piece; the partition lines are dropped
    for (const auto& piece : set.pieces) exterior.triangles.insert(exterior.triangles.end(), piece.triangles.begin(), piece.triangles.end());
    exterior.positions = set.positions;
    po.sample_points = 0;
  }
  const PieceReport checked = check_pieces(set, exterior, po);
  std::vector<std::string> piece_failures, partition_failures;
  for (const std::string& line : checked.failures) {
    if (line.rfind("pieces: ", 0) == 0) {
      partition_failures.push_back("exterior.ply: " + line.substr(8));
      continue;
    }
    const std::size_t colon = line.find(": ");
    const std::size_t p = std::stoull(line.substr(6, colon - 6));  // "piece N: why"
    if (p < files.size() && files[p].present) piece_failures.push_back(files[p].name + line.substr(colon));
  }
  std::size_t closed = 0;
  for (const PieceCheck& c : checked.pieces) closed += c.closed() && c.edge_manifold() && c.outward() && c.self_intersections == 0;
  record(report, "piece_meshes", piece_failures, std::to_string(closed) + " of " + std::to_string(files.size()) + " pieces closed, manifold, outward, free of self-intersections");
  if (!have_exterior) {
    record(report, "partition", {"exterior.ply: missing"}, "no exterior to compare with");
    return;
  }
  char detail[160];
  std::snprintf(detail, sizeof detail, "volume error %.3g, %zu points: %zu in no piece, %zu in several",
                checked.volume_relative_error, checked.points_tested, checked.points_in_no_piece, checked.points_in_several_pieces);
  record(report, "partition", partition_failures, detail);
}

using PositionKey = std::array<std::uint64_t, 3>;

PositionKey key_of(const glm::dvec3& p) {
  return {std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y), std::bit_cast<std::uint64_t>(p.z)};
}

// Per piece, the vertices of its fracture faces, ascending.
std::vector<std::uint32_t> fracture_vertices(const PieceFile& f) {
  std::vector<std::uint32_t> out;
  for (std::size_t t = 0; t < f.mesh.triangles.size(); ++t)
    if (f.inside[t]) out.insert(out.end(), f.mesh.triangles[t].begin(), f.mesh.triangles[t].end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string position_text(const glm::dvec3& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.17g, %.17g, %.17g)", p.x, p.y, p.z);
  return buffer;
}

void check_shared(const std::vector<PieceFile>& files, CheckReport& report) {
  struct Seen {
    int first = -1;
    bool shared = false;
  };
  std::map<PositionKey, Seen> seen;
  std::vector<std::vector<std::uint32_t>> vertices;
  for (std::size_t p = 0; p < files.size(); ++p) {
    vertices.push_back(files[p].present ? fracture_vertices(files[p]) : std::vector<std::uint32_t>{});
    for (std::uint32_t v : vertices.back()) {
      Seen& s = seen[key_of(files[p].mesh.positions[v])];
      if (s.first < 0) s.first = int(p);
      else if (s.first != int(p)) s.shared = true;
    }
  }
  std::vector<std::string> failures;
  std::size_t total = 0;
  for (std::size_t p = 0; p < files.size(); ++p) {
    std::size_t lonely = 0;
    std::uint32_t example = 0;
    for (std::uint32_t v : vertices[p])
      if (!seen[key_of(files[p].mesh.positions[v])].shared && lonely++ == 0) example = v;
    total += vertices[p].size();
    if (lonely)
      failures.push_back(files[p].name + ": " + std::to_string(lonely) + " of " + std::to_string(vertices[p].size()) +
                         " fracture vertices are not shared bit for bit with another piece, e.g. vertex " +
                         std::to_string(example) + " at " + position_text(files[p].mesh.positions[example]));
  }
  record(report, "shared_vertices", failures, std::to_string(total) + " fracture vertex uses");
}

}  // namespace

const char* check_status_name(CheckStatus status) {
  switch (status) {
    case CheckStatus::kPassed: return "passed";
    case CheckStatus::kFailed: return "failed";
    case CheckStatus::kSkipped: return "skipped";
  }
  return "?";
}

CheckReport check_output(const fs::path& out, const CheckOptions& options) {
  const Json report_json = read_report(out);
  const std::string report_file = (out / "report.json").string();
  CheckReport report;
  report.pieces = count_key(report_json, "pieces", report_file);
  report.frames = count_key(report_json, "frames", report_file);
  record(report, "report", {}, std::to_string(report.pieces) + " pieces, " + std::to_string(report.frames) + " frames");
  if (!report_json.contains("piece_meshes") && !fs::exists(out / "pieces")) {
    for (const char* name : {"piece_files", "piece_meshes", "partition", "shared_vertices", "frames", "glb", "glb_frames"})
      record_skipped(report, name, "no pieces in this output (the run stopped before the pieces stage)");
    return report;
  }
  const std::vector<PieceFile> files = check_piece_files(out, report_json, report.pieces, report);
  check_meshes(out, files, options, report);
  check_shared(files, report);
  FrameReader frame;
  if (fs::exists(out / "frames")) frame = check_frames(out, files, report.frames, report);
  else record_skipped(report, "frames", "no frames/ folder (the run did not animate, or the scene's output.frames is false)");
  if (fs::exists(out / "animation.glb")) {
    check_glb(out, files, report.frames, frame, report);
  } else {
    record_skipped(report, "glb", "no animation.glb (the run did not animate, or the scene's output.glb is false)");
    record_skipped(report, "glb_frames", "no animation.glb");
  }
  return report;
}

nlohmann::ordered_json check_report_json(const CheckReport& report) {
  nlohmann::ordered_json j;
  j["ok"] = report.ok();
  j["pieces"] = report.pieces;
  j["frames"] = report.frames;
  j["checks"] = nlohmann::ordered_json::array();
  for (const CheckResult& c : report.checks)
    j["checks"].push_back({{"name", c.name}, {"status", check_status_name(c.status)}, {"detail", c.detail}});
  j["failures"] = report.failures;
  return j;
}

}  // namespace fracref
