within Bicycle.Sources;
block TorquePulse "Rectangular torque pulse: amplitude on [start, start + duration), else 0 (a lateral push)"
  parameter Bicycle.Units.Torque amplitude = 1 "Pulse height";
  parameter Bicycle.Units.Time start = 1 "Start of the pulse";
  parameter Bicycle.Units.Time duration(min = 1e-9) = 0.1 "Length of the pulse";
  Bicycle.Interfaces.RealOutput y(final quantity = "Torque", final unit = "N.m") "Torque pulse";
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jumps need no event handling when start and start + duration are communication points.
  y = if time >= start - 1e-12 and time < start + duration - 1e-12 then amplitude else 0;
  annotation(__Cosim(export = true), Documentation(info = "<html>
<p>No input; output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>y</code> (torque, N.m). The FMU has the same output name. Modelica twin of the Python block
<code>Pulse</code> (<code>cosim.cosimulation.blocks</code>).</p>
<p>A lateral push: connect <code>y</code> to a roll-torque input, e.g. <code>bike.T_phi</code>.</p>
</html>"));
end TorquePulse;
