within Bicycle.Mechanics.Rider;
model HipHinge "Hip hinge: revolute about the rear frame's x axis, driven by the rider's lean torque, with passive stiffness and damping"
  extends Bicycle.Mechanics.Rider.PartialHinge;
  parameter Real c(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = 0 "Passive stiffness of the hip (lean torque per lean angle)";
  parameter Real d(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = 0 "Passive damping of the hip (lean torque per lean rate)";
  Bicycle.Mechanics.Joints.ActuatedRevolute revolute(n = n, k = k, final nx = 1, final ny = 0, final nz = 0, c = c, d = d, angle0 = angle0, omega0 = omega0) "Revolute about the longitudinal axis, driven by the lean torque"
    annotation(Placement(transformation(origin = {0, 0}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
equation
  angle = revolute.angle;
  omega = revolute.omega;
  connect(frame_a, revolute.frame_a) annotation(Line(points = {{0, -100}, {0, -20}}, color = {95, 95, 95}, thickness = 0.5));
  connect(revolute.frame_b, frame_b) annotation(Line(points = {{0, 20}, {0, 100}}, color = {95, 95, 95}, thickness = 0.5));
  connect(tau_in, revolute.tau_in) annotation(Line(points = {{-120, -40}, {-60, -40}, {-60, 0}, {-24, 0}}, color = {0, 0, 127}));
  annotation(Documentation(info = "<html><p>The upper body (<code>frame_b</code>) turns relative to the
rear frame (<code>frame_a</code>) about the x axis of <code>frame_a</code> by the lean angle. The
hinge torque on the upper body is <code>tau_in - c*angle - d*omega</code>: the rider's lean torque
plus a passive spring (neutral upright) and damper; the reaction acts on the rear frame.</p></html>"));
end HipHinge;
