// Seed punch (paper section 4.1), half model: structured triangle mesh.
// Block [0, W] x [0, H] (cm), punch on the top edge 0 <= x <= A, symmetry plane x = 0.
// Two transfinite blocks (under the punch and beside it) so that the punch edge x = A is a
// mesh line; every quad is cut along the same diagonal (gmsh's default "Left").
// Run: gmsh -2 -format msh41 -setnumber N 8 punch_structured.geo -o s1.msh
// N = elements along the punch half-width A; the element size is A / N everywhere.
DefineConstant[ W = 3.0, H = 2.0, A = 1.0, N = 8 ];
nx_punch = N;
nx_side = Round(N * (W - A) / A);
ny = Round(N * H / A);
Point(1) = {0, 0, 0};
Point(2) = {A, 0, 0};
Point(3) = {W, 0, 0};
Point(4) = {W, H, 0};
Point(5) = {A, H, 0};
Point(6) = {0, H, 0};
Line(1) = {1, 2};      // bottom under the punch
Line(2) = {2, 3};      // bottom beside the punch
Line(3) = {3, 4};      // outer side x = W
Line(4) = {4, 5};      // free top surface
Line(5) = {5, 6};      // punch face
Line(6) = {6, 1};      // symmetry plane x = 0
Line(7) = {2, 5};      // internal line below the punch edge
Curve Loop(1) = {1, 7, 5, 6};
Curve Loop(2) = {2, 3, 4, -7};
Plane Surface(1) = {1};
Plane Surface(2) = {2};
Transfinite Curve{1, 5} = nx_punch + 1;
Transfinite Curve{2, 4} = nx_side + 1;
Transfinite Curve{3, 6, 7} = ny + 1;
Transfinite Surface{1} = {1, 2, 5, 6};
Transfinite Surface{2} = {2, 3, 4, 5};
Physical Curve("bottom") = {1, 2};
Physical Curve("side") = {3};
Physical Curve("free") = {4};
Physical Curve("punch") = {5};
Physical Curve("symmetry") = {6};
Physical Surface("block") = {1, 2};
