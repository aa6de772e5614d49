within Bicycle.Bicycles;
model SelfStabilizing "Rear frame (14) with static front fork (11): self-stabilizing bicycle with steer-torque input"
  extends Bicycle.Icons.Bike;
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m of bicycle and rider";
  parameter Bicycle.Units.Length a(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.a "Horizontal distance a from the rear contact point to the centre of mass";
  parameter Bicycle.Units.Length h(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.h "Height h of the centre of mass";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  parameter Bicycle.Units.Length c(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.c "Trail c";
  parameter Bicycle.Units.Angle lambda(min = 1e-6, max = 1.5707963267948966) = Bicycle.Records.Astrom2005SecondOrder.lambda "Head angle lambda (70 deg)";
  parameter Bicycle.Units.MomentOfInertia J(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J "Moment of inertia J about the x axis";
  parameter Bicycle.Units.MomentOfInertia D(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.D "Inertia product D = -Jxz";
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  Bicycle.Interfaces.RealInput T(final quantity = "Torque", final unit = "N.m") "Steer torque applied to the handlebars"
    annotation(Placement(transformation(extent = {{-140, -20}, {-100, 20}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right"
    annotation(Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle, positive steering to the left"
    annotation(Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the rear frame, positive to the left"
    annotation(Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the rear contact point, positive to the left"
    annotation(Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Bicycle.Components.SecondOrderRearFrame frame(m = m, h = h, b = b, J = J, D = D, V = V, g = g) "Rear frame with rider and wheels, eq (1)"
    annotation(Placement(transformation(extent = {{-70, -40}, {-30, 0}})));
  Bicycle.Components.StaticFrontFork fork(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g) "Front fork, eqs (7)-(13)"
    annotation(Placement(transformation(extent = {{30, -40}, {70, 0}})));
  Bicycle.Components.SteerTorque handlebar(T = T) "Rider's steer torque"
    annotation(Placement(transformation(extent = {{30, 20}, {70, 60}})));
  Bicycle.Components.PathKinematics path(V = V, b = b) "Yaw angle and path deviation"
    annotation(Placement(transformation(extent = {{-20, 10}, {20, 50}})));
equation
  connect(frame.roll, fork.roll) annotation(Line(points = {{-50, -40}, {-50, -60}, {50, -60}, {50, -40}}, color = {0, 0, 0}));
  connect(fork.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(fork.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  connect(handlebar.steer, fork.steer) annotation(Line(points = {{50, 20}, {50, 0}}, color = {0, 0, 0}));
  phi = frame.phi;
  delta = fork.steer.delta;
  psi = path.psi;
  eta = path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(14) (11)", textColor = {64, 64, 64})}),
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>The bicycle of eqs (14) and (11): steer torque T in; roll angle phi, steer angle delta, yaw
angle psi and path deviation eta out. The frame (1) and the static fork together give (14): the
fork supplies the effective steer angle delta*sin(lambda) (8) and the roll torque of its shifted
contact point. Stable for V &gt; V_c = sqrt(b*g*cot(lambda)) (16) when b*h &gt; a*c*tan(lambda) (17).
A constant positive T gives the inverse path response of Figure 5 (eta first positive, then
negative; roll positive, steer negative).</p>
<p>States: frame.phi, frame.L (momentum form), path.psi, path.eta. The path uses the effective
steer angle: der(psi) = V*sin(lambda)*delta/b, der(eta) = V*psi. Singular at V = V_sa (10).</p>
</html>"));
end SelfStabilizing;
