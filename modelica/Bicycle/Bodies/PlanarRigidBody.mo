within Bicycle.Bodies;
partial model PlanarRigidBody "Rigid body symmetric about the bicycle's x-z plane: mass, centre of mass, inertia and their moments about the rear contact point"
  parameter Bicycle.Units.Mass m(min = 0) "Mass";
  parameter Bicycle.Units.Position x "Centre of mass: x coordinate (forward from the rear contact point)";
  parameter Bicycle.Units.Position z(max = 0) "Centre of mass: z coordinate (downward; negative above the ground)";
  parameter Bicycle.Units.MomentOfInertia Ixx(min = 0) "Inertia-tensor element xx about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Ixz "Inertia-tensor element xz about the centre of mass (-integral(x z dm))";
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Inertia-tensor element yy about the centre of mass";
  parameter Bicycle.Units.MomentOfInertia Izz(min = 0) "Inertia-tensor element zz about the centre of mass";
  final parameter Bicycle.Units.FirstMomentOfMass mx = m*x "First moment of mass m*x about the rear contact point";
  final parameter Bicycle.Units.FirstMomentOfMass mz = m*z "First moment of mass m*z about the rear contact point";
  final parameter Bicycle.Units.MomentOfInertia Jxx = Ixx + m*z^2 "Inertia-tensor element xx about the rear contact point (parallel axes)";
  final parameter Bicycle.Units.MomentOfInertia Jxz = Ixz - m*x*z "Inertia-tensor element xz about the rear contact point (parallel axes)";
  final parameter Bicycle.Units.MomentOfInertia Jzz = Izz + m*x^2 "Inertia-tensor element zz about the rear contact point (parallel axes)";
  annotation(Documentation(info = "<html>
<p>Mass properties of a rigid body whose x-z plane is a plane of symmetry (Ixy = Iyz = 0), in the
axes of Meijaard et al. (2007): x forward, y right, z down, origin at the rear contact point.
The body carries no equations: the linearized bicycle needs only its mass properties.
<code>mx</code>, <code>mz</code>, <code>Jxx</code>, <code>Jxz</code> and <code>Jzz</code> are the first
moments and the inertia-tensor elements about axes through the rear contact point
(J = I + m*(|r|^2*E - r*r') with r = (x, 0, z)).</p>
</html>"));
end PlanarRigidBody;
