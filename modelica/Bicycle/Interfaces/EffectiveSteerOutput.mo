within Bicycle.Interfaces;
connector EffectiveSteerOutput "Effective steer angle delta_f = delta*sin(lambda) of eq (8), as a signal (output)"
  output Bicycle.Units.Angle delta_f "Effective steer angle: angle between the lines of intersection of the rear and front planes with the ground, positive to the left";
  annotation(
    defaultComponentName = "front",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}, {-100, 100}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 50}, {0, 0}, {-100, -50}, {-100, 50}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Text(extent = {{-100, 60}, {100, 100}}, textString = "%name", textColor = {0, 0, 127})}));
end EffectiveSteerOutput;
