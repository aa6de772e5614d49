within Bicycle.Bodies;
partial model Wheel "Axisymmetric knife-edge wheel in the bicycle's x-z plane: mass, inertia, gyrostatic coefficient"
  parameter Bicycle.Units.Length r(min = 1e-6) "Wheel radius";
  parameter Bicycle.Units.Mass m(min = 0) "Wheel mass";
  parameter Bicycle.Units.MomentOfInertia Ixx(min = 0) "Diametral inertia Ixx = Izz about the wheel centre";
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Spin (polar) inertia Iyy about the wheel axle";
  final parameter Bicycle.Units.Position z = -r "Centre: z coordinate (down), -r";
  final parameter Bicycle.Units.FirstMomentOfMass mz = -m*r "First moment of mass m*z about the rear contact point";
  final parameter Bicycle.Units.MomentOfInertia Jxx = Ixx + m*r^2 "Inertia-tensor element xx about the rear contact point (parallel axes)";
  final parameter Bicycle.Units.FirstMomentOfMass S = Iyy/r "Gyrostatic coefficient S = Iyy/r (spin angular momentum per forward speed)";
  annotation(Documentation(info = "<html>
<p>A wheel rotationally symmetric about its axle (the y axis), touching the ground in a point
directly below its centre when upright (knife edge), in the axes of Meijaard et al. (2007):
x forward, y right, z down, origin at the rear contact point. The inertia tensor about the centre is
diag(Ixx, Iyy, Ixx). <code>S = Iyy/r</code> is the spin angular momentum per unit forward
speed, the wheel's gyroscopic coefficient.</p>
</html>"));
end Wheel;
