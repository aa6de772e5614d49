within Bicycle.Mechanics.Rider;
model LockedHinge "Locked hip hinge: the upper body held at its initial lean angle"
  extends Bicycle.Mechanics.Rider.PartialHinge(final omega0 = 0);
  Bicycle.Mechanics.Joints.LockedRevolute revolute(n = n, k = k, final nx = 1, final ny = 0, final nz = 0, angle0 = angle0) "Revolute about the longitudinal axis, held"
    annotation(Placement(transformation(origin = {0, 0}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
equation
  angle = revolute.angle;
  omega = revolute.omega;
  connect(frame_a, revolute.frame_a) annotation(Line(points = {{0, -100}, {0, -20}}, color = {95, 95, 95}, thickness = 0.5));
  connect(revolute.frame_b, frame_b) annotation(Line(points = {{0, 20}, {0, 100}}, color = {95, 95, 95}, thickness = 0.5));
  connect(tau_in, revolute.tau_in) annotation(Line(points = {{-120, -40}, {-60, -40}, {-60, 0}, {-24, 0}}, color = {0, 0, 127}));
  annotation(
    Icon(graphics = {
      Line(points = {{-30, -70}, {30, -10}}, color = {255, 0, 0}, thickness = 1),
      Line(points = {{-30, -10}, {30, -70}}, color = {255, 0, 0}, thickness = 1)}),
    Documentation(info = "<html>
<p>The hinge of <a href=\"modelica://Bicycle.Mechanics.Rider.HipHinge\">HipHinge</a>, locked (<a
href=\"modelica://Bicycle.Mechanics.Joints.LockedRevolute\">LockedRevolute</a>): the upper body
turns relative to the rear frame by the lean angle as with the free hinge, but the hinge's own
equation of motion (Kane's equation of the lean speed, which contains the hinge torque) is replaced
by <code>der(omega) = 0</code>. The hinge starts at rest, so the upper body keeps its initial lean
angle <code>angle0</code>, and the bicycle moves exactly as one with the upper body rigidly fixed to
the rear frame at that angle. The rider's lean torque <code>tau_in</code> has no effect.</p>
</html>"));
end LockedHinge;
