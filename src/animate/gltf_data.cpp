// animation.glb's binary data (accessors, sparse morph targets) and its motion analysis: which
// pieces move rigidly, and their node poses (see gltf_writer.hpp).
#include <algorithm>
#include <bit>
#include <cmath>

#include "animate/gltf_internal.hpp"
#include "animate/rigid_fit.hpp"
#include "util/error.hpp"
#include "util/parallel.hpp"

namespace fracref::gltf_detail {

std::size_t Glb::add(Accessor a, std::size_t begin, int target) {
  if (begin != std::string::npos) a.view = add_view(begin, target);
  accessors.push_back(std::move(a));
  return accessors.size() - 1;
}

int Glb::add_view(std::size_t begin, int target) {
  views.push_back({begin, bin.size() - begin, target});
  return int(views.size() - 1);
}

void put_u32(std::string& bin, std::uint32_t v) {
  const char bytes[4] = {char(v & 0xFF), char((v >> 8) & 0xFF), char((v >> 16) & 0xFF), char((v >> 24) & 0xFF)};
  bin.append(bytes, 4);
}

void put_f32(std::string& bin, float v) { put_u32(bin, std::bit_cast<std::uint32_t>(v)); }

namespace {

void bound(Accessor& a, const std::vector<float>& values, int width) {
  a.min.assign(std::size_t(width), std::numeric_limits<float>::infinity());
  a.max.assign(std::size_t(width), -std::numeric_limits<float>::infinity());
  for (std::size_t i = 0; i < values.size(); ++i) {
    a.min[i % std::size_t(width)] = std::min(a.min[i % std::size_t(width)], values[i]);
    a.max[i % std::size_t(width)] = std::max(a.max[i % std::size_t(width)], values[i]);
  }
}

// The pose of frame f written in float, and whether it moves every vertex within `tolerance`.
bool fit_frame(const std::vector<glm::dvec3>& rest, const glm::dvec3* moved, const glm::dvec3& pivot,
               const glm::dquat& near, double tolerance, glm::vec3& t, glm::vec4& q) {
  const RigidPose pose = fit_rigid(rest.data(), moved, rest.size(), pivot, near);
  t = glm::vec3(pose.translation);
  q = glm::vec4(float(pose.rotation.x), float(pose.rotation.y), float(pose.rotation.z), float(pose.rotation.w));
  const glm::dmat3 r = glm::mat3_cast(glm::dquat(double(q.w), double(q.x), double(q.y), double(q.z)));
  for (std::size_t i = 0; i < rest.size(); ++i) {
    const glm::dvec3 local(glm::vec3(rest[i] - pivot));
    if (!(glm::length(r * local + glm::dvec3(t) - moved[i]) <= tolerance)) return false;
  }
  return true;
}

void fit_all(std::vector<PieceMotion>& motion, const std::vector<std::vector<glm::dvec3>>& rest, const PieceLayout& layout,
             const std::vector<glm::dvec3>& x, std::size_t f, double tolerance) {
  for (std::size_t p = 0; p < motion.size(); ++p) {
    PieceMotion& m = motion[p];
    if (!m.rigid) continue;
    const glm::vec4 last = f > 0 ? m.rotation[f - 1] : glm::vec4(0, 0, 0, 1);
    const glm::dquat near(double(last.w), double(last.x), double(last.y), double(last.z));
    m.rigid = fit_frame(rest[p], x.data() + layout.offsets[p], m.pivot, near, tolerance, m.translation[f], m.rotation[f]);
  }
}

}  // namespace

std::size_t add_floats(Glb& g, const std::vector<float>& values, int width, const char* type, bool bounds, int target) {
  Accessor a;
  a.count = values.size() / std::size_t(width);
  a.type = type;
  if (bounds) bound(a, values, width);
  const std::size_t begin = g.bin.size();
  for (float v : values) put_f32(g.bin, v);
  return g.add(std::move(a), begin, target);
}

std::size_t add_target(Glb& g, const std::vector<float>& xyz) {
  const std::size_t count = xyz.size() / 3;
  std::vector<std::uint32_t> moving;
  for (std::size_t i = 0; i < count; ++i)
    if (xyz[3 * i] != 0.0f || xyz[3 * i + 1] != 0.0f || xyz[3 * i + 2] != 0.0f) moving.push_back(std::uint32_t(i));
  if (16 * moving.size() >= 12 * count) return add_floats(g, xyz, 3, "VEC3", true, kArrayBuffer);
  Accessor a;
  a.count = count;
  a.type = "VEC3";
  std::vector<float> values;
  for (std::uint32_t i : moving) values.insert(values.end(), {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  if (moving.size() < count) values.insert(values.end(), {0.0f, 0.0f, 0.0f});  // the bounds include the zeros
  bound(a, values, 3);
  if (moving.empty()) return g.add(std::move(a), std::string::npos, 0);
  a.sparse_count = moving.size();
  std::size_t begin = g.bin.size();
  for (std::uint32_t i : moving) put_u32(g.bin, i);
  a.sparse_indices = g.add_view(begin, 0);
  begin = g.bin.size();
  for (std::size_t k = 0; k < 3 * moving.size(); ++k) put_f32(g.bin, values[k]);
  a.sparse_values = g.add_view(begin, 0);
  return g.add(std::move(a), std::string::npos, 0);
}

std::vector<glm::dvec3> frame_positions(const FrameSource& src, std::size_t f) {
  std::vector<glm::dvec3> x = src.frame(f);
  if (x.size() != src.layout.slot_count())
    throw RunError("animation.glb: frame " + std::to_string(f) + " has " + std::to_string(x.size()) +
                   " positions, expected " + std::to_string(src.layout.slot_count()));
  for (std::size_t s = 0; s < x.size(); ++s)
    if (!std::isfinite(x[s].x) || !std::isfinite(x[s].y) || !std::isfinite(x[s].z))
      throw RunError("animation.glb: frame " + std::to_string(f) + ": position " + std::to_string(s) + " is not finite");
  return x;
}

std::vector<PieceMotion> analyse_motion(const FrameSource& src, const std::vector<std::vector<glm::dvec3>>& rest,
                                        double tolerance) {
  std::vector<PieceMotion> motion(rest.size());
  for (std::size_t p = 0; p < rest.size(); ++p) {
    motion[p].rigid = !rest[p].empty();
    for (const glm::dvec3& x : rest[p]) motion[p].pivot += x / double(rest[p].size());
    motion[p].translation.resize(src.count);
    motion[p].rotation.resize(src.count);
  }
  // Frames are evaluated two at a time, side by side; the fits run in frame order (each starts
  // from the previous frame's quaternion).
  auto any_rigid = [&] { return std::any_of(motion.begin(), motion.end(), [](const PieceMotion& m) { return m.rigid; }); };
  for (std::size_t f = 0; f < src.count && any_rigid(); f += 2) {
    const std::size_t n = std::min<std::size_t>(2, src.count - f);
    std::vector<glm::dvec3> x[2];
    parallel_chunks(n, n, 2, [&](std::size_t c, std::size_t, std::size_t) { x[c] = frame_positions(src, f + c); });
    for (std::size_t c = 0; c < n; ++c) fit_all(motion, rest, src.layout, x[c], f + c, tolerance);
  }
  return motion;
}

}  // namespace fracref::gltf_detail
