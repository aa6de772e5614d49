within Bicycle.Sources;
block TorquePulse "Rectangular torque pulse: amplitude on [start, start + duration), else 0 (a lateral push)"
  extends Bicycle.Icons.Block;
  parameter Bicycle.Units.Torque amplitude = 1 "Pulse height";
  parameter Bicycle.Units.Time start = 1 "Start of the pulse";
  parameter Bicycle.Units.Time duration(min = 1e-9) = 0.1 "Length of the pulse";
  Bicycle.Interfaces.RealOutput y(final quantity = "Torque", final unit = "N.m") "Torque pulse"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jumps need no event handling when start and start + duration are communication points.
  y = if time >= start - 1e-12 and time < start + duration - 1e-12 then amplitude else 0;
  annotation(
    Icon(graphics = {
      Line(points = {{-80, 68}, {-80, -80}}, color = {192, 192, 192}),
      Polygon(points = {{-80, 90}, {-88, 68}, {-72, 68}, {-80, 90}}, lineColor = {192, 192, 192}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{-90, -70}, {82, -70}}, color = {192, 192, 192}),
      Polygon(points = {{90, -70}, {68, -62}, {68, -78}, {90, -70}}, lineColor = {192, 192, 192}, fillColor = {192, 192, 192}, fillPattern = FillPattern.Solid),
      Line(points = {{-80, -70}, {-20, -70}, {-20, 50}, {20, 50}, {20, -70}, {80, -70}}, color = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "start=%start", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>No input; output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>y</code> (torque, N.m). The FMU has the same output name. Modelica twin of the Python block
<code>Pulse</code> (<code>cosim.cosimulation.blocks</code>).</p>
<p>A lateral push: connect <code>y</code> to a roll-torque input, e.g. <code>bike.T_phi</code>.</p>
</html>"));
end TorquePulse;
