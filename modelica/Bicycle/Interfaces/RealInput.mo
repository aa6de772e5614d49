within Bicycle.Interfaces;
connector RealInput = input Real "Connector of a Real input signal (as Modelica.Blocks.Interfaces.RealInput)"
  annotation(
    defaultComponentName = "u",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}, {-100, 100}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{0, 50}, {100, 0}, {0, -50}, {0, 50}}, lineColor = {0, 0, 127}, fillColor = {0, 0, 127}, fillPattern = FillPattern.Solid),
      Text(extent = {{-120, 60}, {80, 100}}, textString = "%name", textColor = {0, 0, 127})}));
