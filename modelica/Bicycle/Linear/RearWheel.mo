within Bicycle.Linear;
model RearWheel "Rear wheel R: axisymmetric knife-edge wheel with its centre above the rear contact point"
  extends Bicycle.Icons.Wheel;
  extends Bicycle.Linear.PartialRearBody(final x = 0, final z = -r, final Izz = Ixx, final Ixz = 0, final S = Iyy/r);
  parameter Bicycle.Units.Length r(min = 1e-6) "Wheel radius rR";
  parameter Bicycle.Units.MomentOfInertia Iyy(min = 0) "Spin (polar) inertia IRyy about the axle";
  annotation(Documentation(info = "<html>
<p>Rear wheel of mass m, diametral inertia Ixx = Izz and spin inertia Iyy about its centre at
x = 0, z = -r. Its gyrostatic coefficient S = Iyy/r is Meijaard's SR (A17).</p>
</html>"));
end RearWheel;
