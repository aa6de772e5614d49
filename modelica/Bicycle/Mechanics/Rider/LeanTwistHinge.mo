within Bicycle.Mechanics.Rider;
model LeanTwistHinge "Hip of two hinges in series: lean about the rear frame's x axis, then twist about the upper body's z axis, each with stiffness, damping and a torque input"
  extends Bicycle.Mechanics.Rider.PartialHinge(n = 8);
  parameter Real c(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = 0 "Passive stiffness of the lean hinge";
  parameter Real d(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = 0 "Passive damping of the lean hinge";
  parameter Real cT(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = 0 "Passive stiffness of the twist hinge";
  parameter Real dT(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = 0 "Passive damping of the twist hinge";
  parameter Bicycle.Units.Angle twist0 = 0 "Initial twist angle";
  parameter Bicycle.Units.AngularVelocity twistRate0 = 0 "Initial twist rate";
  Bicycle.Interfaces.RealInput tau_twist(final quantity = "Torque", final unit = "N.m") "Twist torque of the rider on the upper body about its vertical axis, positive turning the upper body right"
    annotation(Placement(transformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Mechanics.Joints.ActuatedRevolute lean(c = c, d = d, omega0 = omega0, n = n, k = k, nx = 1, ny = 0, nz = 0, angle0 = angle0) "Lean hinge (column k)"
    annotation(Placement(transformation(origin = {0, -40}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
  Bicycle.Mechanics.Joints.ActuatedRevolute twist(c = cT, d = dT, omega0 = twistRate0, n = n, k = k + 1, nx = 0, ny = 0, nz = 1, angle0 = twist0) "Twist hinge (column k + 1)"
    annotation(Placement(transformation(origin = {0, 40}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
equation
  angle = lean.angle;
  omega = lean.omega;
  connect(frame_a, lean.frame_a) annotation(Line(points = {{0, -100}, {0, -60}}, color = {95, 95, 95}, thickness = 0.5));
  connect(lean.frame_b, twist.frame_a) annotation(Line(points = {{0, -20}, {0, 20}}, color = {95, 95, 95}, thickness = 0.5));
  connect(twist.frame_b, frame_b) annotation(Line(points = {{0, 60}, {0, 100}}, color = {95, 95, 95}, thickness = 0.5));
  connect(tau_in, lean.tau_in) annotation(Line(points = {{-120, -40}, {-24, -40}}, color = {0, 0, 127}));
  connect(tau_twist, twist.tau_in) annotation(Line(points = {{-120, 40}, {-24, 40}}, color = {0, 0, 127}));
  annotation(
    Icon(graphics = {
      Ellipse(extent = {{-50, 40}, {50, 70}}, lineColor = {255, 0, 0}, lineThickness = 0.5, startAngle = 200, endAngle = 340, closure = EllipseClosure.None),
      Polygon(points = {{40, 50}, {52, 60}, {48, 44}, {40, 50}}, lineColor = {255, 0, 0}, fillColor = {255, 0, 0}, fillPattern = FillPattern.Solid)}),
    Documentation(info = "<html><p>The upper body leans about the longitudinal axis of the
rear frame (coordinate <code>k</code>) and twists about its own vertical axis (coordinate
<code>k + 1</code>), each hinge with a spring (neutral at zero), a damper and the rider's torque.
Two joints that own their coordinates: the assembly that uses this hinge raises its number of
generalized speeds by one and changes nothing else. With the twist hinge held (a
<a href=\"modelica://Bicycle.Mechanics.Joints.LockedRevolute\">LockedRevolute</a> in its place) the
hip is <a href=\"modelica://Bicycle.Mechanics.Rider.HipHinge\">HipHinge</a>, with both held
<a href=\"modelica://Bicycle.Mechanics.Rider.LockedHinge\">LockedHinge</a>.</p></html>"));
end LeanTwistHinge;
