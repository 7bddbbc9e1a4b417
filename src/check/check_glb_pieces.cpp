// The glb check, per piece: nodes, meshes, primitives (split rim vertices, normals, material
// coordinates), the animation's channels, and the glb's positions at each key against frames/.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <glm/gtc/quaternion.hpp>

#include "check/check_glb_internal.hpp"

namespace fracref::check_detail {
namespace {

using Json = nlohmann::json;
using Tri = std::array<std::uint32_t, 3>;

std::string piece_name(std::size_t p) {
  char name[32];
  std::snprintf(name, sizeof name, "piece_%03zu", p);
  return name;
}

// What the writer's layout gives for a piece file: n vertices, then a copy per rim vertex.
struct Expected {
  std::size_t n = 0;
  std::vector<std::uint32_t> rim;
  std::vector<Tri> outside, inside;
  std::uint32_t original(std::size_t i) const { return i < n ? std::uint32_t(i) : rim[i - n]; }
  std::size_t count() const { return n + rim.size(); }
};

Expected expected_of(const PieceFile& f) {
  Expected e;
  e.n = f.mesh.positions.size();
  e.outside = obj_order(f, 0);
  e.inside = obj_order(f, 1);
  std::vector<std::uint8_t> uses(e.n, 0);
  for (const Tri& t : e.outside) for (std::uint32_t v : t) uses[v] |= 1;
  for (const Tri& t : e.inside) for (std::uint32_t v : t) uses[v] |= 2;
  std::map<std::uint32_t, std::uint32_t> copy;
  for (std::uint32_t v = 0; v < e.n; ++v)
    if (uses[v] == 3) copy[v] = std::uint32_t(e.n + e.rim.size()), e.rim.push_back(v);
  for (Tri& t : e.inside)
    for (std::uint32_t& v : t) v = copy.count(v) ? copy[v] : v;
  return e;
}

double diagonal_of(const std::vector<PieceFile>& pieces) {
  glm::dvec3 lo(1e300), hi(-1e300);
  for (const PieceFile& f : pieces)
    for (const glm::dvec3& x : f.mesh.positions) lo = glm::min(lo, x), hi = glm::max(hi, x);
  return hi.x >= lo.x ? glm::length(hi - lo) : 0.0;
}

// The index of a float attribute with one element per mesh vertex.
std::size_t attribute(const GlbFile& g, const Json& prim, const char* name, const char* type, std::size_t count,
                      const std::string& where) {
  const std::string at = where + ".attributes." + name;
  if (!prim.contains("attributes") || !prim["attributes"].contains(name)) throw Problem(where + ": no " + name);
  const std::size_t index = index_at(prim["attributes"], name, where + ".attributes", g.acc.size());
  const AccessorInfo& a = g.acc[index];
  if (a.component != 5126 || a.type != type) throw Problem(at + " is not float " + type);
  if (a.count != count) throw Problem(at + ": " + std::to_string(a.count) + " vertices, expected " + std::to_string(count) + " (the piece's and its rim copies)");
  return index;
}

std::vector<Tri> read_triangles(const GlbFile& g, const AccessorInfo& a, std::size_t vertices, const std::string& where) {
  if (a.component != 5125 || a.type != "SCALAR" || !a.has_view || a.count % 3)
    throw Problem(where + ": indices are not uint32 triangles in a buffer view");
  std::vector<Tri> out(a.count / 3);
  for (std::size_t i = 0; i < a.count; ++i) {
    const std::uint32_t v = u32_at(g.bin, a.offset + 4 * i);
    if (v >= vertices) throw Problem(where + ": index " + std::to_string(v) + " out of range (" + std::to_string(vertices) + " vertices)");
    out[i / 3][i % 3] = v;
  }
  return out;
}

void check_vertex_data(const GlbFile& g, const Json& prim, const PieceFile& f, const Expected& e, double tolerance, const std::string& where) {
  if (!g.acc[attribute(g, prim, "POSITION", "VEC3", e.count(), where)].has_bounds)
    throw Problem(where + ": POSITION accessor without min and max (glTF requires them)");
  const std::vector<double> n = float_values(g, attribute(g, prim, "NORMAL", "VEC3", e.count(), where), 3, where + ".NORMAL");
  for (std::size_t i = 0; i < e.count(); ++i)
    if (!(std::abs(glm::length(glm::dvec3(n[3 * i], n[3 * i + 1], n[3 * i + 2])) - 1.0) < 1e-3))
      throw Problem(where + ": NORMAL " + std::to_string(i) + " is not of unit length");
  const std::vector<double> m =
      float_values(g, attribute(g, prim, "_MATERIAL_POSITION", "VEC3", e.count(), where), 3, where + "._MATERIAL_POSITION");
  for (std::size_t i = 0; i < e.count(); ++i)
    if (!(glm::length(glm::dvec3(m[3 * i], m[3 * i + 1], m[3 * i + 2]) - f.mesh.positions[e.original(i)]) <= tolerance))
      throw Problem(where + ": _MATERIAL_POSITION " + std::to_string(i) + " is not vertex " + std::to_string(e.original(i)) + " of " + f.name);
}

// One primitive: attributes, morph targets and triangles against the piece file.
void check_primitive(const GlbFile& g, const Json& prim, const PieceFile& f, const Expected& e, std::size_t targets,
                     double tolerance, const std::string& where) {
  check_vertex_data(g, prim, f, e, tolerance, where);
  const Json& list = array_of(prim, "targets", where);
  if (list.size() != targets)
    throw Problem(where + ": " + std::to_string(list.size()) + " morph targets, expected " + std::to_string(targets));
  for (std::size_t t = 0; t < list.size(); ++t) {
    const AccessorInfo& a = g.acc[index_at(list[t], "POSITION", where + name_at(".targets", t), g.acc.size())];
    if (a.component != 5126 || a.type != "VEC3" || a.count != e.count() || !a.has_bounds)
      throw Problem(where + name_at(".targets", t) + ": POSITION is not float VEC3 with min/max, one per vertex");
  }
  const std::size_t material = index_at(prim, "material", where, array_of(g.j, "materials", "gltf").size());
  const bool inside = g.j["materials"][material].value("name", std::string()) == "inside";
  if (inside) attribute(g, prim, "TEXCOORD_0", "VEC2", e.count(), where);
  if (prim.contains("attributes") && prim["attributes"].contains("COLOR_0")) {
    const std::size_t c = attribute(g, prim, "COLOR_0", "VEC3", e.count(), where);
    for (const double v : float_values(g, c, 3, where + ".COLOR_0"))
      if (!(v >= 0.0 && v <= 1.0)) throw Problem(where + ".COLOR_0: a colour component " + std::to_string(v) + " outside [0, 1]");
  }
  const std::vector<Tri> faces = read_triangles(g, g.acc[index_at(prim, "indices", where, g.acc.size())], e.count(), where);
  if (faces != (inside ? e.inside : e.outside))
    throw Problem(where + ": its " + std::to_string(faces.size()) + " triangles differ from the " + (inside ? "inside" : "outside") +
                  " faces of " + f.name + (inside ? " (rim vertices on their copies)" : ""));
}

// Per node, its animation channels: path -> sampler.
std::vector<std::map<std::string, const Json*>> node_channels(const GlbFile& g, std::size_t nodes) {
  std::vector<std::map<std::string, const Json*>> out(nodes);
  const Json& animations = array_of(g.j, "animations", "gltf");
  if (animations.size() > 1) throw Problem(std::to_string(animations.size()) + " animations, expected 1");
  if (animations.empty()) return out;
  const Json& channels = array_of(animations[0], "channels", "animations[0]");
  const Json& samplers = array_of(animations[0], "samplers", "animations[0]");
  for (std::size_t c = 0; c < channels.size(); ++c) {
    const std::string where = name_at("animations[0].channels", c);
    const Json& target = channels[c].contains("target") ? channels[c]["target"] : Json::object();
    const std::string path = target.value("path", std::string());
    const Json* sampler = &samplers[index_at(channels[c], "sampler", where, samplers.size())];
    if (!out[index_at(target, "node", where + ".target", nodes)].emplace(path, sampler).second)
      throw Problem(where + ": a second " + path + " channel of its node");
  }
  return out;
}

// A channel's sampler: LINEAR, keyed at the kept frames, `width` values per key and per target.
void check_sampler(const GlbFile& g, const Json& sampler, std::size_t keys, std::size_t per_key, const std::string& where) {
  if (sampler.value("interpolation", std::string("LINEAR")) != "LINEAR") throw Problem(where + ": not LINEAR");
  const AccessorInfo& input = g.acc[index_at(sampler, "input", where, g.acc.size())];
  const AccessorInfo& output = g.acc[index_at(sampler, "output", where, g.acc.size())];
  if (input.count != keys || !input.has_bounds || input.component != 5126)
    throw Problem(where + ": sampler input has " + std::to_string(input.count) + " float keys" + (input.has_bounds ? "" : " without min/max") +
                  ", expected " + std::to_string(keys) + " with min/max");
  if (output.component != 5126 || output.count * (output.type == "VEC4" ? 4 : output.type == "VEC3" ? 3 : 1) != keys * per_key)
    throw Problem(where + ": sampler output has " + std::to_string(output.count) + " " + output.type + ", expected " +
                  std::to_string(keys * per_key) + " floats");
}

// A node's channels: weights for a mesh with targets, translation and rotation otherwise.
void check_channels(const GlbFile& g, const std::map<std::string, const Json*>& channels, std::size_t keys, std::size_t targets,
                    const std::string& name) {
  if (keys <= 1) {
    if (!channels.empty()) throw Problem(name + ": animated, but the animation has one frame");
    return;
  }
  const bool deforming = targets > 0;
  const std::size_t expected = deforming ? 1 : 2;
  if (channels.size() != expected || (deforming ? !channels.count("weights") : !channels.count("translation") || !channels.count("rotation")))
    throw Problem(name + ": expected " + (deforming ? "one weights channel (its mesh has morph targets)" : "a translation and a rotation channel"));
  for (const auto& [path, sampler] : channels)
    check_sampler(g, *sampler, keys, path == "weights" ? targets : path == "rotation" ? 4 : 3, name + " " + path);
}

}  // namespace

std::vector<std::size_t> glb_kept_frames(const GlbFile& g, std::size_t frames) {
  std::size_t step = 1;
  const Json& animations = array_of(g.j, "animations", "gltf");
  if (!animations.empty() && animations[0].contains("extras")) {
    const Json& extras = animations[0]["extras"];
    step = std::max<std::size_t>(1, optional_size(extras, "frame_step", "animations[0].extras"));
    if (extras.contains("frame_count") && optional_size(extras, "frame_count", "animations[0].extras") != frames)
      throw Problem("animations[0].extras.frame_count is " + extras["frame_count"].dump() + ", report.json has " + std::to_string(frames) + " frames");
  }
  std::vector<std::size_t> kept;
  for (std::size_t f = 0; f < frames; f += step) kept.push_back(f);
  if (frames > 0 && kept.back() != frames - 1) kept.push_back(frames - 1);
  return kept;
}

GlbSummary check_glb_pieces(const GlbFile& g, const std::vector<PieceFile>& pieces, std::size_t frames) {
  const Json& nodes = array_of(g.j, "nodes", "gltf");
  if (nodes.size() != pieces.size())
    throw Problem(std::to_string(nodes.size()) + " nodes, report.json has " + std::to_string(pieces.size()) + " pieces");
  const std::size_t keys = glb_kept_frames(g, frames).size();
  const auto channels = node_channels(g, nodes.size());
  const Json& meshes = array_of(g.j, "meshes", "gltf");
  const double tolerance = 1e-6 * diagonal_of(pieces);
  GlbSummary s;
  for (std::size_t p = 0; p < nodes.size(); ++p) {
    const std::string name = piece_name(p);
    if (nodes[p].value("name", std::string()) != name) throw Problem(name_at("nodes", p) + " is not named " + name);
    const std::size_t m = index_at(nodes[p], "mesh", name_at("nodes", p), meshes.size());
    if (meshes[m].value("name", std::string()) != name) throw Problem(name_at("meshes", m) + " is not named " + name);
    if (!pieces[p].present) continue;  // already reported by piece_files
    const Json& prims = array_of(meshes[m], "primitives", name_at("meshes", m));
    if (prims.empty()) throw Problem(name_at("meshes", m) + " has no primitive");
    const Expected e = expected_of(pieces[p]);
    const std::size_t targets = channels[p].count("weights") ? keys - 1 : 0;
    std::size_t triangles = 0;
    for (std::size_t k = 0; k < prims.size(); ++k) {
      check_primitive(g, prims[k], pieces[p], e, targets, tolerance, name_at("meshes", m) + name_at(".primitives", k));
      triangles += g.acc[prims[k]["indices"].get<std::size_t>()].count / 3;
    }
    if (triangles != pieces[p].mesh.triangles.size())
      throw Problem(name + ": " + std::to_string(triangles) + " triangles, " + pieces[p].name + " has " + std::to_string(pieces[p].mesh.triangles.size()));
    check_channels(g, channels[p], keys, targets, name);
    targets ? ++s.deforming : ++s.rigid;
    s.targets = std::max(s.targets, targets);
  }
  return s;
}

}  // namespace fracref::check_detail
