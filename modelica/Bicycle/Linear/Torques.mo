within Bicycle.Linear;
model Torques "Roll torque on the rear frame and steer torque between rear and front frame"
  Bicycle.Interfaces.RealInput T_phi(final quantity = "Torque", final unit = "N.m") "Roll torque T_phi on the rear frame, positive tending to lean right"
    annotation(Placement(transformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealInput T_delta(final quantity = "Torque", final unit = "N.m") "Steer torque T_delta between rear frame and front frame, positive tending to steer right"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Linear.RollSteer_a frame "Roll and steer coordinates; the torques go out through it as generalized forces"
    annotation(Placement(transformation(extent = {{-16, -116}, {16, -84}})));
equation
  frame.Q_phi = -T_phi;
  frame.Q_delta = -T_delta;
  annotation(
    Icon(graphics = {
      Rectangle(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Line(points = {{-73.8, 47.7}, {-68.6, 38.1}, {-60.6, 30.5}, {-50.8, 25.7}, {-40, 24}, {-29.2, 25.7}, {-19.4, 30.5}, {-11.4, 38.1}, {-6.2, 47.7}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8, smooth = Smooth.Bezier),
      Line(points = {{-73.8, -32.3}, {-68.6, -41.9}, {-60.6, -49.5}, {-50.8, -54.3}, {-40, -56}, {-29.2, -54.3}, {-19.4, -49.5}, {-11.4, -41.9}, {-6.2, -32.3}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8, smooth = Smooth.Bezier),
      Text(extent = {{0, 70}, {90, 20}}, textString = "Tφ", textColor = {0, 0, 0}),
      Text(extent = {{0, -10}, {90, -60}}, textString = "Tδ", textColor = {0, 0, 0}),
      Line(points = {{0, -84}, {0, -100}}, color = {0, 128, 128}, thickness = 0.5),
      Text(extent = {{-150, 110}, {150, 150}}, textString = "%name", textColor = {0, 0, 255})}),
    Documentation(info = "<html>
<p>The applied torques of eq (24): T_phi and T_delta are the generalized forces of the roll and steer
coordinates. The component has no inertia: the generalized force through its
<a href=\"modelica://Bicycle.Linear.RollSteer_a\">RollSteer_a</a> connector balances the torques
alone (flows positive into the component, hence delivered with a minus sign). It uses neither the
coordinates nor the accelerations of the connector.</p>
</html>"));
end Torques;
