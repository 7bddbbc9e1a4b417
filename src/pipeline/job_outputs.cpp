#include "pipeline/job_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "field/field_sampler.hpp"
#include "pipeline/surface_preview.hpp"
#include "geom/bvh.hpp"
#include "io/mesh_io.hpp"
#include "util/atomic_output.hpp"
#include "util/parallel.hpp"
#include "version.hpp"

namespace fracref {

JobReport::JobReport(const Scene& scene, const std::string& backend, std::uint64_t seed) : scene_(scene) {
  j_["version"] = kVersion;
  j_["scene"] = scene.name;
  j_["backend"] = backend;
  j_["seed"] = seed;
  j_["threads"] = default_threads();
  j_["seconds"] = nlohmann::ordered_json::object();
}

void JobReport::coarse(const CoarseModel& model, const CoarseAnimation& animation) {
  j_["coarse_triangles"] = model.surface.faces.size();
  j_["pieces"] = model.piece_count;
  j_["virtual_fracture"] = {{"faces_added", model.virtual_faces_added}, {"area_added", model.virtual_area_added}};
  j_["frames"] = animation.frames.size();
  if (scene_.fracture.kind != FractureKind::pieces) return;
  const PiecesFit& f = model.fit;
  j_["pieces_fit"] = {{"fitted", f.fitted}};
  if (!f.fitted) return;
  j_["pieces_fit"].update({{"reason", f.reason}, {"tolerance", f.tolerance}, {"cell", f.cell}, {"tets", f.tets},
                           {"gap_volume", f.gap_volume}, {"overlap_volume", f.overlap_volume},
                           {"pieces_volume", f.pieces_volume}, {"exterior_volume", f.exterior_volume},
                           {"tets_relabelled", f.tets_relabelled}, {"grown", f.grown}});
}

void JobReport::rim_smoothing(int passes) { j_["rim_smoothing"] = passes; }

void JobReport::refined(const FractureSurface& coarse, const FractureSurface& refined, const RefineResult& r,
                        const Grid3& zeta, double diagonal) {
  j_["refined_triangles"] = refined.faces.size();
  j_["initial_energy"] = r.initial_energy;
  const char* stops[] = {"converged", "max_triangles", "max_iterations"};
  j_["stop_reason"] = stops[int(r.stop)];
  nlohmann::ordered_json its = nlohmann::ordered_json::array();
  for (const IterationStats& st : r.iterations) {
    const IterationStats::Phases& p = st.phases;
    its.push_back({{"energy", st.energy}, {"triangles", st.triangles}, {"max_displacement", st.max_displacement},
                   {"collisions_stopped", st.collisions_stopped}, {"splits", st.splits}, {"flips", st.flips}, {"collapses", st.collapses},
                   {"dt", st.dt}, {"solver_iterations", st.solver_iterations}, {"graded", st.graded},
                   {"attempts", st.attempts}, {"seconds", st.seconds},
                   {"phase_seconds", {{"splits", p.splits}, {"flips", p.flips}, {"evaluate", p.evaluate},
                                      {"flow", p.flow}, {"flow_collisions", p.flow_collisions}}}});
  }
  j_["iterations"] = its;
  j_["mean_strength"] = {{"coarse", mean_strength(coarse, zeta)}, {"refined", mean_strength(refined, zeta)}};
  const CoarseDistance d = distance_to_coarse(coarse, refined);
  const double allowed = allowed_distance(scene_.weights, zeta, diagonal);
  j_["distance_to_coarse"] = {{"max", d.max}, {"mean", d.mean}};
  if (std::isfinite(allowed)) j_["distance_to_coarse"]["allowed"] = allowed;
  else j_["distance_to_coarse"]["allowed"] = nullptr;
}

void JobReport::quality(const SurfaceQuality& q) {
  j_["quality"] = {{"energy_ratio", q.energy_ratio},
                   {"energy", {{"coarse", q.coarse_energy}, {"refined", q.refined_energy}}},
                   {"weak_fraction", {{"coarse", q.weak_coarse}, {"refined", q.weak_refined}, {"threshold", q.weak_threshold},
                                      {"reachable", {{"radius", q.displacement_p95}, {"fraction", q.weak_reachable},
                                                     {"half_radius", std::isfinite(q.weak_half_radius)
                                                                         ? nlohmann::ordered_json(q.weak_half_radius)
                                                                         : nlohmann::ordered_json(nullptr)}}}}},
                   {"displacement", {{"mean", q.displacement_mean}, {"p95", q.displacement_p95}, {"max", q.displacement_max}}}};
}

void JobReport::pieces(const PieceSet& pieces, const PieceReport& checked) {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (std::size_t p = 0; p < checked.pieces.size(); ++p) {
    const PieceCheck& c = checked.pieces[p];
    list.push_back({{"piece", p}, {"triangles", c.triangles}, {"fracture_triangles", c.inside_triangles},
                    {"volume", c.volume}, {"closed", c.closed()}, {"edge_manifold", c.edge_manifold()},
                    {"outward", c.outward()}, {"self_intersections", c.self_intersections}});
  }
  j_["piece_meshes"] = list;
  j_["partition"] = {{"exterior_volume", checked.exterior_volume}, {"volume_sum", checked.volume_sum},
                     {"volume_relative_error", checked.volume_relative_error},
                     {"points_tested", checked.points_tested}, {"points_in_no_piece", checked.points_in_no_piece},
                     {"points_in_several_pieces", checked.points_in_several_pieces}};
  j_["pieces_ok"] = checked.ok();
  j_["rim_on_exterior_vertices"] = pieces.snapped_to_b_vertex;
}

void JobReport::animated(const AnimationTransfer& transfer, std::size_t frames_written) {
  j_["frames_written"] = frames_written;
  std::size_t fractured = 0;
  for (std::int64_t f : transfer.coarse_fracture_frame) fractured += f != kNeverFractures;
  j_["coarse_vertices_fracturing"] = fractured;
}

void JobReport::gltf(const GltfSummary& g) {
  j_["glb"] = {{"bytes", g.bytes}, {"frames_kept", g.frames_kept}, {"frame_step", g.frame_step},
              {"rigid_pieces", g.rigid_pieces}};
  if (g.frame_step > 1 || g.over_budget)
    note("animation.glb: " + std::to_string(g.frames_kept) + " of " + std::to_string(g.frame_count) +
         " frames kept (frame step " + std::to_string(g.frame_step) + ", and the last frame): " +
         (g.over_budget ? "even these exceed" : "all of them would exceed") + " the byte budget of the glb");
}

void JobReport::seconds(const std::string& key, double value) { j_["seconds"][key] = value; }

void JobReport::note(const std::string& text) { j_["notes"].push_back(text); }

void JobReport::kernels(const KernelSeconds& k) {
  j_["seconds"]["kernels"] = k.pyramid + k.k1k2 + k.k3;
  j_["kernel_seconds"] = {{"pyramid", k.pyramid}, {"k1k2", k.k1k2}, {"k3", k.k3}};
  j_["kernel_calls"] = {{"pyramid", k.pyramid_calls}, {"k1k2", k.k1k2_calls}, {"k3", k.k3_calls}};
}

nlohmann::ordered_json JobReport::finish(const std::filesystem::path& out, double total,
                                         const std::function<Image()>& preview) {
  if (scene_.output.preview) write_png(out / "preview.png", preview());
  j_["seconds"]["total"] = total;
  write_file_atomic(out / "report.json", j_.dump(2) + "\n");
  return j_;
}

void write_surface_ply(const std::filesystem::path& path, const FractureSurface& s, const RefinementTree* tree,
                       const Grid3* zeta) {
  MeshSoup m;
  for (const glm::vec4& p : s.positions) m.positions.push_back(glm::dvec3(glm::vec3(p)));
  for (const glm::uvec4& f : s.faces) m.triangles.push_back({f.x, f.y, f.z});
  PropertyColumn front{"front", PropertyType::Int32, {}}, back{"back", PropertyType::Int32, {}};
  for (const glm::ivec2& p : s.face_pieces) front.values.push_back(p.x), back.values.push_back(p.y);
  m.face_properties = {front, back};
  PropertyColumn flags{"flags", PropertyType::UInt8, {}};
  for (std::uint32_t f : s.vertex_flags) flags.values.push_back(f);
  m.vertex_properties.push_back(flags);
  if (zeta) {
    PropertyColumn strength{"strength", PropertyType::Float32, {}};
    for (const glm::vec4& p : s.positions) strength.values.push_back(sample_trilinear(*zeta, glm::dvec3(glm::vec3(p))));
    m.vertex_properties.push_back(strength);
  }
  if (tree) {
    for (int k = 0; k < 3; ++k) {
      PropertyColumn parent{"parent" + std::to_string(k), PropertyType::UInt32, {}};
      PropertyColumn weight{"weight" + std::to_string(k), PropertyType::Float32, {}};
      for (std::size_t v = 0; v < tree->parents.size(); ++v)
        parent.values.push_back(tree->parents[v][k]), weight.values.push_back(tree->weights[v][k]);
      m.vertex_properties.push_back(parent);
      m.vertex_properties.push_back(weight);
    }
  }
  write_mesh(path, m);
}

double mean_strength(const FractureSurface& s, const Grid3& zeta) {
  std::vector<double> z(s.positions.size());
  for (std::size_t i = 0; i < z.size(); ++i) z[i] = sample_trilinear(zeta, glm::dvec3(glm::vec3(s.positions[i])));
  double area = 0.0, acc = 0.0;
  for (const glm::uvec4& f : s.faces) {
    glm::dvec3 a(glm::vec3(s.positions[f.x])), b(glm::vec3(s.positions[f.y])), c(glm::vec3(s.positions[f.z]));
    double A = 0.5 * glm::length(glm::cross(b - a, c - a));
    area += A;
    acc += A * (z[f.x] + z[f.y] + z[f.z]) / 3.0;
  }
  return area > 0.0 ? acc / area : 0.0;
}

CoarseDistance distance_to_coarse(const FractureSurface& coarse, const FractureSurface& refined) {
  std::vector<glm::dvec3> pos;
  for (const glm::vec4& p : coarse.positions) pos.push_back(glm::dvec3(glm::vec3(p)));
  std::vector<std::array<std::uint32_t, 3>> tris;
  for (const glm::uvec4& f : coarse.faces) tris.push_back({f.x, f.y, f.z});
  const Bvh bvh = build_bvh(pos, tris);
  std::vector<double> d(refined.positions.size());
  CoarseDistance out;
  for (std::size_t i = 0; i < d.size(); ++i) {
    d[i] = std::sqrt(closest_point(bvh, glm::dvec3(glm::vec3(refined.positions[i]))).squared_distance);
    out.max = std::max(out.max, d[i]);
  }
  double area = 0.0, acc = 0.0;
  for (const glm::uvec4& f : refined.faces) {
    glm::dvec3 a(glm::vec3(refined.positions[f.x])), b(glm::vec3(refined.positions[f.y])), c(glm::vec3(refined.positions[f.z]));
    const double A = 0.5 * glm::length(glm::cross(b - a, c - a));
    area += A;
    acc += A * (d[f.x] + d[f.y] + d[f.z]) / 3.0;
  }
  out.mean = area > 0.0 ? acc / area : 0.0;
  return out;
}

double allowed_distance(const WeightsSpec& w, const Grid3& zeta, double diagonal) {
  if (!(w.distance > 0.0)) return std::numeric_limits<double>::infinity();
  const auto [lo, hi] = std::minmax_element(zeta.values.begin(), zeta.values.end());
  const double range = zeta.values.empty() ? 0.0 : double(*hi) - double(*lo);
  return diagonal * w.strength * range / w.distance;
}

Image preview_frames(const PieceSet& set, const AnimationTransfer& transfer, const CoarseAnimation& animation,
                     int count, const FractureColour& color_at) {
  const std::size_t n = animation.frames.size();
  std::vector<std::vector<PreviewMesh>> scenes;
  for (int k = 0; k < count && n > 0; ++k) {
    std::size_t frame = count == 1 ? n - 1 : std::size_t(k) * (n - 1) / std::size_t(count - 1);
    std::vector<glm::dvec3> slots = transfer_frame(transfer, animation, frame);
    std::vector<PreviewMesh> meshes;
    for (std::size_t p = 0; p < set.pieces.size(); ++p) {
      const std::vector<std::uint32_t>& used = transfer.layout.vertices[p];
      PreviewMesh m;
      std::vector<int> groups;  // fracture and exterior faces are lit apart
      for (std::size_t i = 0; i < used.size(); ++i) m.positions.push_back(slots[transfer.layout.offsets[p] + i]);
      const PieceSet::Piece& piece = set.pieces[p];
      for (std::size_t f = 0; f < piece.triangles.size(); ++f) {
        std::array<std::uint32_t, 3> t;
        for (int c = 0; c < 3; ++c)
          t[c] = std::uint32_t(std::lower_bound(used.begin(), used.end(), piece.triangles[f][c]) - used.begin());
        m.triangles.push_back(t);
        m.triangle_colors.push_back(piece.inside[f] ? piece_color(int(p)) : glm::vec3(0.86f, 0.86f, 0.88f));
        groups.push_back(piece.inside[f] ? 1 : 0);
      }
      smooth_corner_normals(m, kPreviewCrease, groups);
      if (color_at) m.paint = paint_piece(set, p, color_at, glm::vec3(0.86f, 0.86f, 0.88f));
      meshes.push_back(std::move(m));
    }
    scenes.push_back(std::move(meshes));
  }
  // Each picture is framed on its own moment: falling pieces would shrink a shared frame to dots.
  RenderOptions ro;
  ro.width = 320;
  ro.height = 240;
  std::vector<Image> images;
  for (auto& meshes : scenes) images.push_back(render_preview(meshes, ro));
  return contact_sheet(images, 4);
}

Image preview_surface(const FractureSurface& s, const MeshSoup& exterior) {
  PreviewMesh fracture;
  for (const glm::vec4& p : s.positions) fracture.positions.push_back(glm::dvec3(glm::vec3(p)));
  for (std::size_t f = 0; f < s.faces.size(); ++f) {
    fracture.triangles.push_back({s.faces[f].x, s.faces[f].y, s.faces[f].z});
    fracture.triangle_colors.push_back(piece_color(s.face_pieces[f].x));
  }
  PreviewMesh outside;
  outside.positions = exterior.positions;
  outside.triangles = exterior.triangles;
  outside.triangle_colors.assign(exterior.triangles.size(), glm::vec3(0.80f, 0.80f, 0.84f));
  smooth_corner_normals(fracture, kPreviewCrease);
  smooth_corner_normals(outside, kPreviewCrease);
  RenderOptions ro;
  ro.width = 640;
  ro.height = 540;
  // Both views share the exterior's framing so they line up.
  PreviewMesh frame = outside;
  frame.triangles.clear();
  frame.triangle_colors.clear();
  return contact_sheet({render_preview({fracture, frame}, ro), render_preview({outside}, ro)}, 2);
}

}  // namespace fracref
