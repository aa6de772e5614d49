within Bicycle.Components;
model PathKinematics "Yaw angle psi and path deviation eta of the rear contact point, linearized about a straight path along the xi axis"
  parameter Bicycle.Units.Velocity V = Bicycle.Records.Astrom2005SecondOrder.V "Forward speed V of the rear contact point";
  parameter Bicycle.Units.Length b(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.b "Wheel base b";
  Bicycle.Interfaces.EffectiveSteerInput front "Effective steer angle delta_f of the front wheel, eq (8)"
    annotation(Placement(transformation(origin = {0, -120}, extent = {{-20, -20}, {20, 20}}, rotation = 90)));
  Bicycle.Units.Angle psi(start = 0, fixed = true) "Yaw angle psi between the xi axis and the x axis, positive to the left";
  Bicycle.Units.Position eta(start = 0, fixed = true) "Path deviation eta of the rear contact point along the eta axis (to the left)";
equation
  der(psi) = V*front.delta_f/b;
  der(eta) = V*psi;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Line(points = {{-90, -70}, {90, -70}}, color = {128, 128, 128}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 6),
      Line(points = {{-80, -80}, {-80, 90}}, color = {128, 128, 128}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 6),
      Line(points = {{-80, -50}, {-20, -46}, {30, -10}, {80, 60}}, color = {0, 0, 127}, thickness = 1, smooth = Smooth.Bezier),
      Text(extent = {{70, -74}, {98, -98}}, textString = "ξ", textColor = {64, 64, 64}),
      Text(extent = {{-76, 96}, {-46, 66}}, textString = "η", textColor = {64, 64, 64}),
      Text(extent = {{0, 90}, {90, 50}}, textString = "ψ, η", textColor = {0, 0, 0}),
      Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>Section \"Maneuvering\": <code>der(eta) = V*psi</code>, <code>der(psi) = V*delta/b</code>, with the
effective steer angle <code>delta_f = delta*sin(lambda)</code> (8) in place of <code>delta</code>,
consistent with the yaw rate <code>V*delta_f/b</code> used by the frame model (14). For a vertical
steer axis (model (1)) <code>delta_f = delta</code> and <code>G_eta_delta = V^2/(b*s^2)</code> as printed;
with a head angle lambda it is <code>V^2*sin(lambda)/(b*s^2)</code> (the analytic twin's
<code>frame=\"eq14\"</code>).</p>
</html>"));
end PathKinematics;
