within Bicycle.Sources;
block TorqueStep "Torque step: amplitude from start on, else 0 (a steady push)"
  extends Bicycle.Icons.Block;
  parameter Bicycle.Units.Torque amplitude = 1 "Height of the step";
  parameter Bicycle.Units.Time start = 0 "Time of the step";
  Bicycle.Interfaces.RealOutput y(final quantity = "Torque", final unit = "N.m") "Torque step"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jump needs no event handling when start is a communication point.
  y = if time >= start - 1e-12 then amplitude else 0;
  annotation(
    Icon(graphics = {
      Line(points = {{-80, 68}, {-80, -80}}, color = {192, 192, 192}),
      Polygon(points = {{-80, 90}, {-88, 68}, {-72, 68}, {-80, 90}}, lineColor = {192, 192, 192}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{-90, -70}, {82, -70}}, color = {192, 192, 192}),
      Polygon(points = {{90, -70}, {68, -62}, {68, -78}, {90, -70}}, lineColor = {192, 192, 192}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{-80, -70}, {0, -70}, {0, 50}, {80, 50}}, color = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "start=%start", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>No input; output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>y</code> (torque, N.m). The FMU has the same output name. Modelica twin of the Python block
<code>Step</code> (<code>cosim.cosimulation.blocks</code>).</p>
<p>A steady torque, e.g. on a steer-torque input (Examples.SelfStabilizingTorqueStep).</p>
</html>"));
end TorqueStep;
