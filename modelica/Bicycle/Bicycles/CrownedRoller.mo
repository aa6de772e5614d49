within Bicycle.Bicycles;
model CrownedRoller "Bicycle on crowned rollers of rocking radius R (27): model (1) with gravity term m*g*(h - R), steer angle in"
  extends Bicycle.Icons.Bike;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Length R(min = 0) = Bicycle.Records.Astrom2005SecondOrder.R "Lateral (rocking) radius R of the crowned rollers";
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle (vertical steer axis), positive steering to the left"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right"
    annotation(Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the rear frame, positive to the left"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the rear contact point, positive to the left"
    annotation(Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Bicycle.Components.SecondOrderRearFrame frame(m = m, h = h, b = b, J = J, D = D, V = V, g = g) "Rear frame with rider and wheels, eq (1)"
    annotation(Placement(transformation(extent = {{-70, -40}, {-30, 0}})));
  Bicycle.Components.SteerAngle handlebar(delta = delta) "Rider's steer angle"
    annotation(Placement(transformation(extent = {{30, -40}, {70, 0}})));
  Bicycle.Components.PathKinematics path(V = V, b = b) "Yaw angle and path deviation"
    annotation(Placement(transformation(extent = {{-20, 10}, {20, 50}})));
  Bicycle.Components.CrownedRollers rollers(m = m, g = g, R = R) "Crowned rollers instead of thin tyres"
    annotation(Placement(transformation(extent = {{-70, -90}, {-30, -50}})));
equation
  connect(handlebar.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(handlebar.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  connect(frame.roll, rollers.roll) annotation(Line(points = {{-50, -40}, {-50, -50}}, color = {0, 0, 0}));
  phi = frame.phi;
  psi = path.psi;
  eta = path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(27)", textColor = {64, 64, 64}),
      Ellipse(extent = {{-74, -92}, {-58, -76}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{-54, -92}, {-38, -76}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{38, -92}, {54, -76}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{58, -92}, {74, -76}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid)}),
    experiment(StartTime = 0, StopTime = 2, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Model (1) on crowned rollers (Figure 21): the gravity term m*g*h*phi becomes
m*g*(h - R)*phi, so with the steer angle held the roll poles are +-sqrt(m*g*(h - R)/J) (27):
unstable for R &lt; h, an undamped rocking mode (stable, not asymptotically) for R &gt; h. The steer
angle is the input, as in (1), so that the poles of (27) are the poles of G_phi_delta
(G_phi_delta(s) = V*(D*s + m*V*h)/(b*(J*s^2 - m*g*(h - R)))); the lateral forces of the
steered rollers are those of (1).</p>
</html>"));
end CrownedRoller;
