within Bicycle.Sources;
block TorqueStep "Torque step: amplitude from start on, else 0 (a steady push)"
  parameter Bicycle.Units.Torque amplitude = 1 "Height of the step";
  parameter Bicycle.Units.Time start = 0 "Time of the step";
  output Bicycle.Units.Torque y "Torque step";
equation
  // A stateless block: a Co-Simulation master samples it at communication points, so the
  // jump needs no event handling when start is a communication point.
  y = if time >= start - 1e-12 then amplitude else 0;
  annotation(__Cosim(export = true));
end TorqueStep;
