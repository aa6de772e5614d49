within Bicycle.Examples;
model WhippleLinearRiderP "Benchmark bicycle at 5 m/s with the rider's proportional steer torque inside one model"
  extends Bicycle.Icons.Example;
  parameter Real k(unit = "N.m/rad") = 2 "Rider gain: T_delta = -k*phi";
  Bicycle.Bicycles.WhippleLinear bike(v = 5, phi0 = 0.05, T_phi = 0) "Linear Whipple bicycle, released with 0.05 rad of roll, no roll torque"
    annotation(Placement(transformation(extent = {{0, -55}, {80, 25}})));
  Bicycle.Control.Proportional rider(k = k) "The paper's rider, T = -k*phi"
    annotation(Placement(transformation(extent = {{-80, -19}, {-40, 21}})));
  Bicycle.Interfaces.RealOutput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{100, 5}, {120, 25}})));
  Bicycle.Interfaces.RealOutput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle"
    annotation(Placement(transformation(extent = {{100, -25}, {120, -5}})));
equation
  connect(bike.phi, rider.phi) annotation(Line(points = {{84, 15}, {92, 15}, {92, 55}, {-92, 55}, {-92, 1}, {-84, 1}}, color = {0, 0, 127}));
  connect(rider.T, bike.T_delta) annotation(Line(points = {{-38, 1}, {-8, 1}}, color = {0, 0, 127}));
  connect(bike.phi, phi) annotation(Line(points = {{84, 15}, {110, 15}}, color = {0, 0, 127}));
  connect(bike.delta, delta) annotation(Line(points = {{84, 3}, {96, 3}, {96, -15}, {110, -15}}, color = {0, 0, 127}));
  annotation(experiment(StartTime = 0, StopTime = 5, Tolerance = 1e-10, Interval = 0.01), Documentation(info = "<html>
<p>The single-model reference of the co-simulated rider loop (WhippleLinear FMU + Proportional
controller): the controller block is connected to the bicycle as the master connects the two
FMUs (<code>bike.phi -&gt; rider.phi</code>, <code>rider.T -&gt; bike.T_delta</code>), but here the
loop is closed in continuous time. Jacobi and Gauss-Seidel, which hold the torque over each
communication step, converge to this solution at first order as the step shrinks
(cosim.studies.convergence).</p>
</html>"));
end WhippleLinearRiderP;
