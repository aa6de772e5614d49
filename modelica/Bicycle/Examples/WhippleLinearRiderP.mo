within Bicycle.Examples;
model WhippleLinearRiderP "Benchmark bicycle at 5 m/s with the rider's proportional steer torque inside one model"
  parameter Real k(unit = "N.m/rad") = 2 "Rider gain: T_delta = -k*phi";
  Bicycle.Bicycles.WhippleLinear bike(v = 5, phi0 = 0.05) "Linear Whipple bicycle, released with 0.05 rad of roll";
  output Bicycle.Units.Angle phi "Roll angle";
  output Bicycle.Units.Angle delta "Steer angle";
equation
  bike.T_phi = 0;
  bike.T_delta = -k*bike.phi;
  phi = bike.phi;
  delta = bike.delta;
  annotation(experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-10, Interval = 0.01), Documentation(info = "<html>
<p>The single-model reference of the co-simulated rider loop (WhippleLinear FMU + Proportional
controller): Jacobi and Gauss-Seidel must converge to this solution as the step shrinks.</p>
</html>"));
end WhippleLinearRiderP;
