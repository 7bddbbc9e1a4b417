// animate_pieces and the per-frame OBJ files.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <functional>

#include "animate/animate.hpp"
#include "animate/animate_internal.hpp"
#include "util/parallel.hpp"
#include "util/atomic_output.hpp"
#include "util/error.hpp"

namespace fracref {
namespace {

using animate_detail::Tri;

std::string numbered(const char* format, std::size_t n) {
  char buffer[48];
  std::snprintf(buffer, sizeof buffer, format, n);
  return buffer;
}

void append_number(std::string& out, double value) {
  char buffer[32];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

void append_number(std::string& out, std::uint32_t value) {
  char buffer[16];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  out.append(buffer, result.ptr);
}

// Per piece, its "o" line and its faces' lines: the topology is the same in every frame, so
// they are formatted once and only the vertex lines are formatted per frame.
struct FrameTemplate {
  std::vector<std::string> heads, faces;
};

FrameTemplate frame_template(const animate_detail::LocalFaces& f, const PieceLayout& layout) {
  FrameTemplate out;
  for (std::size_t p = 0; p < f.faces.size(); ++p) {
    out.heads.push_back("o " + numbered("piece_%03zu", p) + "\n");
    std::string& text = out.faces.emplace_back();
    int material = -1;
    const std::uint32_t base = layout.offsets[p] + 1;  // OBJ ids are 1-based and global to the file
    for (std::size_t t = 0; t < f.faces[p].size(); ++t) {
      if (f.inside[p][t] != material) {
        material = f.inside[p][t];
        text += material ? "usemtl inside\n" : "usemtl outside\n";
      }
      const Tri& tri = f.faces[p][t];
      text += 'f';
      for (int k = 0; k < 3; ++k) text += ' ', append_number(text, tri[k] + base);
      text += '\n';
    }
  }
  return out;
}

std::string frame_text(const FrameTemplate& tmpl, const PieceLayout& layout, const std::vector<glm::dvec3>& x,
                       std::size_t frame, std::size_t frame_count, double fps) {
  std::string out = "# fracref frame " + std::to_string(frame) + " of " + std::to_string(frame_count) + ", fps ";
  append_number(out, fps);
  out += "\nmtllib frames.mtl\n";
  std::size_t size = out.size() + 64 * x.size();
  for (std::size_t p = 0; p < tmpl.faces.size(); ++p) size += tmpl.heads[p].size() + tmpl.faces[p].size();
  out.reserve(size);
  for (std::size_t p = 0; p < tmpl.faces.size(); ++p) {
    out += tmpl.heads[p];
    for (std::uint32_t s = layout.offsets[p]; s < layout.offsets[p + 1]; ++s) {
      out += 'v';
      for (int k = 0; k < 3; ++k) out += ' ', append_number(out, x[s][k]);
      out += '\n';
    }
    out += tmpl.faces[p];
  }
  return out;
}

const char* material_text() {
  return "# fracref frames: exterior (outside) and fracture (inside) faces\n"
         "newmtl outside\nKa 0 0 0\nKd 0.8 0.8 0.8\nKs 0.1 0.1 0.1\nNs 20\nillum 2\n\n"
         "newmtl inside\nKa 0 0 0\nKd 0.85 0.55 0.35\nKs 0.05 0.05 0.05\nNs 10\nillum 2\n";
}

void write_all(const PieceSet& pieces, const PieceLayout& layout, std::size_t frame_count, double fps,
               const std::filesystem::path& out, const std::function<std::vector<glm::dvec3>(std::size_t)>& frame) {
  const animate_detail::LocalFaces faces = animate_detail::local_faces(pieces, layout, "write_frames");
  const std::filesystem::path dir = out / "frames";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw RunError(dir.string() + ": cannot create the folder: " + ec.message());
  const FrameTemplate tmpl = frame_template(faces, layout);
  auto text_of = [&](std::size_t t) {
    const std::vector<glm::dvec3> x = frame(t);
    if (x.size() != layout.slot_count())
      throw RunError("write_frames: frame " + std::to_string(t) + " has " + std::to_string(x.size()) + " positions, expected " +
                     std::to_string(layout.slot_count()));
    return frame_text(tmpl, layout, x, t, frame_count, fps);
  };
  // Two frames at a time, side by side: computing and formatting a frame costs more than writing it.
  for (std::size_t t = 0; t < frame_count; t += 2) {
    const std::size_t n = std::min<std::size_t>(2, frame_count - t);
    std::string text[2];
    parallel_chunks(n, n, 2, [&](std::size_t c, std::size_t, std::size_t) { text[c] = text_of(t + c); });
    for (std::size_t c = 0; c < n; ++c) write_file_atomic(dir / numbered("frame_%04zu.obj", t + c), text[c]);
  }
  write_file_atomic(dir / "frames.mtl", material_text());
}

}  // namespace

namespace animate_detail {

LocalFaces local_faces(const PieceSet& pieces, const PieceLayout& layout, const char* what) {
  if (layout.vertices.size() != pieces.pieces.size())
    throw RunError(std::string(what) + ": the animation has " + std::to_string(layout.vertices.size()) +
                   " pieces, the piece set " + std::to_string(pieces.pieces.size()));
  LocalFaces out;
  for (std::size_t p = 0; p < pieces.pieces.size(); ++p) {
    const PieceSet::Piece& piece = pieces.pieces[p];
    const std::vector<std::uint32_t>& used = layout.vertices[p];
    out.faces.emplace_back();
    out.inside.emplace_back();
    for (std::uint8_t group : {std::uint8_t(0), std::uint8_t(1)})
      for (std::size_t t = 0; t < piece.triangles.size(); ++t) {
        if (piece.inside[t] != group) continue;
        Tri local;
        for (int k = 0; k < 3; ++k) {
          auto it = std::lower_bound(used.begin(), used.end(), piece.triangles[t][k]);
          if (it == used.end() || *it != piece.triangles[t][k])
            throw RunError(std::string(what) + ": piece " + std::to_string(p) + " uses a vertex the animation does not move");
          local[k] = std::uint32_t(it - used.begin());
        }
        out.faces.back().push_back(local);
        out.inside.back().push_back(group);
      }
  }
  return out;
}

}  // namespace animate_detail

AnimationResult animate_pieces(const CoarseModel& model, const CoarseAnimation& animation, const RefinementTree& tree,
                               const PieceSet& pieces, const AnimateOptions& options) {
  const AnimationTransfer transfer = build_transfer(model, animation, tree, pieces, options);
  AnimationResult result;
  result.layout = transfer.layout;
  result.coarse_fracture_frame = transfer.coarse_fracture_frame;
  result.fps = animation.fps;
  for (std::size_t t = 0; t < transfer.frame_count; ++t) result.frames.push_back(transfer_frame(transfer, animation, t));
  return result;
}

void write_frames(const PieceSet& pieces, const AnimationResult& result, const std::filesystem::path& out) {
  write_all(pieces, result.layout, result.frames.size(), result.fps, out, [&](std::size_t t) { return result.frames[t]; });
}

void write_frames(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                  const std::filesystem::path& out) {
  write_all(pieces, transfer.layout, transfer.frame_count, animation.fps, out,
            [&](std::size_t t) { return transfer_frame(transfer, animation, t); });
}

}  // namespace fracref
