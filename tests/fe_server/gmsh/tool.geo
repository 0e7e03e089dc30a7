// A tool-like hollow cylinder: outer radius 20 mm, bore 8 mm, 100 mm long.
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.1, 0.02};
Cylinder(2) = {0, 0, 0, 0, 0, 0.1, 0.008};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
eps = 1e-6;
Physical Volume("tool", 1) = {3};
Physical Surface("top", 11) = Surface In BoundingBox{-1, -1, 0.1 - eps, 1, 1, 0.1 + eps};
Physical Surface("bottom", 12) = Surface In BoundingBox{-1, -1, -eps, 1, 1, eps};
Physical Surface("bore", 13) = Surface In BoundingBox{-0.008 - eps, -0.008 - eps, -eps, 0.008 + eps, 0.008 + eps, 0.1 + eps};
// The element size: 8 mm for the committed tool.msh; gmsh -setnumber size S for others.
If (!Exists(size))
  size = 0.008;
EndIf
Mesh.CharacteristicLengthMax = size;
Mesh.ElementOrder = 1;
