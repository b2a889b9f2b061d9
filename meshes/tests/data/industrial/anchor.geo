// An anchor-bracket arm as CAD gives it: a block with a bolt hole and a round boss,
// OpenCASCADE booleans, meshed by gmsh in unstructured tet10 with its mid-edge nodes on the
// curved surfaces (squeal's reader tests; lengths in metres).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.06, 0.02, 0.012};
Cylinder(2) = {0.06, 0.01, 0, 0, 0, 0.012, 0.01};
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Cylinder(3) = {0.06, 0.01, -0.001, 0, 0, 0.014, 0.0045};
BooleanDifference{ Volume{1}; Delete; }{ Volume{3}; Delete; }
Mesh.MeshSizeMax = 0.006;
Mesh.MeshSizeFromCurvature = 8;
Physical Volume("body") = {1};
Physical Surface("clamp") = Surface In BoundingBox{-1e-6, -1, -1, 1e-6, 1, 1};
