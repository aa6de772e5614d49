within Bicycle.Interfaces;
connector Steer "Steer axis: steer angle and torque about the steer axis"
  Bicycle.Units.Angle delta "Steer angle, positive steering to the left";
  flow Bicycle.Units.Torque tau "Torque about the steer axis acting on the component";
  annotation(
    defaultComponentName = "steer",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Polygon(points = {{0, 100}, {100, 0}, {0, -100}, {-100, 0}, {0, 100}}, lineColor = {0, 0, 0}, fillColor = {95, 95, 95}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Polygon(points = {{0, 50}, {50, 0}, {0, -50}, {-50, 0}, {0, 50}}, lineColor = {0, 0, 0}, fillColor = {95, 95, 95}, fillPattern = FillPattern.Solid),
      Text(extent = {{-160, 100}, {40, 60}}, textString = "%name", textColor = {0, 0, 0})}));
end Steer;
