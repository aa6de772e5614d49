within Bicycle.Examples;
model WhippleLinearRiderP "Benchmark bicycle at 5 m/s with the rider's proportional steer torque inside one model"
  extends Bicycle.Icons.Example;
  parameter Real k(unit = "N.m/rad") = 2 "Rider gain: T_delta = -k*phi";
  Bicycle.Bicycles.WhippleLinear bike(v = 5, phi0 = 0.05, T_phi = 0) "Linear Whipple bicycle, released with 0.05 rad of roll, no roll torque"
    annotation(Placement(transformation(extent = {{0, -40}, {80, 40}})));
  Bicycle.Control.Proportional rider(k = k) "The paper's rider, T = -k*phi"
    annotation(Placement(transformation(extent = {{-80, -4}, {-40, 36}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{100, 20}, {120, 40}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  connect(bike.phi, rider.phi) annotation(Line(points = {{84, 30}, {92, 30}, {92, 70}, {-92, 70}, {-92, 16}, {-84, 16}}, color = {0, 0, 127}));
  connect(rider.T, bike.T_delta) annotation(Line(points = {{-38, 16}, {-8, 16}}, color = {0, 0, 127}));
  connect(bike.phi, phi) annotation(Line(points = {{84, 30}, {110, 30}}, color = {0, 0, 127}));
  connect(bike.delta, delta) annotation(Line(points = {{84, 18}, {96, 18}, {96, 0}, {110, 0}}, color = {0, 0, 127}));
  annotation(experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-10, Interval = 0.01), Documentation(info = "<html>
<p>The single-model reference of the co-simulated rider loop (WhippleLinear FMU + Proportional
controller): the controller block is connected to the bicycle as the master connects the two
FMUs (<code>bike.phi -&gt; rider.phi</code>, <code>rider.T -&gt; bike.T_delta</code>), but here the
loop is closed in continuous time. Jacobi and Gauss-Seidel, which hold the torque over each
communication step, converge to this solution at first order as the step shrinks
(cosim.studies.convergence).</p>
</html>"));
end WhippleLinearRiderP;
