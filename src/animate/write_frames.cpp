// animate_pieces and frames/: one OBJ per frame, or topology.obj and positions.bin.
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstdio>
#include <fstream>
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


using FrameFn = std::function<std::vector<glm::dvec3>(std::size_t)>;

std::filesystem::path frames_folder(const std::filesystem::path& out) {
  const std::filesystem::path dir = out / "frames";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw RunError(dir.string() + ": cannot create the folder: " + ec.message());
  return dir;
}

std::vector<glm::dvec3> checked_frame(const FrameFn& frame, const PieceLayout& layout, std::size_t t) {
  std::vector<glm::dvec3> x = frame(t);
  if (x.size() != layout.slot_count())
    throw RunError("write_frames: frame " + std::to_string(t) + " has " + std::to_string(x.size()) + " positions, expected " +
                   std::to_string(layout.slot_count()));
  return x;
}

void write_obj_frames(const FrameTemplate& tmpl, const PieceLayout& layout, std::size_t frame_count, double fps,
                      const std::filesystem::path& dir, const FrameFn& frame) {
  // Two frames at a time, side by side: computing and formatting a frame costs more than writing it.
  for (std::size_t t = 0; t < frame_count; t += 2) {
    const std::size_t n = std::min<std::size_t>(2, frame_count - t);
    std::string text[2];
    parallel_chunks(n, n, 2, [&](std::size_t c, std::size_t, std::size_t) {
      text[c] = frame_text(tmpl, layout, checked_frame(frame, layout, t + c), t + c, frame_count, fps);
    });
    for (std::size_t c = 0; c < n; ++c) write_file_atomic(dir / numbered("frame_%04zu.obj", t + c), text[c]);
  }
}

void put_u32(std::string& out, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) out += char((v >> (8 * k)) & 0xFF);
}

// The header of positions.bin (scenes/OUTPUTS.md): magic, version, counts, fps, piece offsets.
std::string positions_header(const PieceLayout& layout, std::size_t frame_count, double fps) {
  std::string out = kPositionsMagic;
  put_u32(out, 1);
  put_u32(out, std::uint32_t(frame_count));
  put_u32(out, std::uint32_t(layout.vertices.size()));
  put_u32(out, std::uint32_t(layout.slot_count()));
  const std::uint64_t bits = std::bit_cast<std::uint64_t>(fps);
  put_u32(out, std::uint32_t(bits)), put_u32(out, std::uint32_t(bits >> 32));
  for (std::uint32_t o : layout.offsets) put_u32(out, o);
  return out;
}

std::string positions_block(const std::vector<glm::dvec3>& x) {
  std::string out;
  out.reserve(12 * x.size());
  for (const glm::dvec3& p : x)
    for (int k = 0; k < 3; ++k) put_u32(out, std::bit_cast<std::uint32_t>(float(p[k])));
  return out;
}

// positions.bin is streamed (it grows with frames x vertices), to a temporary name renamed at the end.
void write_positions(const PieceLayout& layout, std::size_t frame_count, double fps, const std::filesystem::path& file,
                     const FrameFn& frame) {
  const std::filesystem::path tmp = file.string() + ".tmp";
  {
    std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
    os << positions_header(layout, frame_count, fps);
    for (std::size_t t = 0; t < frame_count && os; ++t) os << positions_block(checked_frame(frame, layout, t));
    if (!os.flush()) throw RunError(file.string() + ": cannot be written");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) throw RunError(file.string() + ": cannot be written: " + ec.message());
}

void write_all(const PieceSet& pieces, const PieceLayout& layout, std::size_t frame_count, double fps,
               const std::filesystem::path& out, FramesFormat format, const FrameFn& frame) {
  const animate_detail::LocalFaces faces = animate_detail::local_faces(pieces, layout, "write_frames");
  if (frame_count > UINT32_MAX || layout.slot_count() > UINT32_MAX / 12)
    throw RunError("write_frames: " + std::to_string(frame_count) + " frames of " + std::to_string(layout.slot_count()) +
                   " vertices are too many for the frames files");
  const std::filesystem::path dir = frames_folder(out);
  const FrameTemplate tmpl = frame_template(faces, layout);
  if (format == FramesFormat::kObj) {
    write_obj_frames(tmpl, layout, frame_count, fps, dir, frame);
  } else {
    write_file_atomic(dir / "topology.obj", frame_text(tmpl, layout, checked_frame(frame, layout, 0), 0, frame_count, fps));
    write_positions(layout, frame_count, fps, dir / "positions.bin", frame);
  }
  write_file_atomic(dir / "frames.mtl", animate_detail::material_library("frames"));
}

}  // namespace

namespace animate_detail {

std::string material_library(const std::string& what) {
  return "# fracref " + what + ": exterior (outside) and fracture (inside) faces\n"
         "newmtl outside\nKa 0 0 0\nKd 0.8 0.8 0.8\nKs 0.1 0.1 0.1\nNs 20\nillum 2\n\n"
         "newmtl inside\nKa 0 0 0\nKd 0.85 0.55 0.35\nKs 0.05 0.05 0.05\nNs 10\nillum 2\n";
}

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

void write_frames(const PieceSet& pieces, const AnimationResult& result, const std::filesystem::path& out,
                  FramesFormat format) {
  write_all(pieces, result.layout, result.frames.size(), result.fps, out, format,
            [&](std::size_t t) { return result.frames[t]; });
}

void write_frames(const PieceSet& pieces, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                  const std::filesystem::path& out, FramesFormat format) {
  write_all(pieces, transfer.layout, transfer.frame_count, animation.fps, out, format,
            [&](std::size_t t) { return transfer_frame(transfer, animation, t); });
}

}  // namespace fracref
