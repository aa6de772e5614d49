within Bicycle.Bodies;
model FrontWheel "Front wheel F: axisymmetric knife-edge wheel rolling on the ground (Meijaard 2007, Table 1)"
  extends Bicycle.Bodies.PlanarRigidBody(m = 3, final x = w, final z = -r, Ixx = 0.1405, final Ixz = 0, Iyy = 0.28, final Izz = Ixx);
  parameter Bicycle.Units.Length r(min = 1e-6) = 0.35 "Wheel radius rF";
  parameter Bicycle.Units.Length w(min = 1e-6) = 1.02 "Wheelbase w (x coordinate of the front wheel centre)";
  final parameter Bicycle.Units.FirstMomentOfMass S = Iyy/r "Gyrostatic coefficient S = Iyy/r (spin angular momentum per forward speed)";
  annotation(Documentation(info = "<html>
<p>Front wheel with its centre at (w, -r), above the front contact point of the upright bicycle
with zero steer. Axisymmetric: the spin inertia is <code>Iyy</code> (IFyy), the diametral inertia
<code>Ixx = Izz</code> (IFxx). Defaults: the benchmark bicycle of Meijaard et al. (2007).</p>
</html>"));
end FrontWheel;
