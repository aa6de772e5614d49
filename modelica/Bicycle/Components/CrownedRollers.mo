within Bicycle.Components;
model CrownedRollers "Crowned rollers of lateral (rocking) radius R instead of thin tyres, eq (27)"
  parameter Bicycle.Units.Mass m(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m "Total mass m carried by the rollers";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  parameter Bicycle.Units.Length R(min = 0) = Bicycle.Records.Astrom2005SecondOrder.R "Lateral (rocking) radius R of the crowned rollers (R = 0: thin tyres)";
  Bicycle.Interfaces.Roll roll "Roll axis of the frame resting on the rollers"
    annotation(Placement(transformation(extent = {{-10, 90}, {10, 110}})));
equation
  // Rolling on the crown moves the contact points R*phi towards the lean: the normal force m*g
  // acting there gives the torque -m*g*R*phi on the frame, so gravity acts with m*g*(h - R)*phi.
  roll.tau = m*g*R*roll.phi;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, -70}}, lineColor = {64, 64, 64}, fillColor = {128, 128, 128}, fillPattern = FillPattern.Backward),
      Rectangle(extent = {{-90, -70}, {90, -60}}, lineColor = {0, 0, 0}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{-70, -60}, {-10, 0}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{10, -60}, {70, 0}}, lineColor = {0, 0, 0}, fillColor = {200, 200, 200}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{-46, -36}, {-34, -24}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{34, -36}, {46, -24}}, lineColor = {0, 0, 0}, fillColor = {0, 0, 0}, fillPattern = FillPattern.Solid),
      Ellipse(extent = {{-60, -8}, {60, 112}}, lineColor = {0, 0, 0}, fillColor = {64, 64, 64}, fillPattern = FillPattern.Solid, startAngle = 200, endAngle = 340, closure = EllipseClosure.None),
      Line(points = {{0, 50}, {0, 90}}, color = {95, 95, 95}, thickness = 0.5),
      Text(extent = {{-100, 80}, {-20, 40}}, textString = "R", textColor = {0, 0, 0}),
      Text(extent = {{-150, -110}, {150, -150}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>Figure 21: when the bicycle rolls by <code>phi</code> on rollers whose cross-section is a circle
of radius <code>R</code>, the contact points move <code>R*phi</code> to the side of the lean and the
horizontal distance of the centre of mass from them is <code>(h - R)*phi</code>. The gravity term
<code>m*g*h*phi</code> of (1) becomes <code>m*g*(h - R)*phi</code>: the pendulum pole (27)
<code>p = sqrt(m*g*(h - R)/J)</code> is real for <code>R &lt; h</code> and imaginary (an undamped
rocking mode) for <code>R &gt; h</code>. Both wheels are crowned with the same radius, as in (27).</p>
</html>"));
end CrownedRollers;
