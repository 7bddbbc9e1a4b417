#pragma once
// Small hand-built fracture surfaces with known topology, on integer coordinates: the shapes the
// tests of every room that consumes S can share (sheet, T-junction, cross, sheet with holes).
#include <vector>

#include "surface/fracture_surface.hpp"

namespace fracref {

/// An n x n vertex grid in the plane z = 0 over [0, n-1]^2, each quad split into two triangles
/// (2 (n-1)^2 faces minus holes). Normals are +z: front piece 1 above, back piece 0 below.
/// Quad (i, j) has corners (i, j) and (i+1, j+1); `holes` lists the quads left out.
/// \throw InputError when n < 2 (through make_fracture_surface for other bad input).
FractureSurface example_sheet(int n, const std::vector<glm::ivec2>& holes = {});

/// Three pieces meeting along a line: the sheet z = 0 over x in [-1, 1], y in [0, cells] (two
/// columns of quads) and a vertical sheet x = 0 over y in [0, cells], z in [0, 1] standing on it.
/// Pieces: 0 below, 1 above with x < 0, 2 above with x > 0. Horizontal normals +z, vertical +x.
/// The junction x = z = 0 has `cells` non-manifold edges of 3 faces.
FractureSurface example_t_junction(int cells);

/// Four pieces around a line: the sheets z = 0 (x in [-1, 1]) and x = 0 (z in [-1, 1]), both over
/// y in [0, cells], crossing along x = z = 0 (`cells` edges of 4 faces). Pieces by quadrant of
/// (x, z): 0 = (-, +), 1 = (+, +), 2 = (+, -), 3 = (-, -). Normals +z and +x.
FractureSurface example_cross(int cells);

}  // namespace fracref
