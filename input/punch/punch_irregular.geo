// Seed punch (paper section 4.1), half model: irregular (unstructured) triangle mesh.
// Block [0, W] x [0, H] (cm), punch on the top edge 0 <= x <= A, symmetry plane x = 0.
// Same geometry and physical curves as punch_structured.geo; gmsh's Delaunay mesher with
// the uniform target size h, so element shapes and node valences vary over the block.
// Run: gmsh -2 -format msh41 -setnumber h 0.07 punch_irregular.geo -o u2.msh
DefineConstant[ W = 3.0, H = 2.0, A = 1.0, h = 0.1 ];
Point(1) = {0, 0, 0, h};
Point(2) = {W, 0, 0, h};
Point(3) = {W, H, 0, h};
Point(4) = {A, H, 0, h};
Point(5) = {0, H, 0, h};
Line(1) = {1, 2};      // bottom
Line(2) = {2, 3};      // outer side x = W
Line(3) = {3, 4};      // free top surface
Line(4) = {4, 5};      // punch face
Line(5) = {5, 1};      // symmetry plane x = 0
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Mesh.Algorithm = 5;    // Delaunay
Physical Curve("bottom") = {1};
Physical Curve("side") = {2};
Physical Curve("free") = {3};
Physical Curve("punch") = {4};
Physical Curve("symmetry") = {5};
Physical Surface("block") = {1};
