within Bicycle.Sources;
block TorqueStep "Torque step: amplitude from start on, else 0 (a steady push)"
  parameter Bicycle.Units.Torque amplitude = 1 "Height of the step";
  parameter Bicycle.Units.Time start = 0 "Time of the step";
  Bicycle.Interfaces.RealOutput y(final quantity = "Torque", final unit = "N.m") "Torque step";
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jump needs no event handling when start is a communication point.
  y = if time >= start - 1e-12 then amplitude else 0;
  annotation(__Cosim(export = true), Documentation(info = "<html>
<p>No input; output (<a href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>):
<code>y</code> (torque, N.m). The FMU has the same output name. Modelica twin of the Python block
<code>Step</code> (<code>cosim.cosimulation.blocks</code>).</p>
<p>A steady torque, e.g. on a steer-torque input (Examples.SelfStabilizingTorqueStep).</p>
</html>"));
end TorqueStep;
