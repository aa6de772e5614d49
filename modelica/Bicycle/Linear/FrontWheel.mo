within Bicycle.Linear;
model FrontWheel "Front wheel F: axisymmetric knife-edge wheel, turning with the front frame, its centre one wheelbase ahead"
  extends Bicycle.Icons.Wheel;
  extends Bicycle.Linear.PartialFrontBody(final x = w, final z = -r, final Izz = Ixx, final Ixz = 0, final S = Iyy/r);
  parameter Bicycle.Units.Length r(min = 1e-6) "Wheel radius rF";
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Spin (polar) inertia IFyy about the axle";
  annotation(Documentation(info = "<html>
<p>Front wheel of mass m, diametral inertia Ixx = Izz and spin inertia Iyy about its centre at
x = w, z = -r (straight above the front contact point of the upright bicycle with zero steer). Its
gyrostatic coefficient S = Iyy/r is Meijaard's SF (A17).</p>
</html>"));
end FrontWheel;
