SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.2, 0.02, 0.01};
Physical Volume("body") = {1};
Physical Surface("clamp") = {1};
Mesh.CharacteristicLengthMax = 0.01;
Mesh.ElementOrder = 2;
Mesh.SecondOrderLinear = 1;
Mesh.MshFileVersion = 4.1;
