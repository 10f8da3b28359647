// Seed sphere compression (paper section 4.2): quarter of a sphere of radius R (m),
// x >= 0, y >= 0, -R <= z <= R; symmetry planes x = 0 and y = 0, loaded along z by two rigid
// plates (written by msh_to_k.py, not meshed here).
// Uniform target element size h; gmsh's Delaunay tetrahedra and its optimiser, which raises
// the smallest element quality (the smallest altitude sets the explicit time step).
// Run: gmsh -3 -format msh41 -setnumber h 0.00644 sphere_quarter.geo -o sphere.msh
// (msh_to_k.py does this and writes the decks.)
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.1, h = 0.00644 ];
Sphere(1) = {0, 0, 0, R};
Box(2) = {0, 0, -R, R, R, 2 * R};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-3 * R;                 // selection tolerance (OCC boxes are padded by 1e-7)
sym_x() = Surface In BoundingBox{-eps, -eps, -R - eps, eps, R + eps, R + eps};
sym_y() = Surface In BoundingBox{-eps, -eps, -R - eps, R + eps, eps, R + eps};
all() = Surface{:};
outer() = all();
outer() -= sym_x();
outer() -= sym_y();
Physical Surface("symmetry_x") = {sym_x()};
Physical Surface("symmetry_y") = {sym_y()};
Physical Surface("sphere_surface") = {outer()};
Physical Volume("sphere") = {3};
Mesh.CharacteristicLengthMin = h;
Mesh.CharacteristicLengthMax = h;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.CharacteristicLengthExtendFromBoundary = 1;
Mesh.Algorithm3D = 1;           // Delaunay
Mesh.Optimize = 1;
Mesh.OptimizeNetgen = 0;        // not compiled into Debian 12's gmsh 4.8.4
