within Bicycle.Bicycles;
model InvertedPendulum "Inverted-pendulum bicycle (1): steer angle in; roll angle, yaw angle and path deviation out"
  extends Bicycle.Icons.Bike;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
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
equation
  connect(handlebar.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(handlebar.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  phi = frame.phi;
  psi = path.psi;
  eta = path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(1)", textColor = {64, 64, 64})}),
    experiment(StartTime = 0, StopTime = 2, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Model (1): vertical steer axis, zero trail, the steer angle delta is the control variable.
G_phi_delta(s) = V*(D*s + m*V*h)/(b*(J*s^2 - m*g*h)) (4): poles +-sqrt(m*g*h/J) (2), zero
-m*V*h/D (3). The path: der(psi) = V*delta/b, der(eta) = V*psi, G_eta_delta = V^2/(b*s^2).</p>
<p>The steer angle appears differentiated in (1); the frame is written in momentum form
(state L = J*der(phi) - D*V*delta/b), so the input is never differentiated. A step of delta
makes der(phi) jump. Proportional steering delta = -k2*phi (5) stabilizes it iff k2 &gt; b*g/V^2 (6)
(see Examples.InvertedPendulumSteerFeedback).</p>
</html>"));
end InvertedPendulum;
