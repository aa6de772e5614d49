within Bicycle.Sources;
block TorquePulse "Rectangular torque pulse: amplitude on [start, start + duration), else 0 (a lateral push)"
  parameter Bicycle.Units.Torque amplitude = 1 "Pulse height";
  parameter Bicycle.Units.Time start = 1 "Start of the pulse";
  parameter Bicycle.Units.Time duration(min = 1e-9) = 0.1 "Length of the pulse";
  output Bicycle.Units.Torque y "Torque pulse";
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jumps need no event handling when start and start + duration are communication points.
  y = if time >= start - 1e-12 and time < start + duration - 1e-12 then amplitude else 0;
  annotation(__Cosim(export = true));
end TorquePulse;
