// Per-frame vertex positions, the parent map and backward remeshing.
#include <cctype>
#include <cmath>
#include <exception>
#include <optional>
#include <string>

#include "coarse/animation.hpp"
#include "coarse/coarse_internal.hpp"
#include "io/mesh_io.hpp"
#include "util/parallel.hpp"

namespace fracref {
namespace {
using namespace coarse_detail;
namespace fs = std::filesystem;

constexpr int kReadThreads = 2;  // frame files read side by side (the frames do not depend on it)

struct FrameField {
  std::size_t begin = 0, end = 0;
  int width = 0;
};

// The same rule as the scene schema: one {} or {:0N} field, N in 1..12, no other brace.
std::optional<FrameField> find_frame_field(const std::string& s) {
  const std::size_t open = s.find('{'), close = s.find('}');
  if (open == std::string::npos || close == std::string::npos || close < open) return std::nullopt;
  if (s.find_first_of("{}", close + 1) != std::string::npos || s.find('{', open + 1) < close) return std::nullopt;
  const std::string spec = s.substr(open + 1, close - open - 1);
  FrameField f{open, close + 1, 0};
  if (spec.empty()) return f;
  if (spec.size() < 3 || spec.size() > 4 || spec[0] != ':' || spec[1] != '0') return std::nullopt;
  for (std::size_t i = 2; i < spec.size(); ++i)
    if (!std::isdigit(static_cast<unsigned char>(spec[i]))) return std::nullopt;
  f.width = std::stoi(spec.substr(2));
  if (f.width < 1 || f.width > 12) return std::nullopt;
  return f;
}

bool is_mesh_file(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".obj" || ext == ".off" || ext == ".ply";
}

// Positions of one frame; at most `limit` vertices (more is an error naming the line).
std::vector<glm::dvec3> read_frame(const fs::path& path, std::size_t limit, std::size_t& last_line) {
  if (is_mesh_file(path)) {
    MeshSoup soup = read_mesh(path);
    if (soup.positions.size() > limit)
      throw InputError(path.string() + ": the frame has " + std::to_string(soup.positions.size()) +
                       " vertices, more than the model's " + std::to_string(limit));
    last_line = 0;
    return std::move(soup.positions);
  }
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(path.string(), text);
  std::vector<glm::dvec3> points;
  while (in.next()) {
    if (points.size() == limit)
      throw in.error("the frame has more vertices than the model's " + std::to_string(limit));
    in.expect_tokens(3, "vertex", "x y z");
    const auto& t = in.tokens();
    points.emplace_back(in.real(t[0], "coordinate"), in.real(t[1], "coordinate"), in.real(t[2], "coordinate"));
    last_line = in.line();
  }
  last_line = in.line();
  return points;
}

struct ParentMap {
  std::string file;
  std::vector<std::int64_t> parent;  // -1: none
  std::vector<std::size_t> line;
};

void check_acyclic(const ParentMap& map) {
  std::vector<std::uint8_t> state(map.parent.size(), 0);  // 0 new, 1 on the current walk, 2 done
  for (std::size_t v = 0; v < map.parent.size(); ++v) {
    std::int64_t u = std::int64_t(v);
    while (u >= 0 && state[u] == 0) state[u] = 1, u = map.parent[u];
    if (u >= 0 && state[u] == 1)
      throw input_error_at(map.file, map.line[u], "the parent map has a cycle through vertex " + std::to_string(u));
    for (u = std::int64_t(v); u >= 0 && state[u] == 1; u = map.parent[u]) state[u] = 2;
  }
}

ParentMap read_parent_map(const fs::path& path, std::size_t n) {
  ParentMap map{path.string(), std::vector<std::int64_t>(n, -1), std::vector<std::size_t>(n, 0)};
  const std::string text = io_detail::read_whole_file(path);
  TokenLines in(map.file, text);
  while (in.next()) {
    in.expect_tokens(2, "parent map entry", "v parent");
    const std::int64_t v = in.integer(in.tokens()[0], "vertex"), p = in.integer(in.tokens()[1], "parent");
    for (std::int64_t id : {v, p})
      if (id < 0 || id >= std::int64_t(n))
        throw in.error((id == v ? "vertex " : "parent ") + std::to_string(id) + " is out of range (the model has " +
                       std::to_string(n) + " vertices; ids start at 0)");
    if (v == p) throw in.error("vertex " + std::to_string(v) + " is its own parent");
    if (map.parent[v] >= 0)
      throw in.error("vertex " + std::to_string(v) + " already has a parent (line " + std::to_string(map.line[v]) + ")");
    map.parent[v] = p;
    map.line[v] = in.line();
  }
  check_acyclic(map);
  return map;
}

// Each parent must exist in the first frame that has its child.
void check_parents_exist(const ParentMap& map, const std::vector<std::size_t>& counts, const std::vector<fs::path>& files) {
  for (std::size_t v = 0; v < map.parent.size(); ++v) {
    if (map.parent[v] < 0 || v < counts.front()) continue;
    std::size_t k = 0;
    while (counts[k] <= v) ++k;
    if (map.parent[v] >= std::int64_t(counts[k]))
      throw input_error_at(map.file, map.line[v], "parent " + std::to_string(map.parent[v]) + " of vertex " + std::to_string(v) +
                                                      " is not in " + files[k].string() + " (" + std::to_string(counts[k]) +
                                                      " vertices), the first frame that has vertex " + std::to_string(v));
  }
}

// Gives vertices n..N-1 of a frame the position of their ancestor below n.
void fill_missing(std::vector<glm::dvec3>& frame, std::size_t n, const ParentMap& map, const fs::path& file) {
  const std::size_t total = map.parent.size();
  std::vector<std::int64_t> ancestor(total, -1);
  for (std::size_t v = 0; v < n; ++v) ancestor[v] = std::int64_t(v);
  frame.resize(total);
  for (std::size_t v = n; v < total; ++v) {
    std::vector<std::size_t> chain;
    std::size_t u = v;
    while (ancestor[u] < 0) {
      if (map.parent[u] < 0)
        throw InputError(file.string() + ": vertex " + std::to_string(u) + " is missing (the frame has " + std::to_string(n) +
                         " vertices) and " + map.file + " gives it no parent");
      chain.push_back(u);
      u = std::size_t(map.parent[u]);
    }
    for (std::size_t w : chain) ancestor[w] = ancestor[u];
    frame[v] = frame[std::size_t(ancestor[v])];
  }
}

}  // namespace

fs::path frame_file(const fs::path& pattern, std::int64_t frame) {
  const std::string s = pattern.string();
  const std::optional<FrameField> f = find_frame_field(s);
  if (!f)
    throw InputError(s + ": a frame pattern needs exactly one '{}' or '{:0N}' field (N in 1..12) and no other brace");
  const std::string digits = std::to_string(frame < 0 ? -frame : frame);
  const std::size_t pad = digits.size() < std::size_t(f->width) ? std::size_t(f->width) - digits.size() : 0;
  std::string out = s.substr(0, f->begin);
  if (frame < 0) out.push_back('-');
  out.append(pad, '0');
  out.append(digits);
  out.append(s, f->end, std::string::npos);
  return out;
}

CoarseAnimation load_frames(const fs::path& pattern, std::int64_t first, std::int64_t count, double fps,
                            const fs::path& parent_map_path, const CoarseModel& model) {
  const std::string where = pattern.string();
  if (count < 1) throw InputError(where + ": frame count " + std::to_string(count) + " must be at least 1");
  if (first < 0) throw InputError(where + ": first frame " + std::to_string(first) + " is negative");
  if (!(fps > 0) || !std::isfinite(fps)) throw InputError(where + ": fps must be a positive number");
  const std::size_t n = model.vertices.size();
  const bool remesh = !parent_map_path.empty();
  CoarseAnimation anim;
  anim.fps = fps;
  // The files are read and parsed side by side, then checked in order: a frame's read error is
  // reported at its turn, so the first error is the one a frame-by-frame read would meet.
  std::vector<fs::path> files;
  for (std::int64_t i = 0; i < count; ++i) files.push_back(frame_file(pattern, first + i));
  std::vector<std::vector<glm::dvec3>> read(files.size());
  std::vector<std::size_t> last_lines(files.size(), 0);
  std::vector<std::exception_ptr> errors(files.size());
  parallel_chunks(files.size(), files.size(), kReadThreads, [&](std::size_t i, std::size_t, std::size_t) {
    try {
      read[i] = read_frame(files[i], n, last_lines[i]);
    } catch (...) {
      errors[i] = std::current_exception();
    }
  });
  for (std::size_t i = 0; i < files.size(); ++i) {
    if (errors[i]) std::rethrow_exception(errors[i]);
    const std::size_t last_line = last_lines[i];
    anim.frames.push_back(std::move(read[i]));
    const std::size_t got = anim.frames.back().size();
    std::string at = files[i].string();
    if (last_line) at.append(1, ':').append(std::to_string(last_line));
    at += ": ";
    const bool last = i + 1 == files.size();
    if (got != n && (!remesh || last))
      throw InputError(at + "the frame has " + std::to_string(got) + " vertices, the model has " + std::to_string(n) +
                       (remesh ? " (the last frame must have the model's topology)" : " (no parent map is given)"));
    if (got == 0) throw InputError(at + "the frame has no vertex");
    if (i > 0 && got < anim.file_vertex_counts.back())
      throw InputError(at + "the frame has " + std::to_string(got) + " vertices, fewer than the " +
                       std::to_string(anim.file_vertex_counts.back()) + " of " + files[i - 1].string() +
                       " (backward remeshing only adds vertices)");
    anim.file_vertex_counts.push_back(got);
  }
  if (!remesh) return anim;
  const ParentMap map = read_parent_map(parent_map_path, n);
  check_parents_exist(map, anim.file_vertex_counts, files);
  for (std::size_t i = 0; i < anim.frames.size(); ++i)
    if (anim.file_vertex_counts[i] < n) fill_missing(anim.frames[i], anim.file_vertex_counts[i], map, files[i]);
  return anim;
}

}  // namespace fracref
