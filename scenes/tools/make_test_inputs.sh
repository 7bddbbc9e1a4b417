#!/usr/bin/env bash
# Regenerates tests/data/inputs/ (coarse inputs made with other tools, issue 30) with Debian 12's
# blender (3.4.1, its Cell Fracture add-on), gmsh (4.8.4) and tetgen (1.5.0):
#   apt-get install -y blender gmsh tetgen
#   scenes/tools/make_test_inputs.sh [BUNNY_OBJ]     (default .cache/bunny.obj, what .ci/setup fetches)
# Each step's exact command is in scenes/INPUTS.md, "Inputs from other tools". The outputs are
# byte for byte the same on every run (fixed seeds). The scene files beside them are hand-written.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
bunny=$(realpath "${1:-$root/.cache/bunny.obj}")
out=$root/tests/data/inputs
tools=$root/scenes/tools
mkdir -p "$out" && cd "$out"

cell_fracture() {
  blender -b --factory-startup -noaudio --python-exit-code 1 --python "$tools/cell_fracture.py" -- "$@" >/dev/null
}
# Blender Cell Fracture, 8 cells, seed 1: the add-on's defaults (margin 0.001), margin 0 as n-gons, margin 0 triangulated
cell_fracture cube cf_cube_default.obj cube_exterior.obj --cells 8 --seed 1 --margin 0.001
cell_fracture cube cf_cube_ngon.obj cube_exterior.obj --cells 8 --seed 1 --margin 0
cell_fracture cube cf_cube_tri.obj cube_exterior.obj --cells 8 --seed 1 --margin 0 --triangulate
cell_fracture "$bunny" cf_bunny_default.obj bunny_exterior.obj --cells 8 --seed 1 --margin 0.001 --decimate 0.5
cell_fracture "$bunny" cf_bunny_ngon.obj bunny_exterior.obj --cells 8 --seed 1 --margin 0 --decimate 0.5
cell_fracture "$bunny" cf_bunny_tri.obj bunny_exterior.obj --cells 8 --seed 1 --margin 0 --triangulate --decimate 0.5
mkdir -p cf_cube_shards
cell_fracture cube cf_cube_shards/ cube_exterior.obj --cells 8 --seed 1 --margin 0 --triangulate --split

# gmsh: three physical volumes of a sphere, MEDIT .mesh
gmsh -3 -format mesh -o three_regions.mesh "$tools/three_regions.geo" >/dev/null
# TetGen: a .poly with three regions, -pqAa (quality, region attributes, region volume bounds)
cp "$tools/three_blocks.poly" . && tetgen -pqAa three_blocks.poly >/dev/null && rm -f three_blocks.1.edge three_blocks.1.face three_blocks.poly

# exteriors, rigid transforms and frames for the tets; rigid transforms for the bunny's pieces
for m in three_regions.mesh three_blocks.1.ele; do
  s=${m%%.*}
  python3 "$tools/tet_tools.py" boundary "$m" "${s}_exterior.obj"
  python3 "$tools/tet_tools.py" rigid "$m" "${s}_rigid.txt" --frames 6
  python3 "$tools/tet_tools.py" frames "$m" "${s}_frames" --frames 6
done
python3 "$tools/tet_tools.py" rigid cf_bunny_default.obj cf_bunny_default_rigid.txt --frames 6
