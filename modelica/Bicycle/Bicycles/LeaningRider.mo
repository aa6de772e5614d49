within Bicycle.Bicycles;
model LeaningRider "Self-stabilizing bicycle with a leaning rider: frame (14) with the lean terms of (22), static fork (11) (not (23) as printed, whose frame is (1)): steer torque and lean angle in"
  extends Bicycle.Icons.BikeRider;
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
  parameter Bicycle.Units.Mass m_r(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m_r "Mass m_r of the rider's upper body (part of m)";
  parameter Bicycle.Units.MomentOfInertia J_r(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J_r "Moment of inertia J_r of the upper body with respect to the x axis";
  parameter Bicycle.Units.Length h_r(min = 0) = Bicycle.Records.Astrom2005SecondOrder.h_r "Distance h_r from the centre of mass of the upper body to its lean axis";
  Bicycle.Interfaces.RealInput T(final quantity = "Torque", final unit = "N.m") "Steer torque applied to the handlebars"
    annotation(Placement(transformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealInput theta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Lean angle of the upper body relative to the frame, positive to the right"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle, positive leaning to the right"
    annotation(Placement(transformation(extent = {{100, 50}, {120, 70}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle, positive steering to the left"
    annotation(Placement(transformation(extent = {{100, 10}, {120, 30}})));
  Bicycle.Interfaces.RealOutput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Yaw angle of the rear frame, positive to the left"
    annotation(Placement(transformation(extent = {{100, -30}, {120, -10}})));
  Bicycle.Interfaces.RealOutput eta(final quantity = "Length", final unit = "m") "Path deviation of the rear contact point, positive to the left"
    annotation(Placement(transformation(extent = {{100, -70}, {120, -50}})));
  Bicycle.Components.RearFrameWithLean frame(m = m, h = h, b = b, J = J, D = D, V = V, g = g) "Rear frame with lower body and wheels, carrying the upper body, eq (22)"
    annotation(Placement(transformation(extent = {{-70, -40}, {-30, 0}})));
  Bicycle.Components.StaticFrontFork fork(m = m, a = a, b = b, c = c, lambda = lambda, V = V, g = g) "Front fork, eqs (7)-(13)"
    annotation(Placement(transformation(extent = {{30, -40}, {70, 0}})));
  Bicycle.Components.SteerTorque handlebar(T = T) "Rider's steer torque"
    annotation(Placement(transformation(extent = {{30, 20}, {70, 60}})));
  Bicycle.Components.LeaningUpperBody rider(m_r = m_r, J_r = J_r, h_r = h_r, g = g, theta = theta) "Rider's upper body"
    annotation(Placement(transformation(extent = {{-70, 20}, {-30, 60}})));
  Bicycle.Components.PathKinematics path(V = V, b = b) "Yaw angle and path deviation"
    annotation(Placement(transformation(extent = {{-20, 10}, {20, 50}})));
equation
  connect(frame.roll, fork.roll) annotation(Line(points = {{-50, -40}, {-50, -60}, {50, -60}, {50, -40}}, color = {0, 0, 0}));
  connect(frame.roll, rider.roll) annotation(Line(points = {{-50, -40}, {-50, -60}, {-84, -60}, {-84, 28}, {-70, 28}}, color = {0, 0, 0}));
  connect(rider.lean, frame.lean) annotation(Line(points = {{-34, 18}, {-34, 4}}, color = {0, 0, 127}));
  connect(fork.front, frame.front) annotation(Line(points = {{28, -12}, {-26, -12}}, color = {0, 0, 127}));
  connect(fork.front, path.front) annotation(Line(points = {{28, -12}, {0, -12}, {0, 6}}, color = {0, 0, 127}));
  connect(handlebar.steer, fork.steer) annotation(Line(points = {{50, 20}, {50, 0}}, color = {0, 0, 0}));
  phi = frame.phi;
  delta = fork.steer.delta;
  psi = path.psi;
  eta = path.eta;
  annotation(
    Icon(graphics = {
      Text(extent = {{20, 96}, {100, 56}}, textString = "(14)+(22)", textColor = {64, 64, 64})}),
    experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-8, Interval = 0.01),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>The frame equation used is (14) (effective steer angle delta*sin(lambda) and trail torque, as in
SelfStabilizing) with the upper-body lean terms of (22), combined with the static front fork (11).
This is not (23) as printed: (22) and (23) are written with the frame (1) (lambda = 90 deg, c = 0),
and (23) as printed also lacks the factor h in m*V^2*h*k1*T/b. The analytic twin offers both frames
(frame=\"eq1\" and \"eq14\"); this model is frame=\"eq14\".</p>
<p>Two inputs: steer torque T and lean angle theta of the upper body relative to the frame. The
lean angle appears twice differentiated in (22); the frame is written for the inertia-weighted
roll angle chi = phi + J_r*theta/J (states frame.L, frame.chi), so theta is never differentiated
and phi has a direct feedthrough from theta. m, h, J are those of the whole bicycle with rider
(upper body upright).</p>
</html>"));
end LeaningRider;
