// gmsh: a sphere of radius 1 cut by two planes (z = -0.3, and x = 0.2 above it) into three
// regions, physical volumes 1, 2 and 3, meshed with tets and written as MEDIT .mesh (each tet's
// ref is its physical volume, the piece label):
//   gmsh -3 -format mesh -o three_regions.mesh scenes/tools/three_regions.geo
SetFactory("OpenCASCADE");
Mesh.CharacteristicLengthMax = 0.3;
Mesh.RandomSeed = 1;
Mesh.SaveElementTagType = 2;  // MEDIT ref = the physical volume
Sphere(1) = {0, 0, 0, 1};
Box(2) = {-2, -2, -2, 4, 4, 1.7};
Box(3) = {0.2, -2, -0.3, 2, 4, 2.3};
Box(4) = {-2, -2, -0.3, 2.2, 4, 2.3};
BooleanIntersection(10) = { Volume{1}; }{ Volume{2}; Delete; };
BooleanIntersection(11) = { Volume{1}; }{ Volume{3}; Delete; };
BooleanIntersection(12) = { Volume{1}; Delete; }{ Volume{4}; Delete; };
Coherence;  // the three parts share their cut faces: one conforming mesh
Physical Volume(1) = {10};
Physical Volume(2) = {11};
Physical Volume(3) = {12};
