within Bicycle.Bodies;
model RearWheel "Rear wheel R: axisymmetric knife-edge wheel rolling on the ground (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.PlanarRigidBody(m = 2, final x = 0, final z = -r, Ixx = 0.0603, final Ixz = 0, Iyy = 0.12, final Izz = Ixx);
  parameter Bicycle.Units.Length r(min = 1e-6) = 0.3 "Wheel radius rR";
  final parameter Bicycle.Units.FirstMomentOfMass S = Iyy/r "Gyrostatic coefficient S = Iyy/r (spin angular momentum per forward speed)";
  annotation(Documentation(info = "<html>
<p>Rear wheel with its centre at (0, -r) above the rear contact point. Axisymmetric: the spin
inertia is <code>Iyy</code> (IRyy), the diametral inertia <code>Ixx = Izz</code> (IRxx).
Defaults: the benchmark bicycle of Meijaard et al. (2007).</p>
</html>"));
end RearWheel;
