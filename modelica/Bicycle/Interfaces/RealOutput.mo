within Bicycle.Interfaces;
connector RealOutput = output Real "Connector of a Real output signal (as Modelica.Blocks.Interfaces.RealOutput)"
  annotation(
    defaultComponentName = "y",
    Icon(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 100}, {100, 0}, {-100, -100}, {-100, 100}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid)}),
    Diagram(coordinateSystem(preserveAspectRatio = true, initialScale = 0.2), graphics = {
      Polygon(points = {{-100, 50}, {0, 0}, {-100, -50}, {-100, 50}}, lineColor = {0, 0, 127}, fillColor = {255, 255, 255}, fillPattern = FillPattern.Solid),
      Text(extent = {{-100, 60}, {100, 100}}, textString = "%name", textColor = {0, 0, 127})}));
