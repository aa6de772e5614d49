within Bicycle.Interfaces;
connector Roll "Roll axis of the rear frame: roll angle and torque about the x axis"
  Bicycle.Units.Angle phi "Roll angle of the rear frame, positive leaning to the right";
  flow Bicycle.Units.Torque tau "Torque about the roll (x) axis acting on the component";
  annotation(
    defaultComponentName = "roll",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Ellipse(extent = {{-100, -100}, {100, 100}}, lineColor = {0, 0, 0}, fillColor = {95, 95, 95}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.16), graphics = {
      Ellipse(extent = {{-40, -40}, {40, 40}}, lineColor = {0, 0, 0}, fillColor = {95, 95, 95}, fillPattern = FillPattern.Solid),
      Text(extent = {{-160, 90}, {40, 50}}, textString = "%name", textColor = {0, 0, 0})}));
end Roll;
