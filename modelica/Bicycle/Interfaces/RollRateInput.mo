within Bicycle.Interfaces;
connector RollRateInput "Roll rate of the rear frame, as a signal (input)"
  input Bicycle.Units.AngularVelocity omega "Roll rate der(phi), positive when the lean to the right increases";
  annotation(
    defaultComponentName = "rollRate",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}, {-100, 100}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{0, 50}, {100, 0}, {0, -50}, {0, 50}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid),
      Text(extent = {{-120, 60}, {80, 100}}, textString = "%name", textColor = {0, 0, 127})}));
end RollRateInput;
