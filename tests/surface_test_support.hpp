#pragma once
// Comparison of two fracture surfaces' derived arrays, for the tests of the rebuilds.
#include <gtest/gtest.h>

#include "surface/fracture_surface.hpp"

namespace fracref::test {

/// Expects every array that rebuild_adjacency derives (and the vertex flags) to be equal in a and b.
inline void expect_same_derived(const FractureSurface& a, const FractureSurface& b) {
  EXPECT_EQ(a.vf_offsets, b.vf_offsets);
  EXPECT_EQ(a.vf_faces, b.vf_faces);
  EXPECT_EQ(a.edges, b.edges);
  EXPECT_EQ(a.ef_offsets, b.ef_offsets);
  EXPECT_EQ(a.ef_faces, b.ef_faces);
  EXPECT_EQ(a.face_edges, b.face_edges);
  EXPECT_EQ(a.edge_special, b.edge_special);
  EXPECT_EQ(a.vertex_flags, b.vertex_flags);
  EXPECT_EQ(a.side_component, b.side_component);
  EXPECT_EQ(a.component_count, b.component_count);
  EXPECT_EQ(a.copy_offsets, b.copy_offsets);
  EXPECT_EQ(a.copies, b.copies);
  EXPECT_EQ(a.piece_vertex_counts, b.piece_vertex_counts);
}

}  // namespace fracref::test
